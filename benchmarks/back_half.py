"""The back half of ``fagorcnc check`` alone: planning, the PLN100 envelope and check's summary, on
records interpreted beforehand, against another checkout in the same run.

Run from the repository root::

    python benchmarks/back_half.py --tree OLD [--iso 20000] [--blocks 20000] [--rounds 3]

For each program of ``throughput.py`` (ISO, the rasters, the contours), a fresh process per tree
interprets the program into a list of records (not timed), then plans them, runs every segment
through the envelope and every record through check's summary (:class:`MoveSummary`), ``--rounds``
times, and prints the least CPU time of those rounds (``time.process_time``) and the cycle time.
The trees take turns, so a change of load on a shared machine falls on both alike; the table gives
old ÷ new (above 1: this tree is faster) and whether the cycle times are identical.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from plan_speed import contour, raster
from throughput import iso, write

ROOT = Path(__file__).resolve().parents[1]

CHILD = """
import gc, json, sys, time
import fagorcnc
from fagorcnc.commands.extents import MoveSummary
from fagorcnc.config.machine import load_machine
from fagorcnc.interp.interpreter import Interpreter
from fagorcnc.interp.source import stream_program
from fagorcnc.plan import Planner
from fagorcnc.plan.envelope import Envelope
from fagorcnc.runtime import fewer_collections, keep_freed_memory

keep_freed_memory()
mach = load_machine(None)
with open(sys.argv[1], encoding="utf-8") as f, fewer_collections():
    program, body = stream_program(f, sys.argv[1], mach.compat)
    interp = Interpreter(program, mach, stream=body)
    records = list(interp.run())
best, cycle = None, None
for _ in range(int(sys.argv[2])):
    with fewer_collections():
        gc.collect()
        t0 = time.process_time()
        summary = MoveSummary()
        for rec in records:
            summary.add(rec, interp)
        envelope = Envelope(mach)
        clock = 0.0
        for seg in Planner(mach).segments(records):
            clock = max(clock, seg.t0 + seg.duration)
            envelope.add(seg)
        seconds = time.process_time() - t0
    best = seconds if best is None else min(best, seconds)
    assert cycle is None or cycle == clock
    cycle = clock
print(json.dumps({"package": fagorcnc.__file__, "records": len(records), "seconds": best, "cycle": cycle}))
"""


def run(path: Path, rounds: int, tree: str | None) -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(Path(tree).resolve()) if tree is not None else str(ROOT)
    done = subprocess.run([sys.executable, "-P", "-c", CHILD, str(path), str(rounds)], capture_output=True,
                          text=True, env=env)
    if done.returncode:
        raise RuntimeError(f"child failed ({done.returncode}): {done.stderr.strip()[-2000:]}")
    result = json.loads(done.stdout)
    if not result["package"].startswith(env["PYTHONPATH"] + os.sep):
        raise RuntimeError(f"measured {result['package']}, not the checkout {env['PYTHONPATH']}")
    return result


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tree", required=True, help="the other checkout whose fagorcnc package to measure")
    ap.add_argument("--iso", type=int, default=20_000, help="blocks of the ISO program")
    ap.add_argument("--blocks", type=int, default=20_000, help="blocks of the rasters and the contours")
    ap.add_argument("--rounds", type=int, default=3, help="timed rounds per process (the least counts)")
    ap.add_argument("--turns", type=int, default=2, help="processes per tree, in turn (the least counts)")
    ap.add_argument("--only", nargs="*", help="program names to run (default: all)")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        programs = [("iso", Path(folder) / "iso.nc", iso(args.iso))]
        for mode in ("G50", "G05", "HSC"):
            programs.append((f"raster {mode}", Path(folder) / f"raster{mode}.nc", raster(args.blocks, mode)))
        for mode in ("HSC", "G05"):
            programs.append((f"contour {mode}", Path(folder) / f"contour{mode}.nc", contour(args.blocks, mode)))
        if args.only:
            programs = [p for p in programs if p[0] in args.only]
        for _name, path, lines in programs:
            write(path, lines)
        print(f"this tree: {ROOT}; old: {args.tree}; back half (plan + envelope + summary), CPU, "
              f"least of {args.rounds} rounds x {args.turns} processes")
        print("| program | records | old | new | old ÷ new | cycle time (new) | identical |")
        print("|---|---:|---:|---:|---:|---:|---|")
        for name, path, _ in programs:
            new = old = None
            for _ in range(args.turns):
                o = run(path, args.rounds, args.tree)
                n = run(path, args.rounds, None)
                old = o if old is None or o["seconds"] < old["seconds"] else old
                new = n if new is None or n["seconds"] < new["seconds"] else new
            same = "yes" if repr(old["cycle"]) == repr(new["cycle"]) else f"NO (old {old['cycle']!r})"
            print(f"| {name} | {new['records']} | {old['seconds']:.3f} s | {new['seconds']:.3f} s "
                  f"| {old['seconds'] / new['seconds']:.2f} | {new['cycle']!r} s | {same} |", flush=True)


if __name__ == "__main__":
    main()
