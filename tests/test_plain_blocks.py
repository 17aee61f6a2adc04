"""The fast path of plain blocks (:mod:`fagorcnc.interp.plain`) must be invisible.

A plain block (``N10 G1 X1 Y2 F800``, ``G2 X.. Y.. I.. J..``: literal G00-G03, G90/G91, axis words,
I J K R, F, N) skips the general executor.  Every program here runs twice, with the fast path and
with :attr:`Interpreter.plain_blocks` off, and everything must be the same: each record (its
``repr``, so every float to the last bit, and its type), the diagnostics (code, line, column,
message), the ending, the cycle time and the final state.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import fagorcnc
from fagorcnc.interp import plain
from fagorcnc.interp.interpreter import Interpreter
from fagorcnc.syntax.parser import PLAIN_LINE

PROGRAMS = Path(__file__).resolve().parents[1] / "programs"

MACHINE = {
    "origins": {"G54": {"X": 100.0, "Y": -20.0, "Z": 5.0}, "G55": {"X": -3.25}},
    "tools": {"1": {"1": {"length": 50.0, "radius": 4.0}}, "2": {"1": {"radius": 1.5}}},
}


def _run(source, machine, fast: bool, monkeypatch) -> tuple:
    monkeypatch.setattr(Interpreter, "plain_blocks", fast)
    r = fagorcnc.simulate(source, machine)
    state = r.state
    final = None if state is None else (
        state.position("machine"), state.position("part"), state.modes, state.feed, state.tool, state.offset,
        state.origin, state._state.last_n, state._state.elapsed, state._state.executed_blocks,
        state.param(1) if "P1" in str(source) else None)
    return ([(type(m).__name__, repr(m)) for m in r.moves], [repr(d) for d in r.diagnostics], r.ok,
            repr(r.ending), r.cycle_time, final)


def _same(source, monkeypatch, machine=None) -> None:
    fast = _run(source, machine, True, monkeypatch)
    general = _run(source, machine, False, monkeypatch)
    assert fast[1] == general[1]          # diagnostics first: the clearest message when they differ
    assert fast == general


def _plain_share(source, machine, monkeypatch) -> float:
    """The share of executed blocks the fast path took."""
    taken = []
    run = plain.PlainBlocks.run

    def counting(self, block):
        out = run(self, block)
        taken.append(out is not plain.NOT_PLAIN)
        return out

    monkeypatch.setattr(Interpreter, "plain_blocks", True)
    monkeypatch.setattr(plain.PlainBlocks, "run", counting)
    fagorcnc.simulate(source, machine)
    return sum(taken) / max(len(taken), 1)


def _direct_arcs(source, machine, monkeypatch) -> int:
    """How many arcs :meth:`PlainBlocks._arc` made itself."""
    made = []
    arc = plain.PlainBlocks._arc

    def counting(self, *args):
        out = arc(self, *args)
        made.append(out is not plain.NOT_PLAIN)
        return out

    monkeypatch.setattr(Interpreter, "plain_blocks", True)
    monkeypatch.setattr(plain.PlainBlocks, "_arc", counting)
    fagorcnc.simulate(source, machine)
    return sum(made)


# A bit of everything a CAM program holds around its plain moves: G91 stretches, origin changes, inch
# units, comments, labels and jumps, parameters and expressions, plane changes, tool length and radius
# compensation, mirror, scale, rotation, a canned cycle, a modal subroutine, arcs by centre and radius,
# leading zeros (CAM010), a move at feed with the spindle stopped (CAM014).
MIXED = """\
%L MYSUB
G91 G1 X0.1
G90
M17
%MIXED
G90 G0 X0 Y0 Z5 F1000
N10 G1 X1 Y2 Z-1 F800
X1.5 Y2.5 Z-1.25
N20 G2 X3.5 Y2.5 I1 J0
G3 X1.5 Y2.5 R1
G03 X3.5 Y2.5 R-1 ; a comment
G90 G01 X4 Y4 (another comment)
G090 X4.5
G91 X1 Y-1
X-0.5 Y0.25 Z0.1
G2 X2 Y0 I1 J0
G90 G54 G1 X10 Y10
G1 X11 Y11 Z2
G55 X12
G70 X1 Y1
X1.25 Y1.5 F20
G71 G1 X5 Y5 F600
P1 = 3.5
G1 X[P1] Y[P1 * 2]
X P1
[LABEL1] G1 X6 Y6
N30: X7 Y7
G91 G18 G2 X1 Z0 I0.5 K0
G90 G17
T1 D1 M6
G1 Z60
X9 Y9
G41 G1 X10 Y10
X12 Y10
G40 X14 Y12
G11 X1 Y1
G2 X2 Y2 I0.5 J0.5
G10 G1
G72 S2 X1 Y1
X1.5 Y1.5
G72 S1
G73 Q30
X2 Y0
G73
G00 Z20
G98 G81 X10 Y20 Z2 I-15 K0.5 F200
X3 Y3
G80
M3 S1000
G1 X4 Y4 Z1
#MCALL MYSUB
G1 X5 Y5
#MDOFF
N40 X6 Y6 NR2
G91 G1 X1 NR3
G90
M30
"""


def test_mixed_program_same_records_both_ways(monkeypatch):
    _same(MIXED, monkeypatch, MACHINE)


def test_mixed_program_mostly_fast(monkeypatch):
    # the plain blocks of MIXED take the fast path, the others not (about half of them are plain)
    share = _plain_share(MIXED, MACHINE, monkeypatch)
    assert 0.3 < share < 0.8


@pytest.mark.parametrize("head", ["", "T1 D1 M6\nS8000 M3\nG54\n"])
def test_cam_raster_takes_the_fast_path(head, monkeypatch):
    # with and without a tool (its length applies at the first Z move) and a work offset
    raster = head + "G90 G1 X0 Y0 Z2 F3000\nG05\n" + "\n".join(
        f"X{i * 0.5:.4f} Y{(i // 20) * 0.5:.4f} Z{i % 7 * 0.1:.4f}" for i in range(200)) + "\nG0 Z80\nM30\n"
    assert _plain_share(raster, MACHINE, monkeypatch) > 0.97
    _same(raster, monkeypatch, MACHINE)


@pytest.mark.parametrize("name", sorted(p.name for p in PROGRAMS.glob("*.nc")))
def test_example_programs_same_both_ways(name, monkeypatch):
    _same(PROGRAMS / name, monkeypatch)


# Errors: the fast path raises the general path's error at the same block and column.
ERRORS = [
    "G90 G1 X1 F-5\n",                                   # INT029 negative feed
    "G90 G1 X1\n",                                       # INT060 no feed
    "G90 G1 X1 F100\nG2 X3 Y0 I1 J0.5\n",                # INT062 start and end radius differ
    "G90 G1 X1 F100\nG2 X30 Y0 R1\n",                    # INT064 radius too small for the chord
    "G90 G1 X1 F100\nG2 X1 Y0 I0 J0\n",                  # INT061 centre on the start point
    "G90 G1 X1 F100\nX100000\n",                         # INT100 beyond the soft limit
    "G90 G1 X1 X2 F100\n",                               # INT023 an axis twice (general path)
    "G90 G1 G2 X1 F100\n",                               # INT012 two motion G functions (general path)
    "G1 X1 F100\nN-5 X2\n",                              # INT037 block number out of range
    "G1 X1 F100\nN1.5 X2\n",                             # INT036 block number not whole
    "G1 X1 F100\nI1 I2\n",                               # INT023 a parameter twice
]


@pytest.mark.parametrize("program", ERRORS)
def test_errors_same_both_ways(program, monkeypatch):
    _same("%ERR\n" + program + "M30\n", monkeypatch)


# Arcs made directly (PlainBlocks._arc) against the general _arc.  Each program is valid and is checked to
# run to its end; the figures are chosen so every arc closes (start and end radius equal):
ARCS = {
    # G17 by centre and by R: (0,0) -> (10,0) about (5,0), back about (5,0), R5 both ways, then R-12 from
    # (0,0) to (20,0): the arc over 180 degrees of a chord 20 < 2 * 12
    "centre and R": "G2 X10 Y0 I5 J0\nG3 X0 Y0 I-5 J0\nG2 X10 Y0 R5\nG3 X0 Y0 R5\nG2 X20 Y0 R-12\n",
    # G91: the same half circles as increments; an I alone (J = 0), a J alone from (10,0): centre (10,5),
    # end (10,10); R with an end point in the plane
    "G91": "G91 G2 X10 Y0 I5 J0\nG3 X-10 Y0 R5\nG2 X10 Y0 I5\nG3 X0 Y10 J5\nG90\n",
    # helices: K2 pitch with 6 mm of Z is 3 turns (1080 degrees) back to (10,0); a quarter without pitch
    # from (10,0) about (0,0) to (0,10) with 3 mm of Z; a full circle without axis words
    "helix": "G0 X10 Y0 Z0\nG1 F800\nG3 X10 Y0 Z-6 I-10 J0 K2\nG2 X0 Y10 Z-9 I-10 J0\nG2 I0 J-10\n",
    # G18 (abscissa Z, ordinate X, centre K I, pitch J): (Z0,X0) about (Z5,X0) to (Z10,X0), back by R5,
    # then a helix along Y: 3 mm at pitch 4 is 270 degrees
    "G18": "G18\nG2 X0 Z10 I0 K5\nG3 X0 Z0 R5\nG2 X0 Z10 Y3 I0 K5 J4\nG17\n",
    # G19 (abscissa Y, ordinate Z, centre J K): (Y0,Z0) about (Y5,Z0) to (Y10,Z0), back by R5
    "G19": "G19\nG2 Y10 Z0 J5 K0\nG3 Y0 Z0 R5\nG17\n",
    # inches: I0.5 = 12.7 mm, R0.5 the same; F10 inch/min
    "G70": "G70\nG1 F10\nG2 X1 Y0 I0.5 J0\nG3 X0 Y0 R0.5\nG71\n",
    # G261: the centre is absolute, (5,0) from (0,0) to (10,0); G262 back to incremental centres
    "G261": "G261\nG2 X10 Y0 I5 J0\nG262\nG3 X0 Y0 I-5 J0\nG2 X10 Y0 I5 J0\n",
    # G265 corrects a centre off by 0.001 mm (end radius 5.0000001, within CIRINERR 0.01), G264 keeps it
    "G264 G265": "G265\nG2 X10 Y0.001 I5 J0\nG264\nG3 X0 Y0 I-5 J-0.001\nG2 X10 Y0 I5 J0\n",
    # a tool whose length applies on the first move of Z (an arc here), under G54
    "tool": "T1 D1 M6\nG54 G0 X0 Y0 Z100\nG1 F800\nG2 X10 Y0 Z90 I5 J0\nG3 X0 Y0 R5\n",
}


@pytest.mark.parametrize("name", sorted(ARCS))
def test_arcs_same_both_ways(name, monkeypatch):
    program = "%ARCS\nG90 G0 X0 Y0 Z0 F800\nG1 F800\n" + ARCS[name] + "P1 = V.G.R\nM30\n"
    assert _run(program, MACHINE, True, monkeypatch)[2]   # it runs to its end
    assert _direct_arcs(program, MACHINE, monkeypatch) >= 2
    _same(program, monkeypatch, MACHINE)


ARC_ERRORS = [
    "G2 X3 Y0 I1 J0.5\n",                # INT062 start radius 1.118 and end radius 2.06 differ
    "G2 X30 Y0 R1\n",                    # INT064 a radius smaller than half the chord
    "G2 X1 Y0 I0 J0\n",                  # INT061 centre on the start point
    "G2 X10 Y0 Z-5 I5 J0 K0\n",          # INT069 helix pitch 0
    "G2 X2000 Y0 I1000 J0\n",            # INT100 the end beyond the soft limit
    "G2 X10 Y0 I5 J0 R5\n",              # R with a centre: the general path
    "G2 Y1 R5\n",                        # an end point in the plane: R is the radius
    "G2 Z5 R5\n",                        # no end point in the plane: R is polar (general path: INT061)
    "G2 K2\n",                           # only a pitch: the stored radius, none here (INT061)
]


@pytest.mark.parametrize("program", ARC_ERRORS)
def test_arc_errors_same_both_ways(program, monkeypatch):
    _same("%ERR\nG90 G0 X0 Y0 Z0\nG1 F800\n" + program + "M30\n", monkeypatch)
    _same("%ERR\nG90 G0 X0 Y0 Z0\nG2 X10 Y0 I5 J0\nM30\n", monkeypatch)   # INT060 no feed on an arc


@pytest.mark.parametrize("cirinfact", [0.5, 0.1])
@pytest.mark.parametrize("correction", ["G264", "G265"])
def test_arc_radius_tolerances_same_both_ways(cirinfact, correction, monkeypatch):
    # end radius 5.01 against 5: 0.01 mm over CIRINERR 0.001, 0.2 % within CIRINFACT 0.5 % (the centre kept or
    # corrected) or over 0.1 % (INT062)
    machine = {**MACHINE, "cirinerr": 0.001, "cirinfact": cirinfact}
    program = f"%TOL\nG90 G0 X0 Y0 Z0\n{correction}\nG1 F800\nG2 X10.01 Y0 I5 J0\nG3 X0 Y0 R5.005\nM30\n"
    assert _run(program, machine, True, monkeypatch)[2] == (cirinfact == 0.5)
    assert _direct_arcs(program, machine, monkeypatch) == (2 if cirinfact == 0.5 else 0)
    _same(program, monkeypatch, machine)


# Feeds of plain lines: the fast path's G94 feed (F itself, clamped to MAXFEED) and its F words (a
# positive F in mm/min or mm/rev, inch F) against the general _feed and _active_feed; the others (G93 F,
# F0, G95, DEFAULTFEED) go through the general functions from the fast path.
FEEDS = {
    "G94": "G1 X1 F100\nX2 F250.5\nY3\n",
    "MAXFEED clamp": "G1 X1 F100\nX2 F9000\nY3\nX4 F50\n",
    "inch F": "G70\nG1 X1 F10\nY1\nG71\nX2 F10\n",
    "G93": "G93\nG1 X1 F2\nY3 F0.5\nG94\nX4 F300\n",
    "G95": "S1000 M3\nG95\nG1 X1 F0.1\nY2\nG94\nX3 F200\n",
    "F0": "G1 X1 F100\nX2 F0\nY3\n",
    "DEFAULTFEED": "G0 X1\nG1 X2\nY3 F100\n",
    # arcs: G94 takes F without the arc's length (MAXFEED still clamps), the other modes their own way
    "G94 arcs": "G1 X1 F100\nG2 X3 I1 J0\nG3 X1 I-1 J0 Z1 F9000\nG2 X3 R1 F250.5\n",
    "G93 arcs": "G93\nG1 X1 F2\nG2 X3 I1 J0 F0.5\nG3 X1 I-1 J0 Z2\nG94\nG2 X3 I1 J0 F300\n",
    "G95 arcs": "S1000 M3\nG95\nG1 X1 F0.1\nG2 X3 I1 J0\nG3 X1 Z1 I-1 J0\n",
    "F0 arcs": "G1 X1 F100\nG2 X3 I1 J0 F0\n",
    "DEFAULTFEED arcs": "G0 X1\nG2 X3 I1 J0\nG3 X1 I-1 J0 F100\n",
}
FEED_MACHINE = {**MACHINE, "max_feed": 5000.0, "defaults": {"DEFAULTFEED": 1}}


@pytest.mark.parametrize("name", sorted(FEEDS))
def test_feeds_same_both_ways(name, monkeypatch):
    program = "%FEED\nG90 G0 X0 Y0 Z0\n" + FEEDS[name] + "M30\n"
    _same(program, monkeypatch, FEED_MACHINE)
    _same(program, monkeypatch, MACHINE)   # without MAXFEED (and DEFAULTFEED: INT060 where no F is active)


def test_maxfeed_clamps_a_plain_line(monkeypatch):
    # F9000 over MAXFEED 5000: the record's feed is 5000 mm/min, 1 mm in 0.012 s (1 / 5000 * 60)
    monkeypatch.setattr(Interpreter, "plain_blocks", True)
    r = fagorcnc.simulate("%F\nG90 G0 X0 Y0 Z0\nG1 X1 F9000\nM30\n", FEED_MACHINE)
    line = next(m for m in r.moves if m.kind == "linear")
    assert line.feed == 5000.0
    assert _plain_share("%F\nG90 G0 X0 Y0 Z0\nG1 X1 F9000\nM30\n", FEED_MACHINE, monkeypatch) > 0.5


_axis = st.sampled_from(["X", "Y", "Z", "I", "J", "K", "R", "F", "N", "G", "A", "B", "S", "M", "Q"])
_value = st.sampled_from(["0", "1", "2", "3", "-1", "0.5", "-2.25", "90", "91", "17", "18", "10", "1.5",
                          "100", "500", "-0.001", "3.0000", "01", "090"])
_block = st.lists(st.tuples(_axis, _value).map("".join), min_size=1, max_size=6).map(" ".join)


@settings(max_examples=60, deadline=None)
@given(blocks=st.lists(_block, min_size=1, max_size=8))
def test_random_blocks_same_both_ways(blocks, monkeypatch_session):
    # whatever the words (plain or not, valid or not), both ways give the same run
    program = "%RAND\nG90 G1 X0 Y0 Z0 F1000\n" + "\n".join(blocks) + "\nM30\n"
    _same(program, monkeypatch_session)


@pytest.fixture(scope="module")
def monkeypatch_session():
    with pytest.MonkeyPatch.context() as mp:
        yield mp


def test_record_maker_makes_the_same_records():
    # Line, Arc and Source made without their __init__ compare, hash and print as the class makes them;
    # the fields left out take their defaults; a class that needs its __init__ is returned as it is
    import dataclasses
    import pickle

    from fagorcnc.interp.records import Arc, Line, Source

    src = Source("p.nc", 3, "G1 X1")
    assert plain.record_maker(Source)(file="p.nc", line=3, text="G1 X1") == src
    start, end = {"X": 0.0, "Y": 0.0}, {"X": 1.0, "Y": 0.0}
    made = plain.record_maker(Line)(kind="linear", start=start, end=end, end_part=end, feed=800.0, feed_mode="G94",
                                    src=src)
    line = Line("linear", start, end, end, 800.0, "G94", src)
    assert type(made) is Line and made == line and repr(made) == repr(line) and hash(made.src) == hash(src)
    assert pickle.loads(pickle.dumps(made)) == line
    assert dataclasses.replace(made, feed=100.0) == dataclasses.replace(line, feed=100.0)
    arc = Arc("arc", start, end, end, {"X": 0.5, "Y": 0.0}, {"X": 0.5, "Y": 0.0}, "cw", ("X", "Y", "Z"), 0.5, 0,
              800.0, "G94", src, joins=(40, 138))
    assert plain.record_maker(Arc)(kind="arc", start=start, end=end, end_part=end, center={"X": 0.5, "Y": 0.0},
                                   center_part={"X": 0.5, "Y": 0.0}, direction="cw", plane=("X", "Y", "Z"),
                                   radius=0.5, turns=0, feed=800.0, feed_mode="G94", src=src,
                                   joins=(40, 138)) == arc

    @dataclasses.dataclass
    class Plain:
        x: int
        y: list = dataclasses.field(default_factory=list)

    assert plain.record_maker(Plain) is Plain
    assert all(plain.record_maker(cls) is not cls for cls in (Line, Arc, Source))   # the records' own makers

    @dataclasses.dataclass(frozen=True, slots=True)
    class Other:
        x: int

    Other.__slots__ = ("x", "y")   # slots that are not its layout: no twin of the same layout, the class itself
    assert plain.record_maker(Other) is Other


def test_record_maker_takes_the_fields_in_order():
    # the plain blocks call the maker with the fields in the class's order: the same record as by keyword
    from fagorcnc.interp.records import Line, Source

    src = Source("p.nc", 3, "G1 X1")
    start, end = {"X": 0.0}, {"X": 1.0}
    make = plain.record_maker(Line)
    by_order = make("linear", start, end, end, 800.0, "G94", src, None, None, None, (136, 139), None, None)
    by_name = make(kind="linear", start=start, end=end, end_part=end, feed=800.0, feed_mode="G94", src=src,
                   joins=(136, 139))
    assert repr(by_order) == repr(by_name) and by_order == Line("linear", start, end, end, 800.0, "G94", src,
                                                                  joins=(136, 139))


def _general_points(state, pos: dict, end_part: dict) -> tuple:
    """The part position and the machine end point as ``_motion`` works them out (offsets(), to_machine(),
    shared_end())."""
    off = state.offsets()
    cur_part = {x: pos[x] - off[x] for x in state.axes}
    end = {x: v + off[x] for x, v in end_part.items()}
    return cur_part, state.shared_end(end, end_part)


@pytest.mark.parametrize("origin", [0.0, -0.0, 2.5])
@pytest.mark.parametrize("length", [None, 50.0])
@pytest.mark.parametrize("point", [(1.0, -0.0, 3.5), (float("inf"), 0.0, -0.0), (float("nan"), 1.0, 2.0),
                                   (float("inf"), float("-inf"), 0.0)])
@pytest.mark.parametrize("order", ["XYZ", "ZXY"])
def test_part_point_and_machine_end_as_offsets_make_them(origin, length, point, order):
    # the shortcut of every offset 0.0 gives the general path's points to the last bit (-0.0, inf, NaN), the
    # same dict where the general path shares it, and the channel's axis order
    from fagorcnc.config.machine import load_machine
    from fagorcnc.interp.state import ChannelState

    st = ChannelState(load_machine(None))
    st.abs_offset["Y"] = origin
    st.inc_offset["X"] = -origin
    if length is not None:
        st.length_offset = {"Z": length}
    pos = {a: v for a, v in zip(order, (4.0, -0.0, 1.25), strict=True)}
    end_part = dict(zip("XYZ", point, strict=True))
    off, cur_part = plain._part_point(st, pos)
    general_part, general_end = _general_points(st, pos, end_part)
    assert repr(cur_part) == repr(general_part)
    assert (off is None) == (origin == 0.0 and length is None)
    end = plain._machine_end(st, end_part, off)
    assert repr(end) == repr(general_end) and (end is end_part) == (general_end is end_part)


@pytest.mark.parametrize("head", ["", "G54\n", "T1 D1 M6\nG54\n", "G159=2\nG158 X-0 Y0\n"])
def test_signed_zeros_and_offsets_same_both_ways(head, monkeypatch):
    # -0.0 words and positions, with and without origins and tool length, lines and arcs
    program = head + ("G90 G1 X-0 Y-0 Z-0 F1000\nG1 X0 Y-0\nG2 X-0 Y0 I-0 J0\nX1 Y-0\nG3 X-0 Y1 I-1 J0\n"
                      "G91 G1 X-0 Y-0 Z-0\nX-1 Y0\nG90 G0 X-0 Z-0\nM30\n")
    _same(program, monkeypatch, MACHINE)
    _same(program, monkeypatch)


@pytest.mark.parametrize("fast", [True, False])
def test_arc_variables_read_after_a_plain_arc(fast, monkeypatch):
    # V.G.R, V.G.I, V.G.J and V.G.CIRERR are worked out when read, from the last arc's points (kept as given):
    # the arc G2 X2 Y0 I1.0005 J0 from X0 Y0, its end radius 0.0005 short, centre corrected by G265 onto X1
    monkeypatch.setattr(Interpreter, "plain_blocks", fast)
    program = ("%V\nG90 G0 X0 Y0 Z0\nG265\nG1 F800\nG2 X2 Y0 I1.0005 J0\n"
               "P1 = V.G.R\nP2 = V.G.I\nP3 = V.G.J\nP4 = V.G.CIRERR[1]\nP5 = V.G.CIRERR[2]\nM30\n")
    r = fagorcnc.simulate(program, {"cirinerr": 0.01})
    assert r.ok, r.diagnostics
    values = [r.state.param(n) for n in range(1, 6)]
    assert values == pytest.approx([1.0, 1.0, 0.0, 0.0005, 0.0], abs=1e-12)
    import math

    from fagorcnc.interp.gvars import arc_values
    start, programmed, centre, end = (0.0, 0.0), (1.0005, 0.0), (1.0, 0.0), (2.0, 0.0)
    assert arc_values((start, programmed, centre, end, ("X", "Y", "Z"))) == (
        math.dist(end, centre), {"X": 1.0, "Y": 0.0}, {"X": 1.0005 - 1.0, "Y": 0.0}, ("X", "Y", "Z"))


# Moves whose squares sum to different floats in a loop of += and in sum(), which adds floats with
# compensation from Python 3.12 on (X² holds the small axes' squares only there): the plain path
# sums as Line.length and Arc.length do, so both ways give the same length and time on every Python.
LONG_MACHINE = {"axes": {a: {"type": "linear", "max_velocity": 10000.0, "min_limit": -50000.0,
                             "max_limit": 50000.0} for a in "XYZ"}}


@pytest.mark.parametrize("block", ["G1 X15762.1988 Y0.0002 Z0.0002 F1000", "G1 X17205.3754 Y0.0002 Z0.0002 F1000",
                                   "G2 X0 Y15384.9189 Z0.0001 I0 J7692.45945 F1000"])
def test_long_moves_sum_their_squares_as_the_records_do(block, monkeypatch):
    program = f"%LONG\nG90 G0 X0 Y0 Z0\n{block}\nM30\n"
    _same(program, monkeypatch, LONG_MACHINE)
    monkeypatch.setattr(Interpreter, "plain_blocks", True)
    r = fagorcnc.simulate(program, LONG_MACHINE)
    move = r.moves[-1]
    if move.kind == "linear":   # the plain path's time is the record's length at its feed
        assert r.cycle_time == pytest.approx(move.length / 1000.0 * 60.0, rel=1e-12)


def test_plain_arc_time_is_the_record_time(monkeypatch):
    # PlainBlocks._arc works out record_time() of its arc on the way (Arc.sweep is the sweep it made, where
    # the record's points are its points): the same float as record_time() of the record, in every feed mode,
    # helices, G18/G19, inches, G265, offsets and signed zeros included (those it does not time: record_time()
    # itself in the block loop); and it times the commonest arcs
    from fagorcnc.interp.records import record_time

    timed = []
    arc = plain.PlainBlocks._arc

    def timing(self, *args):
        out = arc(self, *args)
        if out is not plain.NOT_PLAIN:
            timed.append((self.seconds, out))
        return out

    monkeypatch.setattr(Interpreter, "plain_blocks", True)
    monkeypatch.setattr(plain.PlainBlocks, "_arc", timing)
    programs = [("%A\nG90 G0 X0 Y0 Z0 F800\nG1 F800\n" + text + "M30\n", MACHINE) for text in ARCS.values()]
    programs += [("%F\nG90 G0 X0 Y0 Z0\n" + FEEDS[name] + "M30\n", FEED_MACHINE) for name in FEEDS if "arcs" in name]
    programs.append(("G90 G1 X-0 Y-0 Z-0 F1000\nG2 X-0 Y0 I-0 J0\nX1 Y-0\nG3 X-0 Y1 I-1 J0\nG3 X0 Y-1 I0 J-1\n"
                     "G3 X0.3 Y-0.9 I-0.3 J1.9\nM30\n", None))
    # the centre X-0 (0.0 in the record) and the end on it (within CIRINERR): the sweeps differ, the lengths not
    programs.append(("G90 G264 G1 X-0 Y0.005 Z0 F1000\nG2 X-0 Y0 Z1 I-0 J-0.005\nM30\n", None))
    # helices of 600, 1384.6 and 2571.4 degrees: their length is that of the pitch's sweep, not of their end
    # points' sweep and turns (1384.6153846153845 and 1384.6153846153843 degrees)
    programs.append(("G90 G0 X10 Y0 Z0\nG1 F800\nG3 X0 Y10 Z-5 I-10 J0 K3\nG1 X10 Y0\nG3 X0 Y10 Z0 I-10 J0 K1.3\n"
                     "G1 X10 Y0\nG3 X0 Y10 Z-5 I-10 J0 K0.7\nM30\n", None))
    for text, machine in programs:
        fagorcnc.simulate(text, machine)
    machine = fagorcnc.load_machine(MACHINE)
    for seconds, rec in timed:
        if seconds is not None:
            assert repr(seconds) == repr(record_time(machine, rec)), rec
    assert sum(seconds is not None for seconds, _ in timed) >= 20


def _as_tuples(split):
    """``split`` (a splitter of plain lines) giving plain tuples: blocks whose words :meth:`PlainBlocks.run`
    checks one by one."""
    def splitting(lines):
        return [tuple(items) for items in split(lines)]
    return splitting


@pytest.mark.parametrize("name", ["mixed", "arcs", "errors"])
def test_plain_words_run_as_checked_words(name, monkeypatch):
    # the items of a plain line are PlainWords, whose words run() does not check: the same run as the same
    # words in a plain tuple, each checked (lines, arcs, G90/G91, N, feeds, words run() refuses, errors)
    from fagorcnc.syntax import builder, reader
    from fagorcnc.syntax.ast import PlainWords
    program = {"mixed": MIXED, "arcs": "%A\nG90 G0 X0 Y0 Z0 F800\nG1 F800\n" + "".join(ARCS.values()) + "M30\n",
               "errors": "%E\nG90 G1 X0 Y0 F800\nN1 G1 X1 X2\nG2 X1 Y1 R0\nM30\n"}[name]
    lines = [line for line in program.splitlines() if PLAIN_LINE(line)]
    assert lines and all(type(items) is PlainWords for items in builder.split_plain_lines(lines))
    marked = _run(program, MACHINE, True, monkeypatch)
    monkeypatch.setattr(reader, "split_plain_lines", _as_tuples(builder.split_plain_lines))
    monkeypatch.setattr(reader, "split_plain", lambda text: tuple(builder.split_plain(text)))
    assert type(reader.parse_text(program).main.blocks[1].items) is tuple
    assert _run(program, MACHINE, True, monkeypatch) == marked


@given(line=_block)
def test_plain_lines_hold_literal_words(line):
    # what run() takes on trust from a PlainWords tuple, _literal_words() finds in it
    from fagorcnc.syntax.builder import split_plain
    if PLAIN_LINE(line):
        assert plain._literal_words(split_plain(line))


@pytest.mark.parametrize("name", ["mixed", "aids"])
def test_cycle_time_is_the_time_of_the_records_handed_on(name):
    # Interpreter.run adds the time the block loop kept for a record it hands on unchanged, else record_time():
    # the sum of record_time() of every record handed on, in order, whatever the stages replaced (radius
    # compensation, corner aids) or made at the address of a record freed before
    from fagorcnc.interp.records import record_time
    from fagorcnc.machine import load_machine
    from fagorcnc.syntax import parse_text
    program = {"mixed": MIXED, "aids": "%A\nT2 D1 M6\nG90 G0 X5 Y-10 Z0\nG42 G1 X5 Y0 F1000\n"
               + "X10 Y0\nG36 I1\nX10 Y10\nG39 I1\nX0 Y10\nG36 I1\nX0 Y0\nX5 Y0\n" * 40
               + "G40 G1 X5 Y-10\nM30\n"}[name]
    machine = load_machine(MACHINE)
    interp = Interpreter(parse_text(program), machine)
    total = 0.0
    for rec in interp.run():
        total += record_time(machine, rec)
    assert not [d for d in interp.diagnostics if d.is_error]
    assert interp.cycle_time == total
