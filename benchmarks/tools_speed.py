"""How long ``fagorcnc expand`` and ``fagorcnc diff`` take on large CAM programs, and their memory.

Run::

    python benchmarks/tools_speed.py [--blocks 200000]

Programs: the 3D finishing raster of ``plan_speed.py`` (G50, straight lines) and its contour of
arcs.  ``expand``: the whole expansion (JSON Lines) written to /dev/null, in a fresh process, with
its peak resident memory (constant memory: it should not grow with the program; compare
``--blocks 50000``).  ``diff``: the raster against itself with one row moved by 0.02 mm, split into
the two dry runs (interpret and plan both programs, collect their paths) and the geometric
comparison (spatial index and the exact bound), with the number of path segments compared.  The
raster passes over itself (its rows repeat after 400 rows): the hard case of
the nearest-segment search, where many pieces are about as near.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

from plan_speed import contour, raster

EXPAND = """
import json, resource, sys, time
from fagorcnc.commands.expand import expand
from fagorcnc.runtime import keep_freed_memory
keep_freed_memory()
t0 = time.perf_counter()
with open("/dev/null", "w") as out:
    result = expand(sys.argv[1], lambda line: out.write(line + "\\n"))
seconds = time.perf_counter() - t0
assert result.ok
print(json.dumps({"seconds": seconds, "moves": result.moves,
                  "rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""

DIFF = """
import json, resource, sys, time
from fagorcnc.commands import diff
from fagorcnc.commands.geometry_index import SegmentIndex, directed
from fagorcnc.config.machine import load_machine
from fagorcnc.runtime import keep_freed_memory
keep_freed_memory()
machine = load_machine(None)
t0 = time.perf_counter()
pa = diff.program_path(sys.argv[1], machine, 0.0005)
pb = diff.program_path(sys.argv[2], machine, 0.0005)
t1 = time.perf_counter()
ab = directed(pa.a, pa.b, SegmentIndex(pb.a, pb.b), 0.01, 1e-5)
ba = directed(pb.a, pb.b, SegmentIndex(pa.a, pa.b), 0.01, 1e-5)
t2 = time.perf_counter()
print(json.dumps({"dry_runs": t1 - t0, "geometry": t2 - t1, "segments": len(pa.lines) + len(pb.lines),
                  "deviation": max(ab.maximum, ba.maximum),
                  "rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def _run(code: str, *args: str) -> dict:
    out = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--blocks", type=int, default=200_000)
    parser.add_argument("--only", choices=("expand", "diff"), help="run one of the two")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        progs = {}
        for name, make in (("raster", raster), ("contour", contour)):
            path = Path(tmp) / f"{name}.nc"
            path.write_text("\n".join(make(args.blocks, "G50")) + "\n")
            progs[name] = path
        for name, path in progs.items() if args.only != "diff" else ():
            r = _run(EXPAND, str(path))
            print(f"expand {name:8} {args.blocks} blocks: {r['seconds']:.1f} s, {r['moves']} moves, "
                  f"peak {r['rss_mib']:.0f} MiB")
        if args.only == "expand":
            return
        text = progs["raster"].read_text()
        moved = Path(tmp) / "moved.nc"   # row 10 (Y10) moved by 0.02 mm in Y
        moved.write_text(text.replace(" Y10.0000 ", " Y10.0200 "))
        r = _run(DIFF, str(progs["raster"]), str(moved))
        print(f"diff   raster   {args.blocks} blocks x 2: dry runs {r['dry_runs']:.1f} s, geometry "
              f"{r['geometry']:.1f} s for {r['segments']} segments, deviation {r['deviation']:.4f} mm, "
              f"peak {r['rss_mib']:.0f} MiB")


if __name__ == "__main__":
    main()
