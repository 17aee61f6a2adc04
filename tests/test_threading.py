"""G33 electronic threading and G63 rigid tapping (seed 002 ch. 8.7-8.8, L7285-L7690; spec 03 §B.13-§B.14).

Feeds are worked by hand from the manual's rule feed = speed x pitch on the pitch axis (L7381-L7382) and
pitch = F / S for G63 (L7563-L7565).
"""

from __future__ import annotations

import math

import pytest

import fagorcnc
from fagorcnc.backends.interpcnc.backend import InterpCncBackend

LATHE = {"axes": {"X": {}, "Z": {}}}   # the manual's lathe examples program X in radius (L7495)


def _ok(program, machine=None):
    r = fagorcnc.simulate(program, machine)
    assert r.ok, [str(d) for d in r.diagnostics]
    return r


def _threads(r):
    return [m for m in r.moves if m.kind == "linear" and m.thread is not None]


def _errors(program, machine=None):
    return [(d.line, d.code) for d in fagorcnc.simulate(program, machine).errors]


# the manual's milling example L7425-L7435: S100, K1.5 -> 150 mm/min; retract with M19 and a side move
MILL = "S100 M03\nG01 G90 X30 Y30 Z0 F500\nG33 Z-30 K1.5\nM19 S0\nG91 G00 X3\nG90 Z10\nS100 M03\nM30\n"


def test_g33_feed_is_speed_times_pitch_and_runs_at_100_percent():
    r = _ok(MILL)
    (t,) = _threads(r)
    # 100 rpm x 1.5 mm = 150 mm/min (L7413-L7414 say "1000 t/min", the program and the feed say S100)
    assert t.feed == pytest.approx(150.0) and t.feed_mode == "G33"
    assert (t.thread.pitch, t.thread.axis, t.thread.speed, t.thread.entry) == (1.5, "Z", 100.0, 0.0)
    assert t.dyn.override_locked and t.dyn.corner == "G50"
    # the retract: M19 S0 orients the spindle at 0 degrees, then the side move and the exit
    assert [(m.function, m.value) for m in r.moves if m.kind == "aux" and m.line == 4] == [("SPOS", 0.0),
                                                                                         ("M", 19.0)]

    def thread_time(machine):
        seg = next(s for s in fagorcnc.simulate(MILL, machine).segments(keep_profiles=False)
                   if s.kind == "motion" and s.line == 3)
        return seg.duration

    # 30 mm at 150 mm/min = 12 s plus the ramps; a 50 % feed override does not slow the thread (L7382-L7384)
    full = thread_time(None)
    assert 12.0 <= full < 12.5
    assert thread_time({"planner": {"feed_override": 50.0}}) == pytest.approx(full)


def test_the_g01_before_the_thread_follows_the_override():
    # the override is locked on the thread only: the G01 before it (30*sqrt(2) = 42.43 mm at 500 mm/min,
    # 5.09 s) takes about twice as long at 50 %
    def g01(machine):
        return next(s.duration for s in fagorcnc.simulate(MILL, machine).segments(keep_profiles=False)
                    if s.kind == "motion" and s.line == 2)
    assert g01({"planner": {"feed_override": 50.0}}) == pytest.approx(2 * g01(None), rel=0.01)


def test_three_starts_synchronise_on_their_entry_angles():
    # L7437-L7470: three starts at 20, 140 and 260 degrees (360 / 3 apart)
    prog = ("S100 M03\nG01 G90 X30 Y30 Z0 F500\nG33 Z-30 K1.5 Q1=20\nM19 S0\nG91 G00 X3\nG90 Z10\n"
            "S100 M03\nG01 G90 X30 Y30 Z0\nG33 Z-30 K1.5 Q1=140\nM19 S0\nG91 G00 X3\nG90 Z10\n"
            "S100 M03\nG01 G90 X30 Y30 Z0\nG33 Z-30 K1.5 Q1=260\nM19 S0\nG91 G00 X3\nG90 Z10\nS100 M03\nM30\n")
    assert [t.thread.entry for t in _threads(_ok(prog))] == [20.0, 140.0, 260.0]


def test_lathe_longitudinal_and_two_start_threads():
    # L7505-L7526: S100, K5 along Z -> 500 mm/min; two starts Q1=0 and Q1=180
    r = _ok("S100 M03\nG00 G90 X200 Z190\nX116 Z180\nG33 Z40 K5\nG00 X200\nZ190\n"
            "G00 G90 X200 Z190\nX116 Z180\nG33 Z40 K5 Q1=0\nG00 X200\nZ190\nX116 Z180\nG33 Z40 K5 Q1=180\n"
            "G00 X200\nZ190\nM30\n", LATHE)
    threads = _threads(r)
    assert [t.feed for t in threads] == [pytest.approx(500.0)] * 3
    assert [t.thread.entry for t in threads] == [0.0, 0.0, 180.0]
    assert {t.thread.axis for t in threads} == {"Z"}


def test_taper_thread_pitch_is_on_the_axis_not_on_the_path():
    # L7530-L7540: from (X84, Z190) to (X140, Z50), K5 at S100: Z runs at 500 mm/min; the path is
    # sqrt(56^2 + 140^2) = 150.785 mm for 140 mm of Z, so F = 500 * 150.785 / 140 = 538.52 mm/min
    r = _ok("S100 M03\nG00 G90 X200 Z190\nX84\nG33 X140 Z50 K5\nG00 X200\nZ190\nM30\n", LATHE)
    (t,) = _threads(r)
    assert t.feed == pytest.approx(500.0 * math.hypot(56, 140) / 140)
    assert t.feed * 140 / t.length == pytest.approx(500.0)   # the Z component is speed x pitch


def test_joined_threads_synchronise_once_and_are_not_rounded():
    # L7542-L7552, with "G33 Z120 Z50 K5" read as G33 Z120 K5 (Z is written twice there: spec 03 §F.5).
    # The second block is joined: Q1 only in the first after G33 is activated (L7366-L7370). Z 120 -> 60,
    # X 96 -> 160: F = 500 * sqrt(60^2 + 64^2) / 60 = 731.06 mm/min.  G05 is active, yet no curve is
    # inserted inside the thread: the blocks meet at their programmed corner
    prog = "S100 M03\nG00 G90 G05 X220 Z230\nX96\nG33 Z120 K5\nG33 X160 Z60 K5\nG00 X220\nZ230\nM30\n"
    r = fagorcnc.simulate(prog, LATHE)
    assert r.ok and [(d.line, d.code) for d in r.diagnostics] == [(5, "INT187")]   # a corner: pitch not kept
    first, second = _threads(r)
    assert (first.thread.entry, second.thread.entry) == (0.0, None)
    assert second.feed == pytest.approx(500.0 * math.hypot(60, 64) / 60)
    segs = [s for s in r.segments(keep_profiles=False) if s.kind == "motion"]
    assert not any(s.blend for s in segs)
    end_of_first = next(s for s in segs if s.line == 4)
    assert end_of_first.piece.end[1] == pytest.approx(120.0) and end_of_first.v1 == 0.0
    # the written typo itself is an error, not a guess
    assert _errors(prog.replace("G33 Z120 K5", "G33 Z120 Z50 K5"), LATHE) == [(4, "INT023")]


def test_joined_threads_in_line_run_on_without_stopping():
    # two G33 blocks along Z, the second joined (no Q1 counted): Z -10 then -20 at 1 mm x 300 rpm =
    # 300 mm/min; the joint is tangent, so the axes run through it at the thread's speed (5 mm/s)
    r = _ok("S300 M03\nG33 Z-10 K1\nG33 Z-20 K1\nM30\n")
    first = next(s for s in r.segments(keep_profiles=False) if s.kind == "motion" and s.line == 2)
    assert first.v1 == pytest.approx(5.0)


def test_a_thread_after_another_motion_mode_synchronises_again():
    r = _ok("S100 M03\nG33 Z-10 K1 Q1=30\nG33 Z-20 K1 Q1=90\nG00 Z5\nG33 Z-10 K1 Q1=90\nM30\n")
    assert [t.thread.entry for t in _threads(r)] == [30.0, None, 90.0]


@pytest.mark.parametrize(("setup", "block"), [
    ("G17", "G33 Z40 K2"), ("G18", "G33 Z40 K2"), ("G19", "G33 Z40 K2"),
    ("G20 Z1 Y2 X3", "G33 Z40 I2"), ("G20 Y1 Z2 X3", "G33 Z40 J2"), ("G20 Y1 Z3 X2", "G33 Z40 K2"),
])
def test_the_pitch_letter_names_the_axis_in_every_plane(setup, block):
    # L7330-L7352: on an X-Y-Z channel every one of these threads along Z with a 2 mm pitch
    (t,) = _threads(_ok(f"S100 M03\n{setup}\n{block}\nM30\n"))
    assert (t.thread.axis, t.thread.pitch, t.feed) == ("Z", 2.0, pytest.approx(200.0))


@pytest.mark.parametrize(("program", "code"), [
    ("S100 M03\nG33 Z-30\nM30\n", "INT180"),                 # no pitch
    ("S100 M03\nG33 Z-30 K0\nM30\n", "INT180"),              # pitch not positive
    ("S100 M03\nG33 Z-30 I1 K1\nM30\n", "INT180"),           # two pitch letters
    ("S100 M03\nG33 X10 K1\nM30\n", "INT181"),               # the pitch axis Z does not move
    ("S100\nG33 Z-30 K1.5\nM30\n", "INT182"),                # spindle stopped (M05 at power-on)
    ("S100 M03\nM19 S0\nG33 Z-30 K1.5\nM30\n", "INT182"),    # spindle in M19 positioning
    ("M03\nG33 Z-30 K1.5\nM30\n", "INT182"),                 # no speed
    ("G0 X20\nG96 S100 M03\nG33 Z-30 K1.5\nM30\n", "INT182"),   # G96: the speed changes with X
    ("S100 M03\nG33 Z-30 K1.5 Q1=400\nM30\n", "INT184"),     # entry angle beyond 359.9999
    ("S3000 M03\nG33 Z-30 K10\nM30\n", "INT183"),            # 30000 mm/min: above the axis maximum
    ("T1 D1 M6\nS100 M03\nG41 G01 X10 F100\nG33 Z-30 K1\nM30\n", "INT186"),   # under radius compensation
    ("S100 M03\nG33 G01 Z-30 K1\nM30\n", "INT012"),       # L7404: G33 excludes G00-G03 and G63
    ("S100 M03\nF100\nG33 G63 Z-30 K1\nM30\n", "INT012"),
])
def test_threading_errors(program, code):
    machine = {"tools": {"1": {"1": {"radius": 3.0}}}}
    assert [c for _line, c in _errors(program, machine)] == [code]


def test_q1_outside_a_thread_is_not_meaningful():
    assert [c for _l, c in _errors("G01 X10 Q1=20 F100\nM30\n")] == ["INT025"]


def test_the_thread_feed_is_never_cut_down_by_maxfeed():
    # an ordinary F is clamped by MAXFEED silently (L4072); a thread's would cut the wrong pitch
    assert _errors("S1000 M03\nG33 Z-30 K2\nM30\n", {"max_feed": 1500.0}) == [(2, "INT183")]   # 2000 > 1500


# ------------------------------------------------------------------ G63 rigid tapping
def test_g63_pitch_is_feed_over_speed():
    # L7585-L7595: G94 F300 ... G63 Z20 S200 -> pitch 300 / 200 = 1.5 mm; the feed stays F
    (t,) = _threads(_ok("G94 F300\nG01 G90 X30 Y30 Z50\nG63 Z20 S200\nM30\n"))
    assert (t.feed, t.feed_mode, t.thread.pitch, t.thread.speed, t.thread.rigid) == (300.0, "G63", 1.5, 200.0, True)
    assert not t.dyn.override_locked   # L7647-L7649: the override works, the CNC adapts the spindle


def test_g63_return_with_the_opposite_sign_of_s():
    # L7602-L7607: G63 Z-30 S100 then G63 Z0 S-100 backs the tap out; F400 / 100 = 4 mm pitch both ways
    r = _ok("G94 F400\nG01 G90 X30 Y30 Z0\nG63 Z-30 S100\nG63 Z0 S-100\nG01 Z10\nM30\n")
    down, up = _threads(r)
    assert (down.thread.speed, up.thread.speed) == (100.0, -100.0)
    assert down.thread.pitch == up.thread.pitch == 4.0
    # the S of a G63 block stays the active speed (L7637-L7639): a G63 without S turns at -100 again
    r = _ok("G94 F400\nG63 Z-30 S100\nG63 Z0 S-100\nG63 Z-5\nM30\n")
    assert [t.thread.speed for t in _threads(r)] == [100.0, -100.0, -100.0]


def test_m19_cancels_g63_and_retracts():
    # L7596-L7601: G63 Z-30 S100, M19 S0 orients the spindle and cancels G63 (L7642); the side move
    # and the exit are G01 blocks. A block after M19 without a G code runs in the IMOVE mode (G00 here)
    r = _ok("G94 F400\nG01 G90 X30 Y30 Z0\nG63 Z-30 S100\nM19 S0\nZ10\nM30\n")
    after = next(m for m in r.moves if m.kind in ("rapid", "linear") and m.line == 5)
    assert after.kind == "rapid" and after.thread is None
    assert _errors("G94 F400\nG63 Z-30 S100 M19\nM30\n") == [(2, "INT185")]


def test_multi_start_tapping_positions_the_spindle_before_each_start():
    # L7608-L7625: three starts of a 1 mm pitch (F150 / S150) at 0, 120 and 240 degrees
    r = _ok("G90 G01 X0 Y0 Z0 F150\nM19 S0\nG63 Z-50 S150\nG63 Z0 S-150\nM19 S120\nG63 Z-50 S150\n"
            "G63 Z0 S-150\nM19 S240\nG63 Z-50 S150\nG63 Z0 S-150\nM30\n")
    taps = _threads(r)
    assert [t.thread.pitch for t in taps] == [1.0] * 6
    assert [m.value for m in r.moves if m.kind == "aux" and m.function == "SPOS"] == [0.0, 120.0, 240.0]


def test_negative_s_only_under_g63():
    # L7568-L7569
    assert _errors("S-100 M03\nM30\n") == [(1, "INT027")]


def test_g63_under_g95_takes_f_as_the_pitch():
    # [CONSTRUCTION, spec 03 §F.13] with G95 F is already mm/rev: F0.5 at S200 -> pitch 0.5, 100 mm/min
    (t,) = _threads(_ok("G95 F0.5\nG63 Z-10 S200\nM30\n"))
    assert (t.thread.pitch, t.feed) == (0.5, pytest.approx(100.0))


@pytest.mark.parametrize("program", ["G63 Z-10 S200\nM30\n", "G93 F2\nG63 Z-10 S200\nM30\n",
                                     "F100\nG63 Z-10 K1 S200\nM30\n"])
def test_g63_errors(program):
    assert [c for _l, c in _errors(program)] == ["INT185"]


# ------------------------------------------------------------------ check and the card
def test_check_reports_nothing_unsupported_for_threads(tmp_path, capsys):
    from fagorcnc.cli import main

    f = tmp_path / "thread.nc"
    f.write_text(MILL.replace("M30\n", "G94 F400\nG01 G90 X30 Y30 Z0\nG63 Z-30 S100\nG63 Z0 S-100\nM30\n"))
    assert main(["check", "--format", "json", str(f)]) == 0
    out = capsys.readouterr().out
    assert "INT011" not in out and "INT078" not in out and '"verdict": "pass"' in out


def test_the_interpcnc_card_refuses_a_thread_before_the_start():
    seg = next(s for s in fagorcnc.simulate(MILL).segments(keep_profiles=False) if s.line == 3)
    why = InterpCncBackend.preflight(_Stub(), seg)
    assert why is not None and "spindle" in why


class _Stub:
    name = "interpcnc"


# ------------------------------------------------------------------ G95 feed per revolution in the planner
def test_g95_under_g96_follows_the_radius_along_a_facing_move():
    # seed 002 L5406-L5464: G96 S100 m/min -> rpm = 100000 / (2 pi r), limited to 3000 rpm by G192 below
    # r = 100000 / (2 pi 3000) = 5.305 mm; F0.2 mm/rev.  Facing X50 -> X5: time = integral of dr / (0.2 rpm(r))
    # = pi (50^2 - 5.305^2) / 20000 min + (5.305 - 5) / (0.2 * 3000) min = 0.38828 + 0.00051 min = 23.328 s
    # (the feed of the start alone, 0.2 * 318.3 = 63.7 mm/min, would make it 42.4 s)
    from fagorcnc.interp.records import record_time

    r = _ok("G192 S3000\nG0 X50 Z0\nG96 S100 M3\nG95 G1 X5 F0.2\nM30\n", LATHE)
    face = next(m for m in r.moves if m.kind == "linear")
    rc = 100000 / (2 * math.pi * 3000)
    expected = (math.pi * (50**2 - rc**2) / 20000 + (rc - 5) / 600) * 60
    assert record_time(r.machine, face) == pytest.approx(expected, rel=1e-3)
    planned = sum(s.duration for s in r.segments(keep_profiles=False) if s.kind == "motion" and s.line == 4)
    # the planner's parts run at the lowest feed over each (at most 2 % below it) plus the ramps
    assert expected <= planned <= expected * 1.03
    # the speed rises toward the centre, far above the start's 0.2 * 318.3 / 60 = 1.06 mm/s, never above
    # the G192 limit's 0.2 * 3000 / 60 = 10 mm/s
    speeds = [s.v0 for s in r.segments(keep_profiles=False) if s.kind == "motion" and s.line == 4]
    assert 5 * 1.061 < max(speeds) <= 10.0 + 1e-9


def test_g95_at_constant_speed_is_the_speed_times_f_in_the_planner():
    # S1000 G97, F0.15 mm/rev -> 150 mm/min; 30 mm take 12 s plus the ramps, also in check's cycle time
    r = _ok("S1000 M3\nG95 G1 Z-30 F0.15\nM30\n", LATHE)
    (m,) = [m for m in r.moves if m.kind == "linear"]
    assert m.feed == pytest.approx(150.0) and m.css is None
    assert 12.0 <= r.cycle_time < 12.1


def test_expand_names_the_thread_and_the_tap_as_their_motion_mode():
    from fagorcnc.commands.expand import _modes

    r = _ok("S100 M03\nG33 Z-10 K1\nF300\nG63 Z0 S-200\nM30\n")
    assert [_modes(t) for t in _threads(r)] == ["G33 G50 G40", "G63 G50 G40"]


def test_no_corner_curve_cuts_into_the_start_of_a_thread():
    # under G05 the G01 before the thread would be blended into it; the thread starts at its programmed
    # point (X30 Y30 Z0) at rest instead
    r = _ok("S100 M03\nG05 G01 G90 X30 Y30 Z0 F500\nG33 Z-30 K1.5\nG00 X40\nM30\n")
    segs = [s for s in r.segments(keep_profiles=False) if s.kind == "motion"]
    assert not any(s.blend for s in segs)
    approach = next(s for s in segs if s.line == 2)
    assert approach.v1 == 0.0 and list(approach.piece.end) == pytest.approx([30.0, 30.0, 0.0])


def test_passes_of_one_thread_at_different_speeds_are_warned():
    # L7392-L7400: all passes of a thread begin at the same speed (the CNC does not check: a warning here).
    # Two passes from Z0 with K1.5, the second at S120 instead of S100; a third at a new Z is another thread
    prog = ("S100 M03\nG00 X10 Z0\nG33 Z-30 K1.5\nG00 X12\nZ0\nX9.5\nS120\nG33 Z-30 K1.5\n"
            "G00 X12\nZ5\nX9.5\nG33 Z-30 K1.5\nM30\n")
    r = fagorcnc.simulate(prog, LATHE)
    assert r.ok and [(d.line, d.code) for d in r.diagnostics] == [(8, "INT188")]
    # the manual's three starts, all at S100: no warning
    assert not fagorcnc.simulate(prog.replace("S120\n", ""), LATHE).diagnostics
