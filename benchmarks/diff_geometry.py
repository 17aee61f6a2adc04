"""The geometric comparison of ``fagorcnc diff`` alone, on 10^6 path segments (issue 28).

Run::

    python benchmarks/diff_geometry.py [--segments 1000000]

Two synthetic 3D finishing rasters (rows of 0.5 mm segments 0.2 mm apart, a gentle surface), the
second with one row moved 0.02 mm; the two directed Hausdorff passes of ``diff`` (spatial index and
exact bound) between them, without the dry runs that produce real programs' paths (see
``tools_speed.py`` for those).  Prints the time and the deviation found (0.02 mm).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from fagorcnc.commands.geometry_index import SegmentIndex, directed


def raster(n: int, shift: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """``n`` segments: start and end points (n x 3), rows of 500 segments, the middle row moved by ``shift``."""
    k = np.arange(n + 1)
    row, col = k // 500, k % 500
    x = np.where(row % 2 == 0, col * 0.5, (499 - col) * 0.5)
    y = row * 0.2 + np.where(row == n // 1000, shift, 0.0)
    z = 0.1 * np.sin(x / 10.0) * np.cos(y / 10.0)
    pts = np.stack([x, y, z], axis=1)
    return pts[:-1], pts[1:]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--segments", type=int, default=1_000_000, help="both paths together")
    args = parser.parse_args()
    half = args.segments // 2
    a1, b1 = raster(half)
    a2, b2 = raster(half, 0.02)
    t0 = time.perf_counter()
    ab = directed(a1, b1, SegmentIndex(a2, b2), 0.01, 1e-5)
    ba = directed(a2, b2, SegmentIndex(a1, b1), 0.01, 1e-5)
    seconds = time.perf_counter() - t0
    print(f"{2 * half} segments compared in {seconds:.2f} s; deviation {max(ab.maximum, ba.maximum):.6f} mm")


if __name__ == "__main__":
    main()
