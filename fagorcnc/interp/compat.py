"""What CAM posts write that the manual does not describe, and the machinist's lint.

Each construct's fate comes from the machine's ``[compat]`` policy
(:mod:`fagorcnc.config.compat`): a note, a warning, or an error that stops the run at its block.
Here is what the interpreter does with each one when it is accepted:

* ``G51 A45 E0.002`` (the 8055's look-ahead: A acceleration %, E contour error; not a G function of
  the 8060/8065, seed 002 L1354): no effect at all, the corner mode stays as programmed;
* ``G61`` alone in a block: no effect (G61 rounds the corner of the move of its own block, and
  only that one, L8088-L8107);
* ``G501``/``G500`` with no subroutine file and no mapping: the behaviour of the subroutines Fagor
  supplies (L11084-L11086: G500 cancels HSC, G501 activates HSC for roughing), see
  :func:`smoothing_on` and :func:`smoothing_off`;
* ``T202 LM06``: ``L M06`` is a call of the global subroutine ``M06`` (L10417) written without its
  blank; with no file ``M06``, the block runs as ``T202 M06``.

The lint (warnings whatever ``strict`` says): ``G58`` after another work offset, a move at feed with
the spindle stopped, a G number written with a leading zero before two digits, and hints appended
to errors for the letter O written for a zero and for Fanuc/LinuxCNC codes (:func:`hint`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from ..syntax.ast import Word
from .dynamics import Hsc
from .expressions import InterpError

#: the smoothing subroutines Fagor supplies (seed 002 L11082-L11086)
SMOOTHING = {500: "smoothing_off", 501: "smoothing_on"}


@dataclass
class CamState:
    """What the constructs and the lint remember during a run."""

    acceleration: dict | None = None    # the G131 percentages before a built-in G501 changed them
    spindle_warned: bool = False         # a feed move with the spindle stopped was reported since it stopped
    origin: str | None = None            # the absolute origin the program selected last (G54..G59, G159)


def report(interp, key: str, code: str, message: str, col: int) -> None:
    """A construct's diagnostic with the severity the machine's policy gives it; an error stops the run."""
    compat = interp.machine.compat
    severity = compat.severity(key)
    if severity == "error":
        raise InterpError(code, f"{message} {compat.refusal(key)}", col)
    interp.message(code, severity, message, col)


# ---------------------------------------------------------------------------------------------- G51
_G51_LETTERS = frozenset({"G", "A", "E", "N"})


def g51_block(interp, words: list[Word]) -> bool:
    """``G51 A45 E0.002`` alone in its block (the generic post's header): reported per
    ``compat.g51`` and, when accepted, executed as nothing.  True when the block was that."""
    g51 = next((w for w in words if w.address == "G" and w.value == 51.0), None)
    if g51 is None or any(w.address not in _G51_LETTERS for w in words):
        return False
    if sum(1 for w in words if w.address == "G") != 1:
        return False
    ev = interp.evaluator
    parts = " ".join(f"{w.address}{ev.value(w.value):g}" for w in words if w.address in "AE")
    report(interp, "g51", "CAM001",
           f"G51 {parts}".rstrip() + " is the 8055's look-ahead (A = acceleration %, E = contour error); the "
           "8060/8065 has no G51 (seed 002 L1354): fagorcnc gives it no effect, corners follow the active mode "
           "(on the 8065 smoothing is #HSC ON [CONTERROR e] or G05 with #ROUNDPAR)", g51.col)
    return True


def lone_g61(interp, col: int) -> None:
    """``G61`` in a block that does not move (the posts' way to "cancel smoothing")."""
    report(interp, "lone_g61", "CAM002",
           "G61 alone in its block: G61 rounds the corner of the move of its own block only (seed 002 "
           "L8088-L8107); with no move it has no effect here, and it does not cancel smoothing (#HSC OFF, G07 or "
           "G50 do)", col)


# ---------------------------------------------------------------------------------------------- G500-G599
def oem_target(interp, n: int, col: int) -> tuple[str, str | None]:
    """How to run ``G<n>`` (500..599): ``("file", name)`` or ``("builtin", behaviour)``.

    Order: the machine's mapping (a file or a built-in behaviour), then a file named ``G<n>`` in
    the search paths (seed 002 L11040), then, for G500 and G501 only, the built-in smoothing
    per ``compat.oem_smoothing``.  Otherwise CAM020 says how to provide the subroutine.
    """
    m = interp.machine
    if n in m.oem_builtins:
        return "builtin", m.oem_builtins[n]
    if n in m.oem_subroutines:
        return "file", m.oem_subroutines[n]
    try:
        interp.files.find(f"G{n}", interp.state.path, col)
        return "file", f"G{n}"
    except InterpError as exc:
        if exc.code != "INT093":   # found but unusable (INT151): said as it is
            raise
        where = exc.message.split(" not found in ", 1)[-1]
    if n in SMOOTHING:
        return "builtin", SMOOTHING[n]
    raise InterpError("CAM020", f"G{n} runs the machine builder's global subroutine G{n} (seed 002 L11040), and "
                      f"there is no file G{n} in {where}: put the machine's G{n} in a directory of the machine "
                      f"file's subroutine_paths, or map it there: oem_subroutines = {{{n} = \"file.nc\"}}", col)


def run_builtin(interp, n: int, behaviour: str, args: dict[int, float], col: int, mapped: bool) -> None:
    """A G5xx mapped (or defaulted) to a built-in behaviour."""
    text = " ".join(f"{chr(ord('A') + k) if k < 26 else f'P{k}'}{v:g}" for k, v in sorted(args.items()))
    call = f"G{n} {text}".rstrip()
    what = smoothing_on(interp, args, col) if behaviour == "smoothing_on" else smoothing_off(interp)
    source = ("the machine file maps it to fagorcnc's built-in" if mapped else
              f"no file G{n} and no mapping in the machine file: fagorcnc runs its built-in")
    fagor = "HSC on for roughing" if behaviour == "smoothing_on" else "HSC off"
    message = (f"{call}: the machine builder's subroutine G{n} (Fagor supplies it as {fagor}, seed 002 "
               f"L11084-L11086); {source} {behaviour.replace('_', ' ')}: {what}")
    if mapped:
        interp.message("CAM003", "info", message, col)
    else:
        report(interp, "oem_smoothing", "CAM003", message + f"; give a file G{n} or map it in [oem_subroutines] "
               "to run the machine's own", col)


def smoothing_on(interp, args: dict[int, float], col: int) -> str:
    """Built-in G501: ``#HSC ON [CONTERROR E]`` (E = P4 in program units; HSCROUND without it) with
    the sharp-corner angle CORNER of the machine, and A (P0) as the acceleration percentage of all
    axes, as the Autodesk posts document A ("percentage of acceleration used for G501"); kept at
    most 100 % (fagorcnc never exceeds the machine's limits).  J (P9) and M (P12) are parameters the
    posts write without documenting them: not used."""
    st, planner = interp.state, interp.machine.planner
    e = args.get(4)
    if e is not None and not e > 0:
        raise InterpError("CAM021", f"G501 E{e:g}: the smoothing tolerance E must be positive", col)
    tol = interp.iso.length(e) if e is not None else planner.hsc_round
    st.hsc = Hsc("CONTERROR", tol, planner.corner)
    said = f"#HSC ON [CONTERROR {tol:g}, CORNER {planner.corner:g}]"
    cam = interp.cam
    a = args.get(0)
    if a is not None:
        if not a > 0:
            raise InterpError("CAM021", f"G501 A{a:g}: the acceleration percentage A must be positive", col)
        percent = min(a, 100.0)
        if cam.acceleration is None and (percent != 100.0 or st.acceleration):
            cam.acceleration = dict(st.acceleration)
        st.acceleration = {ax: percent for ax in st.axes} if percent != 100.0 else {}
        said += f" and {percent:g} % acceleration (A{a:g}" + (", at most 100 %)" if a > 100 else ")")
    unused = [f"{chr(ord('A') + k)}{v:g}" for k, v in sorted(args.items()) if k not in (0, 4)]
    if unused:
        said += f"; {' '.join(unused)} not used (local parameters without a documented meaning)"
    st.dynamics_changed()
    return said


def smoothing_off(interp) -> str:
    """Built-in G500: ``#HSC OFF`` and the acceleration percentages from before the built-in G501."""
    st, cam = interp.state, interp.cam
    st.hsc = None
    said = "#HSC OFF"
    if cam.acceleration is not None:
        st.acceleration = cam.acceleration
        cam.acceleration = None
        said += " and the acceleration percentages from before G501"
    st.dynamics_changed()
    return said


# ---------------------------------------------------------------------------------------------- T.. LM06
_GLUED = re.compile(r"L[ \t]*([A-Za-z0-9_.]+)")


def glued_call(interp, word: Word, text: str) -> tuple | None:
    """``T202 LM06`` (``L`` with no value after another word): ``L M06`` calls the global subroutine
    ``M06`` (seed 002 L10417).  With its file: ``((name, "L", {}, col), end)``, the call to run after
    the block and the column after the name (its letters were read as words: they are skipped).
    Without, per ``compat.tool_subroutine``: ``(None, 0)`` for a name like an M function, whose word
    (``M06``) then runs as that M function; an error otherwise.  None: not a glued call."""
    m = _GLUED.match(text, word.col - 1)
    if m is None:
        return None
    name, col = m.group(1), word.col
    try:
        interp.files.find(name, interp.state.path, col)
    except InterpError as exc:
        if exc.code != "INT093":   # found but unusable (INT151): said as it is
            raise
        where = exc.message.split(" not found in ", 1)[-1]
        where = "with no directory configured" if where.startswith("no directory") else f"in {where}"
        mfunc = re.fullmatch(r"M0*([0-9]{1,4})", name)
        if mfunc is None:
            raise InterpError("INT093", f"L{name}: a call of the global subroutine {name} (L {name}, seed 002 "
                              f"L10417), not found {where}", col) from None
        report(interp, "tool_subroutine", "CAM006",
               f"{m.group()} after the T word is a call of the machine builder's global subroutine {name} "
               f"(the manual's block L {name}, seed 002 L10417); there is no file {name} {where}: fagorcnc runs "
               f"the block as M{int(mfunc.group(1)):02d} instead (the subroutine's own moves are not simulated)",
               col)
        return None, 0
    return (name, "L", {}, col), m.end() + 1


# ---------------------------------------------------------------------------------------------- lint
def origin_lint(interp, label: str, col: int) -> None:
    """G58 after another absolute origin of the program: on the 8065 G58 is absolute origin 5 and
    replaces it (seed 002 L3531-L3545), unlike an additive offset."""
    cam = interp.cam
    previous, cam.origin = cam.origin, label
    if label != "G58" or previous is None or previous == "G58":
        return
    entry = interp.state.origin_table.get(5, {})
    shown = " ".join(f"{a}{entry.get(a, 0.0):g}" for a in interp.state.axes)
    report(interp, "g58_after_offset", "CAM013",
           f"G58 after {previous}: on the 8060/8065 G58 selects absolute origin 5 (seed 002 L3531), it replaces "
           f"{previous} instead of adding to it; the work offset is now table entry 5: {shown}", col)


def spindle_lint(interp, rec, col: int) -> None:
    """A move at feed (mm/min or time) with a tool in the spindle while the main spindle is stopped:
    M05 at power-on and after M02/M30 (seed 002 L5729, L889), M03/M04 need a speed (L5467).  Once
    per stop.  The manual forbids it only in G95 (no feed per revolution without rotation: INT065);
    with no tool (T0) nothing cuts, and that is not reported."""
    st = interp.state
    if not st.spindle_state or not st.tool:
        return
    spindle = st.master_spindle()
    cam = interp.cam
    if st.spindle_state[spindle] in (3, 4) and st.speeds.get(spindle, 0.0) > 0:
        cam.spindle_warned = False
        return
    if cam.spindle_warned:
        return
    cam.spindle_warned = True
    why = "M05" if st.spindle_state[spindle] not in (3, 4) else f"M0{st.spindle_state[spindle]} with S0"
    report(interp, "feed_spindle_stopped", "CAM014",
           f"a move at feed with T{st.tool} while the spindle {spindle} is stopped ({why}; the spindle is stopped at "
           "power-on and "
           "after M02/M30, seed 002 L5729): program S and M03/M04 before cutting (reported once until it turns)",
           col)


def leading_zero(interp, n: int, col: int, text: str) -> None:
    """``G011``: a G number written with a leading zero before two digits reads as ``G11``."""
    if n < 10 or col >= len(text) or text[col] not in " \t0":
        return
    m = re.match(r"G[ \t]*(0+)([0-9]{2,})", text[col - 1:])
    if m is None:
        return
    report(interp, "leading_zeros", "CAM010",
           f"G{m.group(1)}{m.group(2)} reads as G{n} (leading zeros do not count); if G0{m.group(2)[0]} was meant, "
           "a digit is too many", col)
