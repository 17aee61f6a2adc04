"""Fuzzing the planner: random paths, corner modes and machines plan without error, and the
sampled motion (1 ms) keeps every axis within its velocity, acceleration and jerk.

Programs are random sequences of rapid, linear and XY arc moves (short, so sampling stays
cheap) under a random corner mode (G50, G07, G05 with a random #ROUNDPAR, HSC with a random
tolerance and CORNER), random G130-G133 percentages, feed overrides, dwells and M functions,
on a machine with random per-axis limits.  Budgets come from the Hypothesis profile
(``tests/conftest.py``).
"""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
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
