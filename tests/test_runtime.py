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


_CHURN = """
import resource, sys
import numpy as np
if sys.argv[1] == "keep":
    from fagorcnc.runtime import keep_freed_memory
    assert keep_freed_memory()
def churn():   # three 1.6 MB arrays made and freed together, as the planner's corner batches do
    a = np.ones(200_000); b = a * 2.0; c = a + b
    return float(c[-1])
churn()
before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
for _ in range(20):
    churn()
print(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before)
"""


def test_freed_memory_is_kept_for_reuse():
    """With keep_freed_memory() (glibc), arrays of a few megabytes made and freed again and again
    reuse the same pages: no page faults after the first round (without it, every round faults
    its pages in again)."""
    import platform
    import subprocess
    import sys

    from fagorcnc.runtime import keep_freed_memory

    if platform.libc_ver()[0] != "glibc":
        assert keep_freed_memory() is False   # nothing to set elsewhere
        return

    def faults(mode: str) -> int:
        out = subprocess.run([sys.executable, "-c", _CHURN, mode], capture_output=True, text=True, check=True)
        return int(out.stdout)

    assert keep_freed_memory() is True
    kept, plain = faults("keep"), faults("plain")
    assert kept < 100
    # every round faults in again without it: at least once each (one fault per huge page where
    # the system maps them), 1.2k times each here
    assert plain >= 20 and plain > 10 * max(kept, 1)


_COMMAND = """
import gc, sys
from fagorcnc.cli import command
frozen = []
gc.callbacks.append(lambda phase, info: frozen.append(gc.get_freeze_count()) if phase == "start" else None)
sys.argv = ["fagorcnc", "check", sys.argv[1]]
status = command()
print(status, min(frozen, default=-1))
"""


def test_the_command_spares_the_collector_its_imports(tmp_path):
    """command() (the fagorcnc process): the check's status and output as main() gives them, every collection
    during the command with the imports' objects out of its reach, and nothing said at exit (a compiled
    extension's objects frozen past it would be reported as leaked)."""
    import subprocess
    import sys

    program = tmp_path / "p.nc"
    program.write_text("G1 X10 F1000\nG2 X20 Y0 I5 J0\nM30\n")
    out = subprocess.run([sys.executable, "-c", _COMMAND, str(program)], capture_output=True, text=True, check=True)
    status, frozen_during = (int(v) for v in out.stdout.splitlines()[-1].split())
    assert status == 0 and out.stderr == ""
    assert frozen_during > 10_000   # the imports' objects (some sixty thousand), frozen before the command ran
    plain = subprocess.run([sys.executable, "-c", "import sys; from fagorcnc.cli import main; sys.exit(main())",
                            "check", str(program)], capture_output=True, text=True, check=True)
    assert out.stdout.splitlines()[:-1] == plain.stdout.splitlines()


def test_spare_collector_freezes_what_is_alive():
    from fagorcnc.runtime import spare_collector

    kept = [[]]   # a tracked object
    try:
        spare_collector()
        assert gc.get_freeze_count() > 0 and not any(o is kept[0] for o in gc.get_objects())
    finally:
        gc.unfreeze()
    assert any(o is kept[0] for o in gc.get_objects())
