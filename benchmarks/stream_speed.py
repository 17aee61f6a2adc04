"""Streaming-speed benchmark: segments per second the interpcnc back-end sustains to the emulated card.

Run from the repository root::

    python benchmarks/stream_speed.py [--segments N] [--speed S] [--in-process]

It plans a raster of short G1 moves (0.3 mm at F3000, a few XY arcs, coolant
M8/M9 mapped to digital outputs), starts the InterpCNC emulator on 127.0.0.1
(a free port; by default in its own process, like a real card beside the PC;
``--in-process`` runs it in a thread of this process instead) with a speed
factor high enough that the card consumes faster than any link can feed it,
streams every segment with :class:`~fagorcnc.backends.interpcnc.InterpCncBackend`
over Modbus TCP, waits for the card to finish, checks that the executed log
matches the plan, and prints one line: segments/s, Modbus requests/s and
registers written per segment.  Each segment costs two requests (its
sequence marker, then its move) plus the status polls.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import fagorcnc
from fagorcnc.backends.interpcnc import InterpCncBackend
from fagorcnc.backends.interpcnc.emulator import Emulator, EmulatorProcess
from fagorcnc.backends.interpcnc.verify import executed_events, expected_events, first_difference

OUTPUTS = {"M8": {"type": 1, "output": 2, "value": 1}, "M9": {"type": 1, "output": 2, "value": 0}}


def program(lines: int) -> str:
    out = ["G90 G0 X0 Y0 Z0", "M8"]
    y = 0.0
    for i in range(lines):
        if i and i % 2500 == 0:
            out += [f"G1 X0 Y{y:.3f} F3000", f"G2 X0 Y{y + 2:.3f} I0 J1", f"G3 X0 Y{y + 4:.3f} I0 J1"]
            y += 4.0
        y += 0.01
        out.append(f"G1 X{0.3 * (i % 2 == 0):.1f} Y{y:.3f} F3000")
    out += ["M9", "M30"]
    return "\n".join(out) + "\n"


def run(segments_wanted: int, speed: float, in_process: bool) -> str:
    result = fagorcnc.simulate(program(segments_wanted))
    if not result.ok:
        raise SystemExit(f"the benchmark program does not plan: {result.diagnostics[:2]}")
    segments = list(result.segments(keep_profiles=False))
    emu = Emulator(port=0, speed=speed) if in_process else EmulatorProcess(speed=speed)
    emu.start()
    try:
        backend = InterpCncBackend(result.machine, port=emu.port, outputs=OUTPUTS)
        backend.open()
        t0 = time.perf_counter()
        for seg in segments:
            backend.send(seg)
        backend.finish()
        elapsed = time.perf_counter() - t0
        requests = backend.link.requests
        backend.close()
        report = emu.stop() if not in_process else None
        log = report["log"] if report else emu.executed()
    finally:
        if in_process:
            emu.stop()
        else:
            emu.kill()
    difference = first_difference(expected_events(segments, backend), executed_events(log))
    where = "in-process" if in_process else "separate process"
    check = "executed log matches the plan" if difference is None else f"MISMATCH: {difference}"
    return (f"stream_speed: {len(segments)} segments in {elapsed:.2f} s = {len(segments) / elapsed:.0f} segments/s "
            f"({requests / elapsed:.0f} Modbus requests/s, {backend.stats['registers'] / len(segments):.1f} "
            f"registers/segment, {backend.stats['polls']} polls) to the emulator ({where}, speed x{speed:g}) "
            f"over loopback TCP; {check}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--segments", type=int, default=20_000, help="short moves in the program (default 20000)")
    ap.add_argument("--speed", type=float, default=1000.0, help="emulator speed factor (default 1000)")
    ap.add_argument("--in-process", action="store_true", help="run the emulator in a thread of this process")
    args = ap.parse_args()
    print(run(args.segments, args.speed, args.in_process), flush=True)


if __name__ == "__main__":
    main()
