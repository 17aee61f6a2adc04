"""``fagorcnc check`` on a large program full of errors: time and peak memory (issue 25.2).

Run::

    python benchmarks/check_errors.py [--blocks 500000] [--errors 100000]

Writes a program of ``--blocks`` G1 moves whose last ``--errors`` go beyond the +X soft
limit of the default machine (+1000 mm), then runs ``fagorcnc check`` (the command, in a
fresh process) on it and prints the wall time, the peak resident memory of the process, the
errors counted and listed, and the report's "more not shown" line.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CHILD = """
import json, resource, sys
from fagorcnc.cli import main
status = main(["check", "--format", "json", "-o", sys.argv[2], sys.argv[1]])
print(json.dumps({"status": status, "rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def write_program(path: Path, blocks: int, errors: int) -> None:
    with open(path, "w") as out:
        out.write("G90 G1 X0 Y0 F3000\n")
        for k in range(blocks - errors):
            out.write(f"G1 X{k % 200}.5 Y{(k // 200) % 100}\n")
        for k in range(errors):
            out.write(f"G1 X{1100 + k % 50} Y{k % 100}\n")   # beyond the +1000 mm soft limit of X
        out.write("M30\n")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--blocks", type=int, default=500_000)
    parser.add_argument("--errors", type=int, default=100_000)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        program, report = Path(tmp) / "errors.nc", Path(tmp) / "report.json"
        write_program(program, args.blocks, args.errors)
        t0 = time.perf_counter()
        out = subprocess.run([sys.executable, "-c", CHILD, str(program), str(report)], capture_output=True,
                             text=True, check=True)
        seconds = time.perf_counter() - t0
        child = json.loads(out.stdout)
        (f,) = json.loads(report.read_text())["files"]
    print(f"{args.blocks} blocks, {args.errors} beyond the soft limit: exit {child['status']}, "
          f"{seconds:.1f} s, peak RSS {child['rss_mib']:.0f} MiB; errors counted {f['counts']['error']}, "
          f"listed {len(f['diagnostics'])}, not shown {f['not_shown']}")


if __name__ == "__main__":
    main()
