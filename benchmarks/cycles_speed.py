"""``fagorcnc check`` of a drilling program with many holes: time and peak memory.

Run::

    python benchmarks/cycles_speed.py [--holes 50000] [--repeat 1]

Two programs per size, each checked in a fresh process: ``G81 + G160`` (a G81 definition, then
rows of 100 holes by one ``G160`` block each, a G00 back to the start of the next row) and
``G81 + points`` (one bare ``X Y`` block per hole in the influence zone, as the Autodesk post
writes).  The canned cycle expands into records as the program streams, so the peak memory
must not grow with the number of holes: each size is also measured at a tenth of it.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

from check_speed import CHILD  # the same timed check in a fresh process (it reports the holes too)

ROW = 100          # holes per row
PITCH = 5.0        # mm between holes
MACHINE_NOTE = "; the default machine: X Y Z within +-1000 mm"


def pattern_program(holes: int) -> str:
    rows = (holes + ROW - 1) // ROW
    out = ["%HOLES", MACHINE_NOTE, "G71 G90 G17 G94", "S2000 M03", "G00 X-400 Y-400 Z20"]
    for r in range(rows):
        y = -400.0 + r * 0.1
        n = min(ROW, holes - r * ROW)
        if r == 0:
            out.append(f"G99 G81 X-400 Y{y:.1f} Z2 I-3 F2000")
        else:
            out.append(f"X-400 Y{y:.1f}")
        if n > 1:
            out.append(f"G160 X{PITCH * (n - 1):g} K{n}")
    out += ["G80", "M30"]
    return "\n".join(out) + "\n"


def points_program(holes: int) -> str:
    out = ["%POINTS", MACHINE_NOTE, "G71 G90 G17 G94", "S2000 M03", "G00 X-400 Y-400 Z20",
           "G98 G81 X-400 Y-400 Z2 I-3 F2000"]
    for k in range(1, holes):
        out.append(f"X{-400 + (k % ROW) * PITCH:g} Y{-400 + (k // ROW) * 0.1:.1f}")
    out += ["G80", "M30"]
    return "\n".join(out) + "\n"


def measure(path: Path, repeat: int) -> dict:
    out = subprocess.run([sys.executable, "-c", CHILD, str(path), str(repeat)], capture_output=True, text=True,
                         check=True)
    return json.loads(out.stdout)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--holes", type=int, default=50_000)
    ap.add_argument("--repeat", type=int, default=1)
    args = ap.parse_args()
    print("| program | holes | moves | check time | holes/s | peak RSS |")
    print("|---|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as folder:
        for name, make in (("G81 + G160", pattern_program), ("G81 + points", points_program)):
            for n in (args.holes // 10, args.holes):
                path = Path(folder) / f"holes{n}.nc"
                path.write_text(make(n))
                r = measure(path, args.repeat)
                assert r["holes"] == n, r
                print(f"| {name} | {n} | {r['moves']} | {r['seconds']:.2f} s | {n / r['seconds']:,.0f} "
                      f"| {r['rss_mib']:.1f} MiB |")


if __name__ == "__main__":
    main()
