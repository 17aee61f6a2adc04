"""Curves: interpretation and planning of #POLY and #SPLINE chords, against the same points as G01.

Run::

    python benchmarks/curves_speed.py [--points 2000]

Times (CPU) the manual's parabola (#POLY, 1648 chords of 1 µm), a spline through ``points`` points
of a sine wave, and the same points as plain G01 moves (G05), each interpreted and planned.
"""

from __future__ import annotations

import argparse
import math
import time

import fagorcnc

BIG = {"axes": {"X": {"min_limit": -10000, "max_limit": 10000}, "Y": {"min_limit": -20000, "max_limit": 20000},
                "Z": {}}}


def wave(points: int) -> list[str]:
    return [f"X{i * 0.5:.4f} Y{10 * math.sin(i * 0.5 / 8):.4f}" for i in range(1, points + 1)]


def measure(name: str, program: str, machine=None) -> None:
    t0 = time.process_time()
    r = fagorcnc.simulate(text=program, machine=machine)
    t1 = time.process_time()
    segments = list(r.segments())
    t2 = time.process_time()
    assert r.ok, r.diagnostics[:3]
    end = segments[-1].t0 + segments[-1].duration
    print(f"| {name} | {len(r.moves)} | {t1 - t0:.3f} s | {t2 - t1:.3f} s | {len(segments) / (t2 - t1):,.0f} |"
          f" {end:.2f} s |")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--points", type=int, default=2000)
    n = ap.parse_args().points
    print("| program | records | interpret | plan | segments/s | planned time |")
    print("|---|---|---|---|---|---|")
    measure("#POLY parabola (L15862)", "G0 X0 Y1 Z0\nG1 F1000\n#POLY [X[0,60,0,0,0] Y[1,0,3,0,0] SP0 EP60]\nM30\n",
            BIG)
    points = "\n".join(wave(n))
    measure(f"#SPLINE through {n} points", f"G1 X0 Y0 F3000\n#SPLINE ON\n{points}\n#SPLINE OFF\nM30\n")
    measure(f"G05 G01 through {n} points", f"G05 G1 X0 Y0 F3000\n{points}\nM30\n")


if __name__ == "__main__":
    main()
