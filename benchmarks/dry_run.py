"""Where a dry run spends its time: interpreter, planner, simulator back-end.

Run::

    python benchmarks/dry_run.py [--blocks 20000] [--repeat 3]

For the 3D finishing raster of ``plan_speed.py`` in each corner mode, and its contour of arcs
under G05 and HSC, it runs
the pipeline of ``fagorcnc run part.nc`` (program file read lazily, interpreted,
planned, sent to the embedded simulator, under the run's collector and allocator settings)
and splits its time by stage: the time spent getting the next record from the
interpreter, sending segments to the back-end, and the rest, which is the
planner.  A stage whose share is the largest is the dry run's bottleneck.  The last column,
seconds of planned motion per second of planning, is how far ahead of a real machine the
planner stays when it streams to one.
Best of ``--repeat`` runs (the machine is shared).
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from collections.abc import Iterator

from instructions import SHAPES
from plan_speed import contour, raster

PROGRAMS = {"raster": raster, "contour": contour}


class Timed:
    """An iterator wrapper adding the time spent inside ``next()`` to ``seconds``."""

    def __init__(self, source) -> None:
        self.source = iter(source)
        self.seconds = 0.0
        self.count = 0

    def __iter__(self) -> Iterator:
        return self

    def __next__(self):
        t0 = time.perf_counter()
        try:
            item = next(self.source)
        finally:
            self.seconds += time.perf_counter() - t0
        self.count += 1
        return item


def dry_run(path: str) -> dict:
    import fagorcnc
    from fagorcnc.backends.sim import SimulatorBackend
    from fagorcnc.plan import Planner
    from fagorcnc.runtime import fewer_collections, keep_freed_memory
    from fagorcnc.simulate import interpret

    keep_freed_memory()   # as the fagorcnc command does
    machine = fagorcnc.load_machine(None)
    with fewer_collections():
        t0 = time.perf_counter()
        records = Timed(interpret(path, machine))
        backend = SimulatorBackend(machine, keep_segments=False)   # as the fagorcnc command runs it
        backend.open()
        send = 0.0
        segments = 0
        for seg in Planner(machine).segments(records):
            t1 = time.perf_counter()
            backend.send(seg)
            send += time.perf_counter() - t1
            segments += 1
        backend.finish()
        total = time.perf_counter() - t0
    return {"records": records.count, "segments": segments, "total": total, "interpret": records.seconds,
            "backend": send, "plan": total - records.seconds - send, "cycle": backend.cycle_time}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--blocks", type=int, default=20_000)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print("| program | mode | records | dry run | interpreter | planner | back-end | interpreter (records/s) "
          "| planner (records/s) | planner / interpreter time | planned motion per second of planning |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for shape, mode in SHAPES:
            path = os.path.join(tmp, f"{shape}_{mode}.nc")
            with open(path, "w", encoding="utf-8") as f:
                f.writelines(line + "\n" for line in PROGRAMS[shape](args.blocks, mode))
            r = min((dry_run(path) for _ in range(args.repeat)), key=lambda x: x["total"])
            n = r["records"]
            print(f"| {shape} | {mode} | {n} | {r['total']:.2f} s "
                  f"| {r['interpret']:.2f} s ({r['interpret'] / r['total']:.0%}) "
                  f"| {r['plan']:.2f} s ({r['plan'] / r['total']:.0%}) "
                  f"| {r['backend']:.2f} s ({r['backend'] / r['total']:.0%}) | {n / r['interpret']:,.0f} "
                  f"| {n / r['plan']:,.0f} | {r['plan'] / r['interpret']:.2f} | {r['cycle'] / r['plan']:,.0f} s |")


if __name__ == "__main__":
    main()
