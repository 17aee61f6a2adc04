"""The path stages between the block loop and the records' consumer, with an idle lane.

:meth:`~fagorcnc.interp.interpreter.Interpreter.run` hands the block loop's records through seven
stages in turn: #SPLINE's chords (:func:`~fagorcnc.interp.curves.splines`), tangential control
(:func:`~fagorcnc.kinematics.tangential.follow`), the transformation's frames
(:func:`~fagorcnc.kinematics.stage.with_frames`), the corner aids G36-G39
(:func:`~fagorcnc.path.aids.apply_aids`, one move of look-ahead), tool radius compensation
(:func:`~fagorcnc.path.compensation.compensate`), machine joints
(:func:`~fagorcnc.kinematics.stage.joint_space`) and coupled slaves
(:func:`~fagorcnc.interp.axes.follow_links`).  In most programs none of them does anything but hand
each record on, and seven generator steps a record cost as much as a plain block's arithmetic.

:func:`stages` is those stages as one loop while they have nothing to do (the idle lane): each
record passes them unchanged, the corner aids' stage holding the last move until the next (as
:func:`apply_aids` does: the records after a move come out after it).  At the first record one of
them would act on (a #SPLINE mark, a corner aid, a move under tangential control, a transformation,
radius compensation or a coupling) the stream goes to the stages themselves, chained as generators
(:func:`chained`), for the rest of the run: each is handed the state it would have had, so the
records, their order and the moments the stages look at the interpreter's state are the chain's.
``tests/test_pipeline.py`` runs programs both ways and compares everything.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from itertools import chain

from ..kinematics.stage import joint_space, with_frames
from ..kinematics.tangential import follow
from ..path.aids import apply_aids
from ..path.compensation import compensate
from .axes import follow_links
from .curves import splines
from .records import IndependentMove

#: The kinds of the move records (the stages' own test).
MOVES = ("rapid", "linear", "arc")


def chained(records: Iterable, interp, on_error: Callable, last=None, held=None, after: Iterable = ()) -> Iterator:
    """The stages as chained generators over ``records`` (made by ``interp``'s block loop); ``on_error`` is
    :func:`follow_links`'.  ``last`` (the last move the spline stage handed on), ``held`` and ``after`` (the
    move the corner aids' stage holds and the records that came after it) are the state the idle lane of
    :func:`stages` leaves: ``held`` and ``after`` enter at the corner aids' stage, having passed those
    before it already."""
    st = interp.state
    framed = with_frames(follow(splines(records, interp, last), interp), st)
    if held is not None:
        framed = chain((held, *after), framed)
    corrected = compensate(apply_aids(framed, interp._aid_error), interp._path_warning)
    return follow_links(joint_space(corrected, interp), st, on_error)


def stages(records: Iterable, interp, on_error: Callable) -> Iterator:
    """The records of :func:`chained`, from its idle lane while no stage has anything to do (see the module):
    a move passes every stage unchanged when no tangential axis, transformation or #MCS move is active as
    it comes, and it is not compensated, transformed or coupled (``follow_links``' couplings: its
    ``dyn.links``; the moves before it had none, else the chain would have them); any other record when it
    is not a #SPLINE mark or a corner aid and no transformation is active."""
    kin = interp.state.kin
    records = iter(records)
    last = held = None   # the spline stage's last move; the move the corner aids' stage holds
    after: list = []     # the records after it
    for rec in records:
        kind = rec.kind
        if kind in MOVES:
            if kin.tangential or kin.raw or kin.frame is not None or rec.comp is not None or rec.frame is not None \
                    or ((dyn := rec.dyn) is not None and dyn.links):
                break
            if not isinstance(rec, IndependentMove):
                last = rec
            if held is not None:
                yield held
                if after:
                    yield from after
                    after.clear()
            held = rec
        elif kind == "spline" or kind == "aid" or kin.frame is not None:
            break
        elif held is None:
            yield rec
        else:
            after.append(rec)
    else:   # the end of the run: what the corner aids' stage holds
        if held is not None:
            yield held
        yield from after
        return
    yield from chained(chain((rec,), records), interp, on_error, last, held, after)
