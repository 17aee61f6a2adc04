"""Streaming interpreter speed and memory on a large CAM-style program.

Run::

    python benchmarks/interp_speed.py [--blocks 1000000] [--compare 100000]

Each size runs in its own subprocess so that its peak RSS (``ru_maxrss``) is
its own.  The program is generated lazily line by line (it never exists as
one string), parsed and interpreted as a stream: ``fagorcnc.simulate`` would
keep every move, the streaming :class:`fagorcnc.Run` keeps none.
"""

from __future__ import annotations

import argparse
import json
import random
import resource
import subprocess
import sys
import time


def program(n: int, seed: int = 8065):
    """A finishing program: G1/G2/G3 moves with IJ centres, P-parameters and a loop every 1000 blocks."""
    r = random.Random(seed)
    yield "%BIG"
    yield "G71 G90 G17 G54"
    yield "T1 D1 M06"
    yield "S12000 M03"
    yield "G0 X0 Y0 Z5"
    yield "G1 Z-1 F1200"
    x = y = 0.0
    for i in range(n):
        if i % 1000 == 999:
            yield "P100 = 0"
            yield "$WHILE P100 < 2"
            yield "P100 = P100 + 1"
            yield "$ENDWHILE"
            continue
        k = r.random()
        if k < 0.8:
            x = round(r.uniform(-150, 150), 3)
            y = round(r.uniform(-150, 150), 3)
            yield f"N{10 + 5 * i} G1 X{x:.3f} Y{y:.3f} F{r.randint(800, 3000)}"
        else:
            # a half circle from (x, y) around (x + 2, y): end (x + 4, y)
            yield f"N{10 + 5 * i} G{2 if k < 0.9 else 3} X{x + 4:.3f} Y{y:.3f} I2 J0"
            x += 4
    yield "G0 Z50"
    yield "M30"


def measure(n: int) -> dict:
    import fagorcnc
    from fagorcnc.simulate import Run

    machine = fagorcnc.load_machine({"axes": {a: {"min_limit": -10000.0, "max_limit": 10000.0} for a in "XYZ"}})
    t0 = time.perf_counter()
    run = Run(program(n), "<generated>", machine)
    count = sum(1 for _ in run)
    dt = time.perf_counter() - t0
    errors = [str(d) for d in run.diagnostics if d.is_error]
    return {"blocks": n, "records": count, "seconds": dt, "blocks_per_s": n / dt,
            "peak_rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
            "released_blocks": run._stream.released, "errors": errors[:3]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, default=1_000_000)
    ap.add_argument("--compare", type=int, default=100_000, help="a smaller size to compare memory with")
    ap.add_argument("--one", type=int, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.one:
        print(json.dumps(measure(args.one)))
        return
    rows = []
    for n in (args.compare, args.blocks):
        out = subprocess.run([sys.executable, __file__, "--one", str(n)], capture_output=True, text=True, check=True)
        rows.append(json.loads(out.stdout))
    import fagorcnc

    print(f"fagorcnc {fagorcnc.__version__} streaming interpreter, Python {sys.version.split()[0]}")
    print(f"{'blocks':>10} {'records':>10} {'seconds':>8} {'blocks/s':>10} {'peak RSS MiB':>13}")
    for r in rows:
        print(f"{r['blocks']:>10} {r['records']:>10} {r['seconds']:>8.1f} {r['blocks_per_s']:>10,.0f} "
              f"{r['peak_rss_mib']:>13.1f}")
        if r["errors"]:
            print("   errors:", r["errors"])


if __name__ == "__main__":
    main()
