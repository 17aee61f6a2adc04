"""How long ``fagorcnc check`` takes on one large CAM program, and its peak memory.

Run::

    python benchmarks/check_speed.py [--blocks 20000] [--tree PATH]

For the 3D finishing raster and the contour of arcs of ``plan_speed.py`` (under HSC), at the
given size and four times it, each in a fresh process: the check's time (best of 3) and its
peak resident memory.  ``--tree`` runs the same with the ``fagorcnc`` package of another
checkout (e.g. an earlier commit, ``git worktree add /tmp/old REV``) for comparison.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from plan_speed import contour, raster

#: The child process that times one file's check (best of argv[2] runs); cycles_speed.py uses it too.
CHILD = """
import json, resource, sys, time
from fagorcnc.commands.check import check_file
from fagorcnc.runtime import keep_freed_memory
keep_freed_memory()   # as the fagorcnc command does
best = None
for _ in range(int(sys.argv[2])):
    t0 = time.perf_counter()
    report = check_file(sys.argv[1])
    seconds = time.perf_counter() - t0
    best = seconds if best is None else min(best, seconds)
assert report.verdict() == "pass", [str(d) for d in report.diagnostics]
print(json.dumps({"seconds": best, "moves": report.moves, "cycle": report.cycle_time,
                  "holes": sum(c["holes"] for c in report.cycles),
                  "rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def measure(path: Path, repeat: int, tree: str | None) -> dict:
    env = dict(os.environ)
    if tree is not None:
        env["PYTHONPATH"] = str(Path(tree).resolve())
    out = subprocess.run([sys.executable, "-c", CHILD, str(path), str(repeat)], capture_output=True, text=True,
                         check=True, env=env)
    return json.loads(out.stdout)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--blocks", type=int, default=20_000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--tree", help="another checkout whose fagorcnc package to measure")
    args = ap.parse_args()
    print("| program | blocks | check time | moves/s | peak RSS |")
    print("|---|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as folder:
        for name, make in (("raster", raster), ("contour", contour)):
            for n in (args.blocks, 4 * args.blocks):
                path = Path(folder) / f"{name}{n}.nc"
                path.write_text("\n".join(make(n, "HSC")) + "\n")
                r = measure(path, args.repeat if n == args.blocks else 1, args.tree)
                print(f"| {name} HSC | {n} | {r['seconds']:.2f} s | {r['moves'] / r['seconds']:,.0f} "
                      f"| {r['rss_mib']:.1f} MiB |")


if __name__ == "__main__":
    main()
