"""Issue 27's figures in one run: ``fagorcnc check`` throughput per program kind against
gcodeparser's parse-only rate, the memory of ``simulate()`` per block, and the memory of
``check`` on a 1 000 000-block raster.

Run from the repository root::

    python benchmarks/throughput.py [--iso 60000] [--blocks 20000] [--tree OLD] [--big 1000000]
    python benchmarks/throughput.py --tree OLD --simulate 0 --rounds 3
    python benchmarks/throughput.py --only-simulate --tree OLD --rounds 3

Every figure is one fresh process, timed in **CPU time of the whole process** (user + system,
imports included: ``os.wait4``), so the load of a shared machine counts less than in wall
time.  Programs (generated, deterministic):

* ``iso``: the CAM-style program of ``parse_speed.py`` (G0/G1/G2/G3 X Y Z I J F, 3-4 decimals),
  ``--iso`` blocks; gcodeparser (``bench`` extra) parses the same file, parse only
  (``list(parse_gcode_lines(text))`` after reading it);
* ``raster G50`` / ``G05`` / ``HSC``: the 3D finishing raster of ``plan_speed.py``;
* ``contour HSC`` / ``G05``: the freeform contour of arcs of ``plan_speed.py``, its passes the same
  XY blocks at every depth (the planner takes their corners back from its memo after the first);
* ``tapered HSC``: the same contour with every pass 0.02 mm wider (no corner repeats).

``--tree OLD`` measures the same programs with the ``fagorcnc`` package of another checkout in
the same run (e.g. ``git archive REV | tar -x -C /tmp/old``) and prints the ratio old ÷ new
(above 1: this tree is faster).  ``--simulate N`` (default 200 000) is the raster size for the
memory of ``simulate()``: (peak RSS − RSS after the imports) ÷ blocks, and the CPU time of the
``simulate()`` call; ``--only-simulate`` measures only that.  ``--rounds K`` runs every measure K times
(this tree and ``--tree`` in turn) and keeps the best CPU time of each, gcodeparser's included: on a
shared machine a run only ever gets slower, so the best of a few is the figure that repeats.
``--big N`` (default 0 = skip) checks an N-block G05 raster and prints its peak RSS.

Bytecode: every measured ``fagorcnc`` package is first compiled to its ``__pycache__``
(``compileall``; gitignored), as ``pip install`` does for an installed package and as Python does
on a first import unless ``PYTHONDONTWRITEBYTECODE`` is set.  Without that, in an environment
that sets it (this machine does), each process would compile all of fagorcnc's modules from
source, about 0.25 s of its CPU, while gcodeparser and the other peers, installed by pip, load
their bytecode.  ``--bytecode source`` measures that case instead (no compile step; whatever
``__pycache__`` holds is still read).
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

from parse_speed import program_lines
from plan_speed import contour, raster, tapered

ROOT = Path(__file__).resolve().parents[1]   # the checkout whose fagorcnc "this tree" measures

CHECK = """
import json, resource, sys
from fagorcnc.commands.check import check_file
from fagorcnc.runtime import keep_freed_memory
keep_freed_memory()   # as the fagorcnc command does
report = check_file(sys.argv[1])
assert report.verdict() == "pass", [str(d) for d in report.diagnostics][:5]
import fagorcnc
print(json.dumps({"package": fagorcnc.__file__, "moves": report.moves, "cycle": report.cycle_time,
                  "rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""

GCODEPARSER = """
import json, resource, sys
from gcodeparser import parse_gcode_lines
with open(sys.argv[1], encoding="utf-8") as f:
    text = f.read()
lines = list(parse_gcode_lines(text))
print(json.dumps({"moves": len(lines), "cycle": 0.0,
                  "rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""

SIMULATE = """
import gc, json, resource, sys, time
import fagorcnc

def rss():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * resource.getpagesize()

base = rss()
t0 = time.process_time()
result = fagorcnc.simulate(sys.argv[1])
seconds = time.process_time() - t0
assert result.ok, [str(d) for d in result.diagnostics][:5]
gc.collect()
kept = rss() - base
package = fagorcnc.__file__
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 - base
print(json.dumps({"package": package, "moves": len(result.moves), "cycle": result.cycle_time, "kept": kept,
                  "peak": peak, "seconds": seconds}))
"""


def compile_tree(tree: str | None) -> None:
    """Compile the ``fagorcnc`` package of ``tree`` (None: this checkout) to its ``__pycache__``."""
    import compileall

    package = (Path(tree).resolve() if tree is not None else ROOT) / "fagorcnc"
    if not compileall.compile_dir(str(package), quiet=1):
        raise RuntimeError(f"could not compile {package}")


def run_timed(code: str, path: Path, tree: str | None) -> dict:
    """As :func:`run`, with the child's CPU time from the resource usage of the children."""
    import resource

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    env = dict(os.environ)
    # -P: without it "-c" puts the working directory first on sys.path, ahead of PYTHONPATH, and a
    # run from a checkout would measure that checkout whatever --tree says
    env["PYTHONPATH"] = str(Path(tree).resolve()) if tree is not None else str(ROOT)
    done = subprocess.run([sys.executable, "-P", "-c", code, str(path)], capture_output=True, text=True, env=env)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode:
        raise RuntimeError(f"child failed ({done.returncode}): {done.stderr.strip()[-2000:]}")
    result = json.loads(done.stdout)
    if "package" in result and not result["package"].startswith(env["PYTHONPATH"] + os.sep):
        raise RuntimeError(f"measured {result['package']}, not the checkout {env['PYTHONPATH']}")
    result["cpu"] = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return result


def iso(blocks: int):
    """The program of ``parse_speed.py`` with a feed programmed before its first move (it may start
    with an arc, which needs one)."""
    lines = program_lines(blocks)
    yield next(lines)   # %BENCH
    yield "G90 G0 X0 Y0 Z5 F1000"
    yield from lines


def write(path: Path, lines) -> int:
    n = 0
    with open(path, "w", encoding="utf-8", newline="\n") as f:
        for line in lines:
            f.write(line)
            f.write("\n")
            n += 1
    return n


def best_of(rounds: int, code: str, path: Path, tree: str | None) -> dict:
    """:func:`run_timed` ``rounds`` times; the result of the run with the least CPU time."""
    return min((run_timed(code, path, tree) for _ in range(rounds)), key=lambda r: r["cpu"])


def check_table(args, programs: list, sizes: dict) -> None:
    """The table of check throughput against gcodeparser's parse-only rate (each CPU time the best of
    ``--rounds`` runs, gcodeparser's too: on a shared machine a run only ever gets slower)."""
    peer = best_of(args.rounds, GCODEPARSER, programs[0][1], None)
    peer_rate = sizes["iso"] / peer["cpu"]
    print(f"gcodeparser parse only, iso ({sizes['iso']} lines): {peer['cpu']:.2f} s CPU, {peer_rate:,.0f} lines/s"
          f" (best of {args.rounds})")
    head = "| program | lines | check CPU | lines/s | ÷ gcodeparser | cycle time | peak RSS |"
    if args.tree:
        head += " old CPU | old ÷ new | old cycle time |"
    print()
    print(head)
    print("|" + "---|" * (head.count("|") - 1))
    for name, path, _ in programs:
        r = o = None
        for _ in range(args.rounds):   # this tree and the old one in turn, the load shared alike
            x = run_timed(CHECK, path, None)
            r = x if r is None or x["cpu"] < r["cpu"] else r
            if args.tree:
                y = run_timed(CHECK, path, args.tree)
                o = y if o is None or y["cpu"] < o["cpu"] else o
        row = (f"| {name} | {sizes[name]} | {r['cpu']:.2f} s | {sizes[name] / r['cpu']:,.0f} "
               f"| {sizes[name] / r['cpu'] / peer_rate:.3f} | {r['cycle']:.4f} s | {r['rss_mib']:.1f} MiB |")
        if args.tree:
            row += f" {o['cpu']:.2f} s | {o['cpu'] / r['cpu']:.2f} | {o['cycle']:.4f} s |"
        print(row, flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--iso", type=int, default=60_000, help="blocks of the ISO program")
    ap.add_argument("--blocks", type=int, default=20_000, help="blocks of the rasters and the contour")
    ap.add_argument("--tree", help="another checkout whose fagorcnc package to measure in the same run")
    ap.add_argument("--simulate", type=int, default=200_000, help="raster blocks for simulate()'s memory (0: skip)")
    ap.add_argument("--big", type=int, default=0, help="blocks of the G05 raster whose check memory is measured")
    ap.add_argument("--only-simulate", action="store_true",
                    help="only simulate()'s memory (and its CPU time): no check program, no gcodeparser")
    ap.add_argument("--rounds", type=int, default=1,
                    help="runs of every measure (each tree in turn): the best CPU time")
    ap.add_argument("--bytecode", choices=("cached", "source"), default="cached",
                    help="cached: compile each measured fagorcnc package first (as installed); source: do not")
    args = ap.parse_args()
    trees = [("this tree", None)] + ([("old", args.tree)] if args.tree else [])
    if args.bytecode == "cached":
        for _label, tree in trees:
            compile_tree(tree)
    with tempfile.TemporaryDirectory() as folder:
        programs = [("iso", Path(folder) / "iso.nc", iso(args.iso))]
        for mode in ("G50", "G05", "HSC"):
            programs.append((f"raster {mode}", Path(folder) / f"raster{mode}.nc", raster(args.blocks, mode)))
        for mode in ("HSC", "G05"):
            programs.append((f"contour {mode}", Path(folder) / f"contour{mode}.nc", contour(args.blocks, mode)))
        programs.append(("tapered HSC", Path(folder) / "taperedHSC.nc", tapered(args.blocks, "HSC")))
        if args.only_simulate:
            programs = []
        sizes = {name: write(path, lines) for name, path, lines in programs}

        print(f"this tree: {ROOT}; old: {args.tree}; fagorcnc bytecode: {args.bytecode}")
        if programs:
            check_table(args, programs, sizes)

        if args.simulate:
            path = Path(folder) / "simulate.nc"
            write(path, raster(args.simulate, "G50"))
            print()
            print("| simulate() | blocks | moves | kept after the run | peak above imports | per block (peak) "
                  "| simulate() CPU |")
            print("|---|---:|---:|---:|---:|---:|---:|")
            best: dict[str, float] = {}
            for _ in range(args.rounds):   # this tree and the old one in turn, the load shared alike
                for label, tree in trees:
                    r = run_timed(SIMULATE, path, tree)
                    best[label] = min(best.get(label, r["seconds"]), r["seconds"])
                    print(f"| {label} | {args.simulate} | {r['moves']} | {r['kept'] / 2**20:.1f} MiB "
                          f"| {r['peak'] / 2**20:.1f} MiB | {r['peak'] / args.simulate / 1024:.2f} KiB "
                          f"| {r['seconds']:.2f} s |", flush=True)
            if args.tree:
                print(f"\nsimulate() CPU, best of {args.rounds}: this tree {best['this tree']:.2f} s, old "
                      f"{best['old']:.2f} s (new / old {best['this tree'] / best['old']:.3f})")
            path.unlink()

        if args.big:
            path = Path(folder) / "big.nc"
            write(path, raster(args.big, "G05"))
            print()
            print("| check of a big raster G05 | blocks | CPU | peak RSS |")
            print("|---|---:|---:|---:|")
            r = run_timed(CHECK, path, None)
            print(f"| this tree | {args.big} | {r['cpu']:.1f} s | {r['rss_mib']:.1f} MiB |")


if __name__ == "__main__":
    main()
