"""Interpreter speed with and without a #LINK coupling (the stage that writes each slave into the records).

Run::

    python benchmarks/link_speed.py [--blocks 30000]

The program is :func:`interp_speed.program` (G1/G2/G3 moves in XY); the coupled run adds
``#LINK [Z, U]`` after its header, so every record carries the slave U.  CPU time, best of three.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import interp_speed

import fagorcnc
from fagorcnc.simulate import Run


def program(n: int, link: bool):
    for i, line in enumerate(interp_speed.program(n)):
        yield line
        if i == 4 and link:
            yield "#LINK [Z, U]"   # Z is not in the arcs' plane: the slave follows every record


def measure(n: int, link: bool) -> float:
    machine = fagorcnc.load_machine({"axes": {a: {"min_limit": -10000.0, "max_limit": 10000.0} for a in "XYZU"}})
    best = float("inf")
    for _ in range(3):
        t0 = time.process_time()
        for _record in Run(program(n, link), "<generated>", machine):
            pass
        best = min(best, time.process_time() - t0)
    return n / best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, default=30_000)
    args = ap.parse_args()
    plain, linked = measure(args.blocks, False), measure(args.blocks, True)
    print(f"{args.blocks} blocks: {plain:,.0f} blocks/s without #LINK, {linked:,.0f} blocks/s with #LINK [Z, U] "
          f"({100 * (1 - linked / plain):.0f} % slower)")


if __name__ == "__main__":
    main()
