"""The arcs a batch of corners at arcs trims at both ends (fagorcnc.plan.shortcuts.arc_trims,
cut_arc): their bounds and limits made with the batch are the very floats of each trimmed arc's own,
and the planner plans the same with them."""

from __future__ import annotations

import pytest
from test_corner_batch import _contour, _corners
from test_plan_batches import _plan_floats

from fagorcnc.plan.geometry import ArcPiece, arc_bound_rows


def test_bound_rows_of_stretches_are_each_stretchs_bounds():
    """arc_bound_rows of stretches of arcs (helices and spirals in the three planes, both turning
    ways; stretches of stretches, an end kept, a whole arc as a stretch of itself) from their start
    angle, radius and length is what each stretch's bound_lists gives, to the bit."""
    ps, qs = _corners(17, 150)
    arcs = [p for p in (*ps, *qs) if isinstance(p, ArcPiece)]
    family, stretches = [], []
    for a in arcs:
        half = a.sub(0.25 * a.length, a.length)
        for s in (a.sub(0.0, a.length), a.sub(0.1 * a.length, 0.7 * a.length), a.sub(0.0, 0.3 * a.length),
                  half, half.sub(0.0, 0.5 * half.length)):
            family.append(a)
            stretches.append(s)
    rows = arc_bound_rows(family, [s.theta0 for s in stretches], [s.r0 for s in stretches],
                          [s.length for s in stretches])
    assert len(stretches) >= 400
    for i, s in enumerate(stretches):
        assert [r[i].tolist() for r in rows] == list(s.bound_lists())


@pytest.mark.parametrize("plane", ["G17", "G18", "G19"])
@pytest.mark.parametrize("mode", ["HSC", "#HSC ON [FAST 80, E0.02, CORNER 165]", "#ROUNDPAR [1, 0.01]",
                                  "#ROUNDPAR [4, 0.005]"])
def test_arcs_trimmed_with_a_batch_plan_as_the_general_path(monkeypatch, mode, plane):
    """Arcs given their stretch's bounds and limits by the batch that trims them (cut_arc) plan to the
    very floats of arcs that make their own (Span.refresh), on a contour with HSC splines between its
    lines, a feed change, a helix, a long arc in parts and (CORNER 165) sharp edges: most arcs take
    the batch's, and an arc whose start the batch did not trim as it took it makes its own."""
    import fagorcnc
    from fagorcnc.plan import junctions
    from fagorcnc.plan.span import Span
    from fagorcnc.simulate import Run

    machine = fagorcnc.load_machine(None)
    program = _contour(mode, plane)
    if mode.startswith("#HSC ON [FAST"):
        program = [mode if line.startswith("#HSC") else line for line in _contour("HSC", plane)]
    records = list(Run(iter(program), "<contour>", machine))
    refreshed, cuts = [], []
    refresh, cut_arc = Span.refresh, junctions.cut_arc

    def counted_refresh(span):
        refreshed.append(span)
        refresh(span)

    def counted_cut(span, keep, known):
        before = len(refreshed)
        cut_arc(span, keep, known)
        cuts.append(len(refreshed) == before)

    monkeypatch.setattr(Span, "refresh", counted_refresh)
    monkeypatch.setattr(junctions, "cut_arc", counted_cut)
    quick = _plan_floats(machine, records)
    if "CORNER" in mode:   # sharp edges stop most corners: the arcs after them are trimmed at one end only
        assert 1 <= sum(cuts) < len(cuts)
    else:
        assert sum(cuts) >= 8
    monkeypatch.setattr(junctions, "arc_trims", lambda *args: ([], [], [], [], [], []))
    cuts.clear()
    general = _plan_floats(machine, records)
    assert not cuts and quick == general
