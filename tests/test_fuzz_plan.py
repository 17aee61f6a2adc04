"""Fuzzing the planner: random paths, corner modes and machines plan without error, and the
sampled motion (1 ms) keeps every axis within its velocity, acceleration and jerk.

Programs are random sequences of rapid, linear and XY arc moves (short, so sampling stays
cheap) under a random corner mode (G50, G07, G05 with a random #ROUNDPAR, HSC with a random
tolerance and CORNER), random G130-G133 percentages, feed overrides, dwells and M functions,
on a machine with random per-axis limits.  A second generator changes the corner mode between
blocks (``#HSC ON``/``OFF`` with CONTERROR, FAST, SURFACE and CORNER, G05, G07, G50, G60, G61 and
the one-block G60/G07/G05/G61 written with a move) in every order, where the planner hands one
mode's corner to the next (issue 30 item 12 was a crash there).  Budgets come from the
Hypothesis profile (``tests/conftest.py``).
"""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import fagorcnc

PERIOD = 0.001
TOL = 1e-6

coord = st.floats(-20, 20, allow_nan=False).map(lambda v: round(v, 3))
small = st.floats(-0.3, 0.3, allow_nan=False).map(lambda v: round(v, 4))


@st.composite
def moves(draw):
    out = []
    for _ in range(draw(st.integers(1, 10))):
        kind = draw(st.sampled_from(["G1", "G1", "G1", "G0", "G2", "G3", "tiny", "dwell", "M"]))
        if kind == "tiny":   # CAM-like micro segments
            out += ["G91", f"G1 X{draw(small)} Y{draw(small)} Z{draw(small)}", "G90"]
        elif kind in ("G2", "G3"):
            # a half circle of radius r from the current point: centre r to the right
            r = draw(st.floats(0.2, 8.0, allow_nan=False))
            out += ["G91", f"{kind} X{2 * r:.4f} Y0 I{r:.4f} J0", "G90"]
        elif kind == "dwell":
            out.append(f"G4 K{draw(st.floats(0, 0.05, allow_nan=False)):.3f}")
        elif kind == "M":
            out.append(draw(st.sampled_from(["M8", "M9", "H5", "S1000 M3"])))
        else:
            out.append(f"{kind} X{draw(coord)} Y{draw(coord)} Z{draw(coord)}")
    return out


@st.composite
def programs(draw):
    mode = draw(st.sampled_from(["G50", "G07", "G05", "HSC"]))
    head = [f"G90 G1 F{draw(st.integers(50, 12000))}"]
    if mode == "G05":
        head.append(draw(st.sampled_from(["#ROUNDPAR [1, 0.01]", "#ROUNDPAR [1, 0.3]", "#ROUNDPAR [2, 50]",
                                          "#ROUNDPAR [3, 0.2, 0.5]", "#ROUNDPAR [4, 0.05]"])))
        head.append("G05")
    elif mode == "HSC":
        tol = draw(st.sampled_from([0.002, 0.01, 0.1]))
        corner = draw(st.integers(0, 180))
        head.append(draw(st.sampled_from([f"#HSC ON [CONTERROR {tol}, CORNER {corner}]", f"#HSC ON [SURFACE, E{tol}]",
                                          f"#HSC ON [FAST {draw(st.integers(10, 100))}, E{tol}]"])))
    else:
        head.append(mode)
    if draw(st.booleans()):
        head.append(f"G131 {draw(st.integers(5, 100))}")
    if draw(st.booleans()):
        head.append(f"G133 {draw(st.integers(5, 100))}")
    body = draw(moves())
    return "\n".join([*head, *body, "M30"]) + "\n"


@st.composite
def machines(draw):
    axes = {}
    for a in "XYZ":
        axes[a] = {"max_velocity": float(draw(st.integers(600, 30000))),
                   "max_acceleration": float(draw(st.integers(50, 5000))),
                   "max_jerk": float(draw(st.integers(500, 200000))),
                   "min_limit": -1000.0, "max_limit": 1000.0}
    return {"axes": axes, "planner": {"feed_override": float(draw(st.integers(10, 150)))}}


@settings(suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(programs(), machines())
def test_random_paths_plan_within_the_axis_limits(program, machine):
    check_plan(program, machine)


def check_plan(program: str, machine: dict | None) -> None:
    r = fagorcnc.simulate(program, machine)
    assert r.ok, (program, [str(d) for d in r.diagnostics])
    assert np.isfinite(r.cycle_time) and r.cycle_time >= 0
    if not r.moves:
        return
    tr = r.trajectory(PERIOD)
    for a, ax in r.machine.axes.items():
        p = tr.position[a]
        v = np.diff(p) / PERIOD
        acc = np.diff(v) / PERIOD
        jerk = np.diff(acc) / PERIOD
        assert np.abs(v).max(initial=0) <= ax.max_velocity / 60 * (1 + TOL), (program, a)
        assert np.abs(acc).max(initial=0) <= ax.max_acceleration * (1 + TOL), (program, a)
        assert np.abs(jerk).max(initial=0) <= ax.max_jerk * (1 + TOL) + 1e-3, (program, a)
    # the motion ends where the program ends
    end = r.moves[-1].end
    for a in r.machine.axes:
        assert tr.position[a][-1] == np.float64(end.get(a, 0.0)) or abs(tr.position[a][-1] - end[a]) < 1e-9


# ---------------------------------------------------------------- corner modes changing between blocks
HSC_ON = ["#HSC ON [CONTERROR 0.01, CORNER 150]", "#HSC ON [FAST, CORNER 130]", "#HSC ON [SURFACE, E0.05]",
          "#HSC ON [CONTERROR 0.002, CORNER 0]", "#HSC ON [FAST 50, CORNER 180]", "#HSC ON"]
MODAL = ["G05", "G07", "G50"]   # the corner group: each cancels HSC (seed 002 L13659)
OTHER = ["#HSC OFF", "#ROUNDPAR [1, 0.05]", "#ROUNDPAR [4, 0.02]"]
ONE_BLOCK = ["G60", "G61"]      # this block only, HSC or not around it (L8018, L8107)


@st.composite
def mode_change_programs(draw):
    """Lines and arcs with corner modes changing between blocks, and one-block modes within them, in
    any order (an #HSC ON while HSC is on is preceded by what cancels it: #HSC OFF, G05, G07 or G50)."""
    out = [f"G90 G17 G71 G94 G01 X0 Y0 F{draw(st.integers(200, 6000))}"]
    hsc = False
    for _ in range(draw(st.integers(2, 12))):
        if draw(st.integers(0, 2)) == 0:
            change = draw(st.sampled_from([*HSC_ON, *HSC_ON, *MODAL, *OTHER]))
            if change.startswith("#HSC ON"):
                if hsc:
                    out.append(draw(st.sampled_from(["#HSC OFF", *MODAL])))
                hsc = True
            elif change in MODAL or change == "#HSC OFF":
                hsc = False
            out.append(change)
        move = draw(st.sampled_from(["line", "line", "line", "arc", "tiny", "rapid"]))
        prefix = draw(st.sampled_from(["", "", "", *ONE_BLOCK])) + " " if move != "rapid" else ""
        if move == "arc":
            r = draw(st.floats(0.5, 6.0, allow_nan=False))
            out += ["G91", f"{prefix}G{draw(st.sampled_from([2, 3]))} X{2 * r:.4f} Y0 I{r:.4f} J0", "G90 G01"]
        elif move == "tiny":
            out += ["G91", f"{prefix}G01 X{draw(small)} Y{draw(small)}", "G90"]
        elif move == "rapid":
            out += [f"G00 X{draw(coord)} Y{draw(coord)}", "G01"]
        else:
            out.append(f"{prefix}X{draw(coord)} Y{draw(coord)}")
    return "\n".join([*out, "M30"]) + "\n"


ISSUE_30_ITEM_12 = ("G90 G17 G71 G94 G01 X0 Y0 F2000\n#HSC ON [CONTERROR 0.01, CORNER 150]\nX40\nG60 X45 Y1\nG50\n"
                    "#HSC ON [FAST, CORNER 130]\nG01 Y40\nM30\n")


@settings(max_examples=max(30, settings.default.max_examples // 3),
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(mode_change_programs())
@example(ISSUE_30_ITEM_12)
def test_corner_mode_changes_between_blocks_plan_within_the_limits(program):
    check_plan(program, None)
    dry = fagorcnc.dry_run(program)   # the streamed planner of fagorcnc check, on the same program
    assert dry.ok, (program, [str(d) for d in dry.diagnostics])
