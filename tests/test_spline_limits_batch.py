"""HSC spline curves take the limits computed with their batch (plan/junctions.py
``_spline_batch_limits``): the same numbers as each span's own, so the same plan."""

from __future__ import annotations

import math

import numpy as np
import pytest

import fagorcnc
from fagorcnc.plan import Planner
from fagorcnc.plan.limits import curve_limits
from fagorcnc.simulate import Run


def _raster(fast: bool, feeds: bool) -> list[str]:
    rows = []
    for r in range(4):   # a 3D finishing raster (0.5 mm steps), optionally a feed change at every block
        xs = [i * 0.5 for i in range(81)]
        for j, x in enumerate(xs[::-1] if r % 2 else xs):
            f = f" F{2000 + 1000 * (j % 3)}" if feeds else ""
            rows.append(f"X{x:.4f} Y{r:.4f} Z{2 * np.sin(x / 7) * np.cos(r / 9):.4f}{f}")
    hsc = "#HSC ON [FAST 80, E0.01]" if fast else "#HSC ON [CONTERROR 0.01]"
    return ["G90 G1 X0 Y0 Z0 F3000", hsc, *rows, "M30"]


@pytest.mark.parametrize(("fast", "feeds"), [(False, False), (True, True)])
def test_spline_spans_take_batched_limits_equal_to_their_own(fast, feeds):
    machine = fagorcnc.load_machine(None)
    records = list(Run(iter(_raster(fast, feeds)), "<raster>", machine))
    planner = Planner(machine)
    used = []
    original = planner._spline_limit

    def recorded(blend, prev, feed):
        found = original(blend, prev, feed)
        if found is not None:
            # the span's own limits, as Span.refresh makes them (a blend is arc-length: speed factor 1)
            own = curve_limits(*blend.bound_lists(), prev.lim, feed / blend.speed_factor(), prev.path_acc,
                               prev.path_jerk)
            assert found == own   # to the bit
        used.append(found is not None)
        return found

    planner._spline_limit = recorded
    batched = [(s.t0, s.duration, s.line) for s in planner.segments(iter(records))]
    assert sum(used) >= 0.9 * len(used) > 250   # nearly every spline corner takes them

    alone_planner = Planner(machine)
    alone_planner._spline_limit = lambda blend, prev, feed: None   # every span makes its own
    alone = [(s.t0, s.duration, s.line) for s in alone_planner.segments(iter(records))]
    assert alone == batched   # the same plan, to the last digit


def test_the_fast_share_is_in_the_batched_feed():
    # #HSC FAST 80: a spline between two F3000 lines (50 mm/s) is planned at 0.8 x 50 = 40 mm/s at most
    machine = fagorcnc.load_machine(None)
    records = list(Run(iter(_raster(True, False)), "<raster>", machine))
    planner = Planner(machine)
    caps = []
    original = planner._spline_limit

    def recorded(blend, prev, feed):
        found = original(blend, prev, feed)
        if found is not None:
            caps.append((feed, found[0]))
        return found

    planner._spline_limit = recorded
    for _ in planner.segments(iter(records)):
        pass
    assert caps and all(math.isclose(f, 40.0) and vc <= 40.0 for f, vc in caps)
