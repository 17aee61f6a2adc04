"""Planning speed against interpretation speed, in the same process, and memory of the full stream.

Run::

    python benchmarks/plan_speed.py [--segments 50000]

For a 3D finishing raster (0.5 mm steps) in each corner mode it times:
interpretation alone (records/s), then interpretation + planning streamed
together (the dry run ``fagorcnc run`` does), and reports the planner's own
rate.  Peak RSS of a run 4x longer shows whether memory grows with the program.
"""

from __future__ import annotations

import argparse
import json
import math
import resource
import subprocess
import sys
import time


def raster(n: int, mode: str):
    yield "G90 G1 X0 Y0 Z2 F3000"
    yield {"G50": "G50", "G05": "G05", "HSC": "#HSC ON [CONTERROR 0.01]"}[mode]
    k, row = 0, 0
    while k < n:
        y = float(row % 400)
        xs = [i * 0.5 for i in range(101)]
        for x in xs[::-1] if row % 2 else xs:
            yield f"X{x:.4f} Y{y:.4f} Z{2 * math.sin(x / 7) * math.cos(y / 9):.4f}"
            k += 1
        row += 1
    yield "M30"


def contour_pass(per: int = 120, grow: float = 0.0):
    """One closed pass of a freeform finishing contour as CAM arc fitting writes it, from X40 Y0:
    arcs through three points of the curve r = 40 + 4 sin(5 t), ``per`` pieces round (2 mm long
    at 120, meeting at small kinks), every fourth piece a line (and a line where the curve is
    nearly straight).  ``grow``: that much wider (r = 40 + grow + ...).  The planner's tests use
    it too."""

    def at(t: float) -> tuple[float, float]:
        r = 40.0 + grow + 4.0 * math.sin(5.0 * t)
        return r * math.cos(t), r * math.sin(t)

    for i in range(per):
        t0, t1 = 2.0 * math.pi * i / per, 2.0 * math.pi * (i + 1) / per
        (x0, y0), (xm, ym), (x1, y1) = at(t0), at((t0 + t1) / 2.0), at(t1)
        cross = (xm - x0) * (y1 - ym) - (ym - y0) * (x1 - xm)
        if i % 4 == 3 or abs(cross) < 1e-3:
            yield f"G1 X{x1:.4f} Y{y1:.4f}"
        else:   # the circle through the three points
            d = 2.0 * (x0 * (ym - y1) + xm * (y1 - y0) + x1 * (y0 - ym))
            s0, sm, s1 = x0 * x0 + y0 * y0, xm * xm + ym * ym, x1 * x1 + y1 * y1
            cx = (s0 * (ym - y1) + sm * (y1 - y0) + s1 * (y0 - ym)) / d
            cy = (s0 * (x1 - xm) + sm * (x0 - x1) + s1 * (xm - x0)) / d
            yield f"{'G3' if cross > 0 else 'G2'} X{x1:.4f} Y{y1:.4f} I{cx - x0:.4f} J{cy - y0:.4f}"


def contour(n: int, mode: str, draft: float = 0.0):
    """At least ``n`` blocks of :func:`contour_pass` passes of 120 pieces, 0.2 mm apart in Z: the
    same XY blocks at every depth (as CAM posts write a profile's passes), or with ``draft`` each
    pass that much wider than the one above (a drafted wall: no corner of one pass is another's)."""
    yield "G90 G1 X40 Y0 Z0 F3000"
    yield {"G50": "G50", "G05": "G05", "HSC": "#HSC ON [CONTERROR 0.01]"}[mode]
    k, z, grow = 0, 0.0, 0.0
    while k < n:
        yield from contour_pass(grow=grow)
        k += 120
        z -= 0.2
        grow += draft
        yield f"G1 X{40.0 + grow:.4f} Z{z:.4f}" if draft else f"G1 Z{z:.4f}"
    yield "M30"


def tapered(n: int, mode: str):
    """:func:`contour` with every pass 0.02 mm wider than the one above (a 5.7 degree draft)."""
    return contour(n, mode, draft=0.02)


def measure(n: int, mode: str) -> dict:
    import fagorcnc
    from fagorcnc.plan import Planner
    from fagorcnc.runtime import fewer_collections, keep_freed_memory
    from fagorcnc.simulate import Run

    keep_freed_memory()   # the allocator setting of the fagorcnc command
    machine = fagorcnc.load_machine(None)
    with fewer_collections():   # the collector setting of a dry run
        t0 = time.perf_counter()
        records = sum(1 for _ in Run(raster(n, mode), "<raster>", machine))
        t_interp = time.perf_counter() - t0
        t0 = time.perf_counter()
        segments = cycle = 0.0
        for seg in Planner(machine).segments(Run(raster(n, mode), "<raster>", machine)):
            segments += 1
            cycle = seg.t0 + seg.duration
        t_both = time.perf_counter() - t0
    return {"mode": mode, "records": records, "segments": int(segments), "interp_s": t_interp, "both_s": t_both,
            "cycle_s": cycle, "rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--segments", type=int, default=50_000)
    ap.add_argument("--child", nargs=2, metavar=("N", "MODE"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        print(json.dumps(measure(int(args.child[0]), args.child[1])))
        return
    print(f"| mode | records | interpret (records/s) | interpret + plan (records/s) | planner alone (segments/s) "
          f"| planned cycle time | peak RSS, {args.segments} / {4 * args.segments} records |")
    print("|---|---|---|---|---|---|---|")
    for mode in ("G50", "G05", "HSC"):
        out = []
        for n in (args.segments, 4 * args.segments):
            p = subprocess.run([sys.executable, __file__, "--child", str(n), mode], capture_output=True, text=True,
                               check=True)
            out.append(json.loads(p.stdout))
        r = out[0]
        plan_only = r["both_s"] - r["interp_s"]
        print(f"| {mode} | {r['records']} | {r['records'] / r['interp_s']:,.0f} | {r['records'] / r['both_s']:,.0f} "
              f"| {r['segments'] / plan_only:,.0f} | {r['cycle_s']:.1f} s | {out[0]['rss_mib']:.1f} / "
              f"{out[1]['rss_mib']:.1f} MiB |")


if __name__ == "__main__":
    main()
