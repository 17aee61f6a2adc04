"""The dry run's collector setting: raised for the run, put back after, nested runs included."""

from __future__ import annotations

import gc

import pytest

import fagorcnc
from fagorcnc.runtime import OLDER_THRESHOLDS, YOUNG_THRESHOLD, fewer_collections


@pytest.fixture
def thresholds():
    saved = gc.get_threshold()
    yield
    gc.set_threshold(*saved)


def test_raised_inside_and_restored_after(thresholds):
    gc.set_threshold(700, 10, 10)
    with fewer_collections():
        assert gc.get_threshold() == (YOUNG_THRESHOLD, *OLDER_THRESHOLDS)
        with fewer_collections():
            assert gc.get_threshold()[0] == YOUNG_THRESHOLD
        assert gc.get_threshold()[0] == YOUNG_THRESHOLD   # the inner end does not restore early
    assert gc.get_threshold() == (700, 10, 10)


def test_never_lowers_a_higher_setting_nor_turns_collection_back_on(thresholds):
    gc.set_threshold(100_000, 50, 500)
    with fewer_collections():
        assert gc.get_threshold() == (100_000, 50, 500)
    gc.set_threshold(0, 10, 10)
    with fewer_collections():
        assert gc.get_threshold()[0] == 0
    assert gc.get_threshold() == (0, 10, 10)


def test_restored_when_the_run_fails(thresholds):
    gc.set_threshold(700, 10, 10)
    with pytest.raises(RuntimeError), fewer_collections():
        raise RuntimeError("stop")
    assert gc.get_threshold() == (700, 10, 10)


def test_simulate_and_run_leave_the_setting_as_they_found_it(thresholds):
    gc.set_threshold(700, 10, 10)
    seen: list[tuple[int, int, int]] = []
    result = fagorcnc.simulate("G1 X10 F1000\nM30\n")
    assert result.ok
    report = fagorcnc.run("G1 X10 F1000\nM30\n", progress=lambda *_: seen.append(gc.get_threshold()))
    assert report.ok and seen and all(t[0] == YOUNG_THRESHOLD for t in seen)
    assert gc.get_threshold() == (700, 10, 10)
