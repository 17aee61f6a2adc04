"""Planner against interpreter in instructions per block (cachegrind): a measure that repeats.

Run::

    python benchmarks/instructions.py [--blocks 3000]

Wall-clock times on a shared machine move by a quarter from run to run; instruction counts
do not.  For the 3D finishing raster of ``plan_speed.py`` in each corner mode, and its
contour of arcs under G05 and HSC, this runs,
under ``valgrind --tool=cachegrind`` with address randomisation off, a fixed hash seed and
OpenBLAS on one thread (its idle threads spin for a time that depends on the load):

* the interpreter alone on ``--blocks`` and on 4x as many blocks: the difference over the
  extra blocks is the interpreter's cost per block, start-up excluded;
* the interpreter, then the planner over its records: the difference from the first run is
  the planner's cost for those blocks.

Both under a dry run's collector setting.  Needs valgrind (``apt install valgrind``); about
a minute per mode.

With ``--stages`` it splits the planner's instructions per block into its three stages, each
run over the records after the ones before it: making the spans (``Planner._spans``), the
corners between them (``Planner._corners``: stops, corner curves, trims) and the timing
(look-ahead, ruckig profiles, segments).
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
from itertools import pairwise

CHILD = """
import sys
sys.path.insert(0, {bench!r})
from plan_speed import contour, raster
import fagorcnc
from fagorcnc.plan import Planner
from fagorcnc.runtime import fewer_collections, keep_freed_memory
from fagorcnc.simulate import Run
keep_freed_memory()
machine = fagorcnc.load_machine(None)
with fewer_collections():
    records = list(Run({shape}({blocks}, {mode!r}), "<{shape}>", machine))
    planner = Planner(machine)
    stage = {stage!r}
    if stage == "spans":
        sum(1 for _ in planner._spans(iter(records)))
    elif stage == "corners":
        sum(1 for _ in planner._corners(planner._spans(iter(records))))
    elif stage == "plan":
        sum(1 for _ in planner.segments(iter(records)))
"""

#: The planner's stages, each measured with the ones before it (``none``: the interpreter alone).
STAGES = ("none", "spans", "corners", "plan")


#: The programs measured: the 3D finishing raster (lines) in each corner mode, and the freeform
#: contour of arcs and lines as CAM arc fitting writes it (``plan_speed.contour``).
SHAPES = (("raster", "G50"), ("raster", "G05"), ("raster", "HSC"), ("contour", "G05"), ("contour", "HSC"))


def instructions(shape: str, mode: str, blocks: int, stage: str) -> int:
    """Instructions of interpreting ``blocks`` of a program and running the planner up to ``stage``."""
    code = CHILD.format(bench=os.path.dirname(os.path.abspath(__file__)), shape=shape, blocks=blocks, mode=mode,
                        stage=stage)
    env = dict(os.environ, PYTHONHASHSEED="0", OPENBLAS_NUM_THREADS="1")
    cmd = ["valgrind", "--tool=cachegrind", "--cache-sim=no", "--cachegrind-out-file=/dev/null",
           sys.executable, "-c", code]
    if shutil.which("setarch"):
        cmd = ["setarch", os.uname().machine, "-R", *cmd]
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, check=True).stderr
    found = re.search(r"I\s+refs:\s+([\d,]+)", out)
    if found is None:
        raise RuntimeError(f"no instruction count in valgrind's output:\n{out[-2000:]}")
    return int(found.group(1).replace(",", ""))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--blocks", type=int, default=3000)
    ap.add_argument("--stages", action="store_true", help="split the planner into spans, corners and timing")
    args = ap.parse_args()
    if shutil.which("valgrind") is None:
        sys.exit("valgrind is not installed: this benchmark counts instructions with cachegrind")
    n = args.blocks
    if args.stages:
        print("| program | mode | spans | corners | timing | planner (instructions per block) |")
        print("|---|---|---|---|---|---|")
        for shape, mode in SHAPES[1:]:
            counts = [instructions(shape, mode, n, stage) for stage in STAGES]
            parts = [(b - a) / n / 1e3 for a, b in pairwise(counts)]
            print(f"| {shape} | {mode} | " + " | ".join(f"{x:,.0f} k" for x in parts) +
                  f" | {sum(parts):,.0f} k |", flush=True)
        return
    print("| program | mode | interpreter (instructions per block) | planner (instructions per block) "
          "| planner / interpreter |")
    print("|---|---|---|---|---|")
    for shape, mode in SHAPES:
        alone = instructions(shape, mode, n, "none")
        interp = (instructions(shape, mode, 4 * n, "none") - alone) / (3 * n)
        planner = (instructions(shape, mode, n, "plan") - alone) / n
        print(f"| {shape} | {mode} | {interp / 1e3:,.0f} k | {planner / 1e3:,.0f} k | {planner / interp:.2f} |",
              flush=True)


if __name__ == "__main__":
    main()
