"""Streaming-speed benchmark: segments per second the interpcnc back-end sustains to the emulated card.

Run from the repository root::

    python benchmarks/stream_speed.py                       # 1 500-segment spiral, card at 10x real time
    python benchmarks/stream_speed.py --speed 6 --marker-every 1
    python benchmarks/stream_speed.py --raster 20000 --speed 1000   # flat out: the card never waits

The default program is issue 29's: an Archimedean spiral of 1 500 chords of
0.5 mm at F3000 (10 ms each at real time).  The InterpCNC emulator runs on
127.0.0.1 in its own process (like a real card beside the PC; ``--in-process``
puts it in a thread of this one) in motion-time mode: every move takes its
motion time (length / feed) divided by ``--speed``, on the wall clock, and the
card counts the underruns (its planner ran dry while the stream had not
ended).  At ``--speed 10`` the card consumes about 1 000 segments per second:
the stream keeps up if the underrun count stays 0.

It prints the segments/s sustained (sent over the time from the first to the
last segment), the underruns, and where the time went: planning (done before
streaming here, per segment), encoding the commands, Modbus writes and polls
(count and mean round trip), and waits for room in the card's buffer.  The
executed log is checked against the plan.  Wall-clock figures: they depend on
the machine and its load (the README quotes one run).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import fagorcnc
from fagorcnc.backends.interpcnc import InterpCncBackend
from fagorcnc.backends.interpcnc.emulator import Emulator, EmulatorProcess
from fagorcnc.backends.interpcnc.verify import executed_events, expected_events, first_difference

OUTPUTS = {"M8": {"type": 1, "output": 2, "value": 1}, "M9": {"type": 1, "output": 2, "value": 0}}


def spiral(segments: int, step: float = 0.5, feed: float = 3000.0) -> str:
    """Issue 29's program: ``segments`` chords of ``step`` mm along a spiral (1 mm further out per turn)."""
    out = ["G90 G0 X10 Y0 Z0", f"G1 F{feed:g}"]
    theta = 0.0
    for _ in range(segments):
        theta += step / (10.0 + theta / (2 * math.pi))
        r = 10.0 + theta / (2 * math.pi)
        out.append(f"X{r * math.cos(theta):.4f} Y{r * math.sin(theta):.4f}")
    out.append("M30")
    return "\n".join(out) + "\n"


def raster(lines: int) -> str:
    """Short G1 moves (0.3 mm at F3000) in a zigzag (X reverses at every joint: one marker per move), a few XY arcs,
    coolant M8/M9."""
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


def run(text: str, speed: float, in_process: bool, marker_every: int, start_lead: float = 2.0) -> str:
    t0 = time.perf_counter()
    result = fagorcnc.simulate(text)
    if not result.ok:
        raise SystemExit(f"the benchmark program does not plan: {result.diagnostics[:2]}")
    segments = list(result.segments(keep_profiles=False))
    planning = time.perf_counter() - t0
    emu = Emulator(port=0, speed=speed, resolution=1000) if in_process else EmulatorProcess(speed=speed,
                                                                                             resolution=1000)
    emu.start()
    try:
        backend = InterpCncBackend(result.machine, port=emu.port, outputs=OUTPUTS, resolution=1000,
                                   marker_every=marker_every, start_lead=start_lead)
        backend.open()
        t0 = time.perf_counter()
        for seg in segments:
            backend.send(seg)
        sending = time.perf_counter() - t0
        backend.finish()
        elapsed = time.perf_counter() - t0
        requests = backend.link.requests
        rate = backend.rate()
        backend.close()
        report = emu.stop() if not in_process else None
        if in_process:
            card = emu.card
            report = {"log": emu.executed(), "underruns": card.underruns, "lag_events": card.lag_events}
    finally:
        if in_process:
            emu.stop()
        else:
            emu.kill()
    difference = first_difference(expected_events(segments, backend), executed_events(report["log"]))
    where = "in-process" if in_process else "separate process"
    check = "executed log matches the plan" if difference is None else f"MISMATCH: {difference}"
    st, n = backend.stats, len(segments)
    writes = st["commands"]
    polls = requests - writes
    other = sending - st["t_encode"] - st["t_write"] - st["t_poll"] - st["t_wait"]
    lines = [
        f"stream_speed: {n} segments, card at x{speed:g} ({where}, loopback TCP, marker_every={marker_every}, "
        f"start_lead={start_lead:g} s): "
        f"{rate:.0f} segments/s sustained, {report['underruns']} underruns (card), {st['underruns']} seen by the "
        f"back-end; sent in {sending:.2f} s, all run in {elapsed:.2f} s; {check}",
        f"  per segment: planning {planning / n * 1e3:.3f} ms (before streaming), encoding "
        f"{st['t_encode'] / n * 1e3:.3f} ms, writes {writes / n:.2f} x {st['t_write'] / max(writes, 1) * 1e3:.3f} ms, "
        f"polls {polls / n:.3f} x {st['t_poll'] / max(polls, 1) * 1e3:.3f} ms, waits for room "
        f"{st['t_wait'] / n * 1e3:.3f} ms, the rest {other / n * 1e3:.3f} ms",
        f"  {st['markers']} markers ({st['markers'] / n:.2f} per segment), {st['registers'] / n:.1f} registers per "
        f"segment, {st['polls']} status polls, {requests} Modbus requests; emulator time lost to CPU starvation: "
        f"{report.get('lag_events', 0)} updates",
    ]
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--spiral", type=int, default=1500, help="chords of the spiral program (default 1500)")
    ap.add_argument("--raster", type=int, default=0, help="instead, a zigzag raster of that many short moves")
    ap.add_argument("--speed", type=float, default=10.0, help="emulator speed factor (default 10 x real time)")
    ap.add_argument("--marker-every", type=int, default=16, help="moves sharing a sequence marker (default 16)")
    ap.add_argument("--start-lead", type=float, default=2.0,
                    help="s of planned motion queued before the card starts (the back-end's default: 2)")
    ap.add_argument("--in-process", action="store_true", help="run the emulator in a thread of this process")
    args = ap.parse_args()
    text = raster(args.raster) if args.raster else spiral(args.spiral)
    print(run(text, args.speed, args.in_process, args.marker_every, args.start_lead), flush=True)


if __name__ == "__main__":
    main()
