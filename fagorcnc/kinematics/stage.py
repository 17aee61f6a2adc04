"""The joint-space stage: records made under a :class:`~fagorcnc.kinematics.frame.Frame` in machine joints.

Runs after the corner aids and radius compensation (which work in the programmed plane).  A record
whose frame is one rigid motion over the move (no rotary axis of the kinematics turns) keeps its
shape: a line stays a line, an arc whose plane the map takes onto a machine plane stays an arc.
Otherwise the move is cut into joint-space lines so that the tool tip stays within the kinematics'
``tolerance`` (or the machine's ``kinematics_tolerance``) of the programmed path, the tool
orientation interpolated linearly in the rotary axes between the block's start and end
(seed 002 L13233: "the orientation is interpolated between the start and end values").  The feed
of each piece is set so that the **tool tip** runs at the programmed feed (the piece's joint length
over its tip length).  Every joint position is checked against the soft limits.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import replace

import numpy as np

from ..diagnostics import Diagnostic
from ..interp.records import Arc, Line
from .frame import Frame

#: Deepest halving of one move into joint-space pieces (2**14 pieces at most).
MAX_DEPTH = 14


class StageError(ValueError):
    """A move the joint-space stage cannot produce; ``code`` is its diagnostic code."""

    def __init__(self, record, code: str, message: str) -> None:
        super().__init__(message)
        self.record = record
        self.code = code


def _arc_point(rec: Arc, s: float) -> dict:
    """The programmed (virtual) position at fraction ``s`` of an arc (helix axes linear)."""
    a, o = rec.plane[0], rec.plane[1]
    c = (rec.center[a], rec.center[o])
    r0 = math.dist((rec.start[a], rec.start[o]), c)
    r1 = math.dist((rec.end[a], rec.end[o]), c)
    ang0 = math.atan2(rec.start[o] - c[1], rec.start[a] - c[0])
    ang = ang0 + math.radians(rec.sweep) * s
    r = r0 + (r1 - r0) * s
    out = {x: rec.start[x] + (rec.end[x] - rec.start[x]) * s for x in rec.end}
    out[a], out[o] = c[0] + r * math.cos(ang), c[1] + r * math.sin(ang)
    return out


def _turned(pos: dict, turns: dict) -> dict:
    return {k: v + turns.get(k, 0.0) for k, v in pos.items()}


def _line_point(rec, s: float) -> dict:
    return {x: rec.start[x] + (rec.end[x] - rec.start[x]) * s for x in rec.end}


class JointStage:
    """Maps the records of a run; ``limits(position, record)`` checks one joint position."""

    def __init__(self, tolerance: float, limits, note=None) -> None:
        self.tolerance = tolerance
        self.limits = limits
        self.note = note   # note(record, text): told once that inclined arcs run as chords

    def run(self, records: Iterable) -> Iterator:
        last = None   # the joints where the last transformed move ended (and the moves after it)
        had_frame = False
        turns: dict[str, float] = {}   # whole turns the joints stand from what the state says (#FACE)
        wrapped: tuple = ()
        for rec in records:
            kind = rec.kind
            if kind not in ("linear", "rapid", "arc"):
                yield rec
                continue
            frame = rec.frame
            if frame is None:
                if turns:
                    rec = replace(rec, start=_turned(rec.start, turns), end=_turned(rec.end, turns))
                if last is not None and wrapped:
                    # the C axis of #FACE stands some turns away from the angle the state knows
                    for k in wrapped:
                        extra = 360.0 * round((last[k] - rec.start[k]) / 360.0)
                        if extra:
                            turns[k] = turns.get(k, 0.0) + extra
                            rec = replace(rec, start=_turned(rec.start, {k: extra}), end=_turned(rec.end, {k: extra}))
                    wrapped = ()
                if last is not None and any(abs(rec.start.get(k, v) - v) > 1e-6 for k, v in last.items()):
                    # a move after transformed ones must start where their joints ended: refuse
                    # rather than jump (a stage that dropped the frame would otherwise pass unseen)
                    raise StageError(rec, "KIN025", "this move does not start where the transformed moves "
                                     "before it left the joints; fagorcnc cannot compute it")
                last = rec.end if had_frame else None
                yield rec
                continue
            had_frame = True
            turns = {}
            wrapped = getattr(frame, "wrapped", ())
            if last is not None:
                # the move starts where the joints are, seen in its own frame (the tool length offset
                # the interpreter applies with a move changes the frame at that move)
                start = frame.inverse(last)
                if any(abs(start[k] - rec.start[k]) > 1e-9 for k in rec.start):
                    rec = replace(rec, start={k: start[k] for k in rec.start})
            for out in self._map(rec, frame, last):
                last = out.end
                yield out

    def _map(self, rec, frame: Frame, last: dict | None) -> Iterator:
        start = frame.point(rec.start, last)
        if frame.affine_between(rec.start, rec.end) and (rec.kind != "arc" or frame.arcs):
            end = frame.point(rec.end, start)
            if rec.kind != "arc":
                self.limits(end, rec)
                yield replace(rec, start=start, end=end)
                return
            arc = self._arc(rec, frame, start, end)
            if arc is not None:
                self.limits(end, rec)
                yield arc
                return
            if self.note is not None:
                self.note(rec, "an arc in an inclined plane runs as joint-space lines within "
                          f"{self.tolerance:g} mm of the programmed arc")
        point = _arc_point if rec.kind == "arc" else _line_point
        # one frame object for the pieces of this move: the planner joins them without a corner
        yield from self._pieces(rec, replace(frame, pieces=True), point, start)

    def _arc(self, rec: Arc, frame: Frame, start: dict, end: dict) -> Arc | None:
        """The arc in machine coordinates when the (rigid) map takes its plane onto a machine plane:
        the image of the plane's normal is a machine axis.  The machine plane is written in its own
        order (XY, YZ, ZX as G17, G19, G18) and the sense follows the image of the normal."""
        names = frame.linear
        a, o = rec.plane[0], rec.plane[1]
        if a not in names or o not in names:
            return None
        m = frame.linear_part(rec.start)
        ca, co = m[:, names.index(a)], m[:, names.index(o)]
        if abs(float(ca @ ca) - 1.0) > 1e-9 or abs(float(co @ co) - 1.0) > 1e-9 or abs(float(ca @ co)) > 1e-9:
            return None   # not rigid on the plane: the circle would not stay a circle
        w = np.cross(ca, co)
        k = int(np.argmax(np.abs(w)))
        if abs(abs(float(w[k])) - 1.0) > 1e-9:
            return None
        ccw = (rec.direction == "ccw") == (w[k] > 0)
        na, no, nn = names[(k + 1) % 3], names[(k + 2) % 3], names[k]
        c = frame.point({**rec.start, a: rec.center[a], o: rec.center[o]})
        return replace(rec, start=start, end=end, center={na: c[na], no: c[no]}, plane=(na, no, nn),
                       direction="ccw" if ccw else "cw")

    def _pieces(self, rec, frame: Frame, point, start: dict) -> Iterator:
        """Joint-space lines whose tool tip stays within the tolerance of the programmed path."""
        n = frame.initial_pieces
        joints = {0.0: start}
        for i in range(1, n + 1):   # the first cut, each joint position followed from the one before
            joints[i / n] = frame.point(point(rec, i / n) if i < n else rec.end, joints[(i - 1) / n])
        stack = [((n - 1 - i) / n, (n - i) / n, 0) for i in range(n)]
        done = []
        while stack:
            s0, s1, depth = stack.pop()
            sm = 0.5 * (s0 + s1)
            pm = point(rec, sm)
            jm = frame.point(pm, joints[s0])
            j0, j1 = joints[s0], joints[s1]
            mid = {k: 0.5 * (j0[k] + j1[k]) for k in j0}
            # the tool tip where the joint-space line puts it, against the programmed tip
            tip = frame.inverse(mid)
            x, y, z = frame.linear
            dev = math.dist((tip[x], tip[y], tip[z]), (pm[x], pm[y], pm[z]))
            joints[sm] = jm
            if dev > self.tolerance or depth < 1:
                if depth >= MAX_DEPTH:
                    raise StageError(rec, "KIN020", f"the move needs more than {2 ** MAX_DEPTH} joint-space "
                                     f"pieces to keep the tool tip within {self.tolerance:g} mm (a pose near "
                                     "a singularity?)")
                stack.append((sm, s1, depth + 1))
                stack.append((s0, sm, depth + 1))
            else:
                done.append((s0, s1))
        done.sort()
        for s0, s1 in done:
            for s_a, s_b in ((s0, 0.5 * (s0 + s1)), (0.5 * (s0 + s1), s1)):
                ja, jb = joints[s_a], joints[s_b]
                self.limits(jb, rec)
                yield self._piece(rec, frame, point, s_a, s_b, ja, jb)

    def _piece(self, rec, frame, point, s_a, s_b, ja, jb) -> Line:
        pa, pb = point(rec, s_a), point(rec, s_b)
        x, y, z = frame.linear
        tip = math.dist((pa[x], pa[y], pa[z]), (pb[x], pb[y], pb[z]))
        joint = math.sqrt(sum((jb[k] - ja[k]) ** 2 for k in jb))
        # a rapid's pieces are one path at the axes' own limits: no feed, but joined like feed moves
        # (a "rapid" record stops at its end)
        kind = "linear"
        feed = None if rec.rapid else rec.feed
        if feed is not None and tip > 1e-12:
            feed = feed * joint / tip   # the tool tip at the programmed feed
        if s_b < 1.0:   # the programmed point there, in the programmed frame (offsets as at the move's end)
            end_part = {k: pb[k] - (rec.end[k] - v) if k in pb else v for k, v in rec.end_part.items()}
        else:
            end_part = rec.end_part
        return Line(kind, ja, jb, end_part, feed, rec.feed_mode, rec.src, None, rec.dyn, frame)


def with_frames(records: Iterable, state) -> Iterator:
    """The interpreter's records, each move tagged with the frame it was made under (``record.frame``);
    a dwell or an auxiliary function made under one gets its position in machine joints."""
    kin = state.kin
    for rec in records:
        if kin.raw and rec.kind in ("linear", "rapid", "arc"):
            kin.raw = False   # an #MCS move: already in the joints
            yield rec
            continue
        frame = kin.frame_for(state) if kin.frame is not None else None
        if frame is not None:
            kind = rec.kind
            if kind in ("linear", "rapid", "arc"):
                rec = replace(rec, frame=frame)
                if kin.pending_ori:
                    kin.pending_ori = False   # the move that turned the rotary axes (#TOOL ORI)
            elif kind in ("dwell", "aux"):
                rec = replace(rec, position=frame.point(rec.position))
        yield rec


def joint_space(records: Iterable, interp) -> Iterator:
    """:class:`JointStage` over a run's records, soft limits of the channel, one note per run."""
    st = interp.state
    told = []

    def limits(position: dict, rec) -> None:
        for a, v in position.items():
            lo, hi = st.lower_limits.get(a, -math.inf), st.upper_limits.get(a, math.inf)
            if not lo - 1e-9 <= v <= hi + 1e-9:
                bound = "lower" if v < lo else "upper"
                raise StageError(rec, "KIN021", f"axis {a} reaches {v:.4f} (machine) inside the transformed move, "
                                 f"beyond its {bound} limit {lo if v < lo else hi:g}")

    def note(rec, text: str) -> None:
        if not told:
            told.append(True)
            interp.diagnostics.append(Diagnostic(rec.src.file, rec.src.line, 1, "KIN022", "info", text,
                                                 rec.src.text))

    # the stage's own generator, not one that hands its records on (one generator step less per record)
    return JointStage(interp.machine.kinematics_tolerance, limits, note).run(records)
