"""Robustness figures for the README, measured: fuzzing, runaway guards, link faults, file safety.

Run from the repository root::

    python benchmarks/robustness.py            # default budgets: about 5 minutes on 2 cores
    python benchmarks/robustness.py --quick    # small budgets: about a minute

It prints progress on stderr and, at the end, a markdown block for the README
(stdout) with the total run time:

(a) **fuzzing**: the three hypothesis suites (``tests/test_fuzz.py`` parser,
    ``tests/test_fuzz_interp.py`` interpreter, ``tests/test_fuzz_plan.py``
    planner), each run by pytest in a subprocess with ``--examples`` inputs per
    property (a settings profile registered by this file acting as a pytest
    plugin, so the suites run unmodified); reports the inputs tried per suite
    (from hypothesis' statistics) and the crashes (failing properties) found;
(b) **runaway guards**: programs that would never end - an endless
    ``$WHILE``, a global subroutine calling itself, ``NR1000000000``, a
    ``#RPT`` of 10^9, endless ``$GOTO`` loops (of moves, of ``#MSG`` notes),
    a gigantic generated program streamed - each must stop with its
    diagnostic code; reports the code, the time it took and the peak memory;
(c) **link faults**: the fault campaign of :func:`run_campaign` (also run,
    bounded, by ``tests/test_fault_campaign.py``): a stream of 10 000+ short
    segments to the InterpCNC emulator with faults of every kind the emulator
    can inject, each recovered as an operator would; reports faults by kind,
    recoveries, segments lost / duplicated and motion commands the card
    accepted after an alarm before ``resume()``;
(d) **file safety**: ``tests/test_file_safety.py``, pass/fail counts.

The campaign (see :func:`run_campaign`)
---------------------------------------
A Fagor program of ``G90 G1 X.. Y.. F3000`` moves of 0.2-0.8 mm (a random
walk), with XY arcs (G2/G3), coolant and spindle M functions mapped to
synchronised actions by the back-end's ``outputs`` option (M5 to two
actions) and a few G4 dwells, is planned and streamed with
:class:`~fagorcnc.backends.interpcnc.InterpCncBackend` to an in-process
:class:`~fagorcnc.backends.interpcnc.emulator.Emulator`.  At seeded random
points of the stream one fault at a time is injected:

* ``drop``: the connection is closed, at once or instead of accepting the
  n-th next command;
* ``exception``: the next one or two requests (writes, or any) are answered
  with a Modbus exception (device failure, busy, illegal value);
* ``delay``: the next request (a write, or any) is applied but answered
  after the back-end's timeout;
* ``alarm``: alarm 2 (soft limit) or 3 (cycle aborted), at once or half-way
  through the n-th next move;
* ``estop``: alarm 10 (emergency stop): the first ``resume()`` must fail,
  the operator releases the button, then ``resume()``;
* ``hold``: the card stops consuming for 0.05-0.3 s (its buffer fills; the
  back-end must wait, not fail).

Recovery is the operator's: ``resume()`` after an error carrying an alarm,
``reconnect_and_continue()`` after a link error - again if the recovery
itself fails.  The card is a :class:`JournalCard`: it records every command
it receives, every alarm and every acknowledge, and the campaign records in
the same journal when an error reached the caller and when the operator
called ``resume()``, so that "nothing was accepted after an alarm until
resume()" is checked on the card's side.  At the end the executed log is
compared event by event with the plan (:mod:`~fagorcnc.backends.interpcnc.verify`).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import logging
import math
import os
import random
import re
import subprocess
import sys
import tempfile
import threading
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from pymodbus.constants import ExcCodes  # noqa: E402

import fagorcnc  # noqa: E402
from fagorcnc.backends.interpcnc import InterpCncBackend, InterpCncError  # noqa: E402
from fagorcnc.backends.interpcnc import protocol as proto  # noqa: E402
from fagorcnc.backends.interpcnc import registers as regs  # noqa: E402
from fagorcnc.backends.interpcnc.card import Card  # noqa: E402
from fagorcnc.backends.interpcnc.emulator import Emulator  # noqa: E402
from fagorcnc.backends.interpcnc.verify import executed_events, expected_events  # noqa: E402

# ==================================================================== (c) the link-fault campaign
OUTPUTS = {
    "M3": {"type": 1, "output": 0, "value": 1},
    "M5": [{"type": 1, "output": 0, "value": 0}, {"type": 2, "output": 0, "value": 0}],
    "M8": {"type": 1, "output": 2, "value": 1},
    "M9": {"type": 1, "output": 2, "value": 0},
}
KINDS = ("drop", "exception", "delay", "alarm", "estop", "hold")
MOTION = (regs.CMD_FEED, regs.CMD_LINE, regs.CMD_ARC_XY)


def campaign_program(moves: int = 10_000, seed: int = 8060) -> str:
    """``moves`` short G1 moves (a random walk in a 40 mm square), an XY arc every 500, M8/M9 every 300, M3/M5
    around, a G4 dwell every 1000."""
    rng = random.Random(seed)
    out = ["G90 G0 X0 Y0 Z5", "M3", "G1 Z0 F1000"]
    x = y = 0.0
    coolant = False
    for i in range(moves):
        if i and i % 500 == 0:                    # an arc from here: random radius, start angle and sweep
            r, a0, sweep = rng.uniform(0.5, 2.0), rng.uniform(0, 2 * math.pi), rng.uniform(0.5, 5.5)
            cw = rng.random() < 0.5
            cx, cy = x - r * math.cos(a0), y - r * math.sin(a0)
            a1 = a0 - sweep if cw else a0 + sweep
            ex, ey = round(cx + r * math.cos(a1), 4), round(cy + r * math.sin(a1), 4)
            out.append(f"G{2 if cw else 3} X{ex:.4f} Y{ey:.4f} I{cx - x:.4f} J{cy - y:.4f} F2000")
            x, y = ex, ey
        if i % 300 == 150:
            coolant = not coolant
            out.append("M8" if coolant else "M9")
        if i % 1000 == 700:
            out.append(f"G4 K{rng.choice((0.01, 0.02, 0.05))}")
        if i % 2500 == 2000:
            out += ["M5", "M3"]
        angle, d = rng.uniform(0, 2 * math.pi), rng.uniform(0.2, 0.8)
        x = min(20.0, max(-20.0, x + d * math.cos(angle)))
        y = min(20.0, max(-20.0, y + d * math.sin(angle)))
        out.append(f"G1 X{x:.3f} Y{y:.3f} F3000")
    out += ["M9", "M5", "G0 Z5", "M30"]
    return "\n".join(out) + "\n"


def plan_campaign(moves: int = 10_000, seed: int = 8060):
    """The machine and the planned segments of :func:`campaign_program`."""
    result = fagorcnc.simulate(campaign_program(moves, seed))
    if not result.ok:
        raise RuntimeError(f"the campaign program does not run: {result.diagnostics[:3]}")
    return result.machine, list(result.segments(keep_profiles=False))


class JournalCard(Card):
    """The emulator's card model, journaling what it receives (under the emulator's lock).

    Entries: ``("cmd", cid, what, alarm_before, alarm_after, log_length, first_words, card_time)`` for every
    command written at holding 2000 (``what``: "queued", "discarded" (sent in alarm), "refused", the code of a
    1200 direct command or "immediate"), ``("alarm", code, marker, log_length)`` after an alarm stopped the card,
    and ``("mark", name, detail)`` written by the campaign ("alarm reported", "link error reported", "resume
    begin", "resume end").
    """

    def __init__(self, **options) -> None:
        self.journal: list[tuple] = []
        super().__init__(**options)

    def _command(self, words: list[int]) -> int | None:
        cid = words[0] if words else 0
        before = self.alarm
        code = super()._command(words)
        if cid in regs.BUFFERED_COMMANDS:
            what = "discarded" if before else ("refused" if code is not None else "queued")
        elif cid == regs.CMD_DIRECT and len(words) > 1:
            what = words[1]
        else:
            what = "immediate"
        self.journal.append(("cmd", cid, what, before, self.alarm, len(self.log), tuple(words[:8]), self.time))
        return code

    def raise_alarm(self, code: int) -> None:
        super().raise_alarm(code)       # (a move stopped with its counters at its end is logged as done here)
        self.journal.append(("alarm", code, self.hr[self.watch], len(self.log)))


@dataclass
class Fault:
    """One injected fault and what the campaign saw of it."""

    id: int
    kind: str
    detail: str
    segment: int                       # index of the segment about to be sent when it was injected
    code: int = 0                      # alarm code or Modbus exception code
    t_injected: float = 0.0
    t_recovered: float | None = None
    errors: list[str] = field(default_factory=list)
    lines: list[int] = field(default_factory=list)
    alarms: list[int] = field(default_factory=list)
    recoveries: int = 0
    waits: int = 0                     # back-end waits for room while a hold lasted
    violations: list[str] = field(default_factory=list)


@dataclass
class Comparison:
    """The executed log against the plan."""

    expected: int
    executed: int
    lost: int                          # planned events never executed
    duplicated: int                    # events executed more often than planned
    ordered: bool = True               # the same events in the same order
    difference: str | None = None


@dataclass
class CampaignResult:
    segments: int
    moves: int
    outputs: int
    dwells: int
    planned: int
    faults: list[Fault]
    skipped: int                       # planned faults left out to keep within the time budget
    comparison: Comparison
    unexpected: list[str]              # errors no injected fault explains (e.g. a slow reply on a loaded machine)
    violations: list[str]              # broken promises (messages, lines, alarm discipline), one sentence each
    motion_after_alarm: int            # motion commands the card accepted between an alarm and resume()
    sent_after_report: int             # commands that reached the card after an alarm was reported, before resume()
    executed_in_alarm: int             # log entries completed while an alarm stood
    discarded: int                     # commands sent before the back-end's next poll saw the alarm (re-sent later)
    acks: int                          # alarm acknowledges (1200/88) the card received
    resumes: int                       # resume() calls of the operator
    card: dict
    stats: dict
    elapsed: float
    speed: float = 0.0
    aborted: str | None = None
    journal: list[tuple] = field(default_factory=list, repr=False)
    log: list = field(default_factory=list, repr=False)
    interrupted: list = field(default_factory=list, repr=False)

    @property
    def injected(self) -> list[Fault]:
        return self.faults

    def by_kind(self) -> Counter:
        return Counter(f.kind for f in self.faults)

    @property
    def interrupted_moves(self) -> int:
        return sum(1 for e in self.interrupted if e.kind in ("line", "rapid", "arc"))

    @property
    def recoveries(self) -> int:
        return sum(f.recoveries for f in self.faults)


def compare(expected: list[tuple], executed: list[tuple]) -> Comparison:
    """Counts lost and duplicated events and checks the order."""
    missing = Counter(expected) - Counter(executed)
    extra = Counter(executed) - Counter(expected)
    k = next((k for k, (a, b) in enumerate(zip(expected, executed, strict=False)) if a != b),
             min(len(expected), len(executed)))
    ordered = k == len(expected) == len(executed)
    difference = None
    if not ordered:
        difference = (f"planned event {k} {expected[k] if k < len(expected) else 'none'}, executed event {k} "
                      f"{executed[k] if k < len(executed) else 'none'}; missing {list(missing.elements())[:3]}, "
                      f"extra {list(extra.elements())[:3]}")
    return Comparison(len(expected), len(executed), sum(missing.values()), sum(extra.values()), ordered, difference)


def _expect(fault: Fault, err: InterpCncError, first: bool, line_now: int) -> list[str]:
    """What an error must say: the fault in words, 'stopped sending', the last block started and its line."""
    msg = str(err)
    out = []
    if first:
        if fault.kind in ("alarm", "estop"):
            want = f"alarm {fault.code} ({proto.alarm_message(fault.code)})"
            if err.alarm != fault.code or want not in msg:
                out.append(f"expected {want!r} with alarm={fault.code}, got alarm={err.alarm}: {msg}")
        elif fault.kind == "exception":
            want = f"Modbus exception {fault.code} ("
            if want not in msg:
                out.append(f"expected {want!r}: {msg}")
        elif "no valid reply" not in msg and "Modbus exception" not in msg:
            out.append(f"expected 'no valid reply': {msg}")
        if "stopped sending" not in msg:
            out.append(f"no 'stopped sending': {msg}")
    if err.status is None or err.status.state != "alarm":
        out.append(f"status not 'alarm' ({err.status.state if err.status else None}): {msg}")
    if err.line <= 0 or (first and f"line {err.line}" not in msg):
        out.append(f"no last block line (line={err.line}): {msg}")
    elif err.line > line_now:
        out.append(f"line {err.line} reported, but the card had only started line {line_now}: {msg}")
    elif first and fault.kind in ("alarm", "estop") and err.line != line_now:
        out.append(f"line {err.line} reported, but the card stopped in line {line_now}: {msg}")
    return out


def _alarm_discipline(journal: list[tuple]) -> tuple[list[str], int, int, int, int, int, int]:
    """Walks the card's journal: (violations, motion commands queued in alarm, commands received after an alarm
    was reported and before resume(), log entries completed in alarm, commands discarded in alarm, acknowledges,
    resume() calls)."""
    violations: list[str] = []
    motion = after_report = in_alarm = discarded = acks = resumes = 0
    alarm_on, alarm_log = False, 0
    reported = resuming = False
    for e in journal:
        if e[0] == "alarm":
            if not alarm_on:
                alarm_on, alarm_log = True, e[3]
        elif e[0] == "mark":
            if e[1] == "alarm reported":
                reported = True
            elif e[1] == "resume begin":
                reported, resuming = False, True
                resumes += 1
            elif e[1] == "resume end":
                resuming = False
        else:
            _, cid, what, before, after, log_length = e[:6]
            if reported and not resuming:
                after_report += 1
                violations.append(f"command {cid}/{what} reached the card after an alarm was reported, "
                                  "before resume()")
            if what == "queued" and before and cid in MOTION:
                motion += 1
            if what == "discarded":
                discarded += 1
            if cid == regs.CMD_DIRECT and what == regs.DIRECT_ACK_ALARM:
                acks += 1
                if not resuming:
                    violations.append("an alarm was acknowledged outside resume()")
                if alarm_on and not after:
                    alarm_on = False
                    if log_length != alarm_log:
                        in_alarm += log_length - alarm_log
                        violations.append(f"{log_length - alarm_log} commands completed while an alarm stood")
    return violations, motion, after_report, in_alarm, discarded, acks, resumes


def _inject(emu: Emulator, fault: Fault, rng: random.Random, delay: float) -> None:
    kind = fault.kind
    if kind == "drop":
        if rng.random() < 0.7:
            n = rng.randint(0, 30)
            emu.drop_connection(after_commands=n)
            fault.detail = f"connection dropped instead of accepting command {n + 1}"
        else:
            emu.drop_now()
            fault.detail = "connection dropped at once"
    elif kind == "exception":
        code = rng.choice((ExcCodes.DEVICE_FAILURE, ExcCodes.DEVICE_BUSY, ExcCodes.ILLEGAL_VALUE))
        n, writes = rng.choice((1, 1, 2)), rng.random() < 0.7
        emu.fail_next(n, code, writes_only=writes)
        fault.code = int(code)
        fault.detail = f"{n} {'write' if writes else 'request'}(s) answered with exception {int(code)}"
    elif kind == "delay":
        writes = rng.random() < 0.7
        emu.delay_next(1, delay, writes_only=writes)
        fault.detail = f"the next {'write' if writes else 'request'} answered {delay:g} s late"
    elif kind in ("alarm", "estop"):
        fault.code = regs.ALARM_ESTOP if kind == "estop" else rng.choice((regs.ALARM_SOFT_LIMIT, 3))
        if kind == "alarm" and rng.random() < 0.5:
            n = rng.randint(1, 40)
            emu.schedule_alarm(fault.code, n)
            fault.detail = f"alarm {fault.code} half-way through the {n}th next move"
        else:
            emu.raise_alarm(fault.code)
            fault.detail = f"alarm {fault.code} at once"
    elif kind == "hold":
        seconds = rng.uniform(0.05, 0.3)
        emu.hold_full(seconds)
        fault.detail = f"card held for {seconds:.2f} s"
        fault.t_recovered = time.monotonic() + seconds
    else:
        raise ValueError(f"unknown fault kind {kind!r}")


class CampaignAbortedError(RuntimeError):
    pass


def run_campaign(*, moves: int = 10_000, faults: int = 100, seed: int = 8060, budget: float | None = None,
                 minimum: int = 20, speed: float = 8.0, timeout: float = 0.5, delay: float = 1.2,
                 deadline: float = 600.0, kinds: tuple[str, ...] = KINDS, progress: Callable[[str], None] | None = None,
                 plan: tuple | None = None) -> CampaignResult:
    """Stream ``moves`` short moves (plus arcs, M functions, dwells) to an emulated card, injecting up to ``faults``
    faults of the given ``kinds`` (seeded: ``seed``) at random points, recovering from each, then compare what the
    card executed with the plan.

    ``budget`` (s): the time the faults may take (from each injection to the end of its recovery, a hold's wait
    included); a planned fault is left out (counted in ``skipped``) when the faults so far have used more
    than their share of it - except ``minimum`` of them, spread over the stream, which are always injected.  None
    injects all.  ``speed``: the emulator's speed factor;
    ``timeout``: the back-end's Modbus timeout (a delayed reply comes ``delay`` s late); ``deadline``: a watchdog
    stops the emulator after that many seconds, so nothing can hang.
    """
    say = progress or (lambda _text: None)
    machine, segments = plan or plan_campaign(moves, seed)
    t_start = time.monotonic()
    rng = random.Random(seed)
    n = len(segments)
    warm, tail = min(200, n // 10), min(400, n // 5)
    span = max(1, (n - tail - warm) // max(faults, 1))
    points = [warm + k * span + rng.randrange(span) for k in range(faults)] if faults else []
    plan_kinds: list[str] = []
    while len(plan_kinds) < faults:            # every kind once in each run of len(kinds) faults, shuffled
        block = list(kinds)
        rng.shuffle(block)
        plan_kinds += block
    required = set(range(0, faults, max(1, faults // max(minimum, 1)))[:minimum])
    done: list[Fault] = []
    unexpected: list[str] = []
    violations: list[str] = []
    skipped = 0
    armed: Fault | None = None
    emu = Emulator(port=0, speed=speed)
    emu.card = card = JournalCard(speed=speed, resolution=1000.0)
    aborted: list[str] = []

    def mark(name: str, detail: object = None) -> int:
        """A journal mark; returns the line of the segment the card has started."""
        def put(c: Card) -> int:
            c.journal.append(("mark", name, detail))
            tag = c.hr[c.watch]
            return segments[tag - 1].line if 0 < tag <= n else 0
        return int(emu.inspect(put))

    def watchdog() -> None:
        aborted.append(f"watchdog: the campaign ran past its {deadline:g} s deadline; emulator stopped")
        emu.stop()

    with emu:
        timer = threading.Timer(deadline, watchdog)
        timer.daemon = True
        timer.start()
        backend = InterpCncBackend(machine, port=emu.port, outputs=OUTPUTS, resolution=1000, timeout=timeout)
        try:
            backend.open()

            def handle(err: InterpCncError) -> None:
                """The operator: resume() after an alarm, reconnect_and_continue() after a link error."""
                nonlocal armed
                fault = armed
                for _attempt in range(8):
                    line_now = mark("alarm reported" if err.alarm else "link error reported", err.alarm)
                    if fault is None:
                        unexpected.append(str(err))
                    else:
                        fault.violations += _expect(fault, err, not fault.errors, line_now)
                        fault.errors.append(str(err))
                        fault.lines.append(err.line)
                        fault.alarms.append(err.alarm)
                    if aborted:
                        raise CampaignAbortedError(aborted[0])
                    try:
                        if err.alarm:
                            if err.alarm == regs.ALARM_ESTOP and "still active" in str(err):
                                emu.release_estop()          # the operator releases the button
                            mark("resume begin")
                            try:
                                backend.resume()
                            finally:
                                mark("resume end")
                        else:
                            backend.reconnect_and_continue()
                    except InterpCncError as again:
                        err = again
                        continue
                    if fault is not None:
                        fault.recoveries += 1
                        fault.t_recovered = time.monotonic()
                    armed = None
                    return
                raise CampaignAbortedError(f"no recovery after 8 attempts: {err}")

            next_point = 0
            for k, seg in enumerate(segments):
                if armed is not None and armed.kind == "hold" and time.monotonic() >= (armed.t_recovered or 0):
                    armed.waits = backend.stats["waits"] - armed.waits
                    armed = None
                while next_point < len(points) and points[next_point] <= k and armed is None:
                    fault = Fault(len(done) + skipped + 1, plan_kinds[next_point], "", k)
                    optional = next_point not in required
                    next_point += 1
                    spent = sum((f.t_recovered or f.t_injected) - f.t_injected for f in done)
                    late = budget is not None and optional and spent > budget * k / n
                    if late or k >= n - tail // 2:
                        skipped += 1
                        continue
                    fault.t_injected = time.monotonic()
                    fault.waits = backend.stats["waits"]
                    _inject(emu, fault, rng, delay)
                    done.append(fault)
                    armed = fault
                    if len(done) % 10 == 0:
                        say(f"  {len(done)} faults injected, segment {k}/{n}, {time.monotonic() - t_start:.1f} s")
                try:
                    backend.send(seg)
                except InterpCncError as err:
                    if not err.accepted:
                        violations.append(f"segment {k + 1} (line {seg.line}) refused: {err}")
                    handle(err)
            for _ in range(8):
                try:
                    backend.finish()
                    break
                except InterpCncError as err:
                    handle(err)
            if armed is not None and armed.kind == "hold":
                armed.waits = backend.stats["waits"] - armed.waits
                armed = None
            if armed is not None:
                violations.append(f"fault {armed.id} ({armed.detail}) never surfaced")
        except CampaignAbortedError as exc:
            aborted.append(str(exc))
        finally:
            timer.cancel()
            with contextlib.suppress(Exception):
                backend.close()
        log = emu.executed()
        journal = list(emu.inspect(lambda c: list(c.journal)))
        interrupted = list(emu.inspect(lambda c: list(c.aborted)))
        counters = {"overflows": card.overflows, "arc_errors": card.arc_errors, "underruns": card.underruns,
                    "discarded": card.discarded, "lag_events": card.lag_events, "requests": emu.requests}
    expected = expected_events(segments, backend)
    comparison = compare(expected, executed_events(log))
    rules, motion, after_report, in_alarm, discarded, acks, resumes = _alarm_discipline(journal)
    violations += rules
    for f in done:
        if f.kind != "hold" and not f.errors:
            violations.append(f"fault {f.id} ({f.detail}) raised no error")
        if f.kind == "hold" and f.errors:
            violations.append(f"fault {f.id} ({f.detail}): the back-end failed instead of waiting: {f.errors[0]}")
        violations += [f"fault {f.id} ({f.kind}: {f.detail}): {v}" for v in f.violations]
    kinds_count = Counter(e[0] for e in expected)
    return CampaignResult(
        segments=n, moves=kinds_count["move"], outputs=kinds_count["out"], dwells=kinds_count["dwell"],
        planned=faults, faults=done, skipped=skipped, comparison=comparison, unexpected=unexpected,
        violations=violations, motion_after_alarm=motion, sent_after_report=after_report,
        executed_in_alarm=in_alarm, discarded=discarded, acks=acks, resumes=resumes, card=counters,
        stats=dict(backend.stats),
        elapsed=time.monotonic() - t_start, speed=speed, aborted=aborted[0] if aborted else None, journal=journal,
        log=log, interrupted=interrupted)


def campaign_summary(r: CampaignResult) -> list[str]:
    """Markdown lines for the README."""
    c = r.comparison
    kinds = r.by_kind()
    by_kind = ", ".join(f"{k} {kinds[k]}" for k in KINDS if kinds[k])
    errors = sum(len(f.errors) for f in r.faults)
    lines = [
        f"- stream: {r.segments:,} segments ({r.moves:,} moves, {r.outputs} output actions, {r.dwells} dwells) "
        f"over Modbus TCP to the emulated card (x{r.speed:g} real time), {r.elapsed:.0f} s",
        f"- faults injected: {len(r.faults)} ({by_kind})"
        + (f", {r.skipped} planned ones left out to keep within the time budget" if r.skipped else ""),
        f"- errors raised to the caller: {errors}, each with the alarm or link message and the last block "
        f"started; broken promises (message, line, alarm discipline): {len(r.violations)}"
        + (f"; errors no injected fault explains: {len(r.unexpected)}" if r.unexpected else ""),
        f"- recoveries: {r.recoveries} (`resume()` after alarms, `reconnect_and_continue()` after link faults), "
        f"{r.stats.get('resyncs', 0)} resynchronisations, {r.card.get('requests', 0):,} Modbus requests",
        f"- segments lost: {c.lost}; duplicated: {c.duplicated}; executed in the planned order: "
        f"{'yes' if c.ordered else 'NO (' + str(c.difference) + ')'} (the card's executed log compared event by "
        f"event with the plan: {c.expected:,} moves, output actions and dwells); moves stopped half-way by an alarm "
        f"or a stop and finished from where they stood: {r.interrupted_moves}",
        f"- motion commands the card accepted after an alarm before `resume()`: {r.motion_after_alarm}; commands "
        f"sent after the alarm was reported: {r.sent_after_report}; commands written between an alarm and the next "
        f"status poll (discarded by the card, re-sent after `resume()`): {r.discarded}",
    ]
    if r.aborted:
        lines.append(f"- ABORTED: {r.aborted}")
    return lines


# ==================================================================== (a) fuzzing
FUZZ_SUITES = (("parser", "tests/test_fuzz.py"), ("interpreter", "tests/test_fuzz_interp.py"),
               ("planner", "tests/test_fuzz_plan.py"))
_PHASE = re.compile(r"- during (\w+) phase.*?\n.*?\n\s*- (\d+) passing, (\d+) failing, and (\d+) invalid", re.S)


# ---- pytest plugin hooks: active only in the pytest subprocess started by run_fuzz (`-p robustness`)
_FAILED: list[str] = []


def pytest_configure(config) -> None:
    examples = os.environ.get("ROBUSTNESS_EXAMPLES")
    if examples:
        from hypothesis import settings
        settings.register_profile("robustness", max_examples=int(examples), deadline=None)
        settings.load_profile("robustness")
    config._robustness = {"tests": {}, "failed": []}


def pytest_runtest_teardown(item) -> None:
    stats = getattr(item, "hypothesis_statistics", None)
    if stats:
        phases = {m[0]: tuple(map(int, m[1:])) for m in _PHASE.findall(stats)}
        item.config._robustness["tests"][item.nodeid] = phases


def pytest_runtest_logreport(report) -> None:
    if report.failed:
        _FAILED.append(f"{report.nodeid} ({report.when})")


def pytest_sessionfinish(session) -> None:
    out = os.environ.get("ROBUSTNESS_STATS")
    if out and hasattr(session.config, "_robustness"):
        data = session.config._robustness
        data["failed"] = list(_FAILED)
        Path(out).write_text(json.dumps(data))


@dataclass
class FuzzResult:
    suite: str
    path: str
    properties: int
    inputs: int                        # valid inputs generated (passing + failing), every phase but shrinking
    invalid: int
    failed: list[str]
    seconds: float
    summary: str


def run_fuzz(examples: int, suites=FUZZ_SUITES, timeout: float = 1800.0) -> list[FuzzResult]:
    """Each suite in a pytest subprocess with ``examples`` per property (the ``slow`` long variants left out)."""
    out = []
    for name, path in suites:
        with tempfile.TemporaryDirectory() as tmp:
            stats_file = Path(tmp) / "stats.json"
            env = dict(os.environ, ROBUSTNESS_EXAMPLES=str(examples), ROBUSTNESS_STATS=str(stats_file),
                       PYTHONPATH=os.pathsep.join([str(ROOT / "benchmarks"), os.environ.get("PYTHONPATH", "")]))
            t0 = time.monotonic()
            proc = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "robustness", "-p", "no:cacheprovider",
                                   "-m", "not slow", path], cwd=ROOT, env=env, capture_output=True, text=True,
                                  timeout=timeout, check=False)
            seconds = time.monotonic() - t0
            data = json.loads(stats_file.read_text()) if stats_file.exists() else {"tests": {}, "failed": []}
        tail = [ln for ln in proc.stdout.splitlines() if re.search(r"\d+ (passed|failed)", ln)]
        inputs = invalid = 0
        for phases in data["tests"].values():
            for phase, (passing, failing, bad) in phases.items():
                if phase != "shrink":
                    inputs += passing + failing
                    invalid += bad
        failed = list(data["failed"])
        if proc.returncode not in (0, 1) and not failed:
            failed = [f"pytest exited {proc.returncode}: {proc.stderr.strip()[-300:] or proc.stdout.strip()[-300:]}"]
        out.append(FuzzResult(name, path, len(data["tests"]), inputs, invalid, failed, seconds,
                              tail[-1].strip("= ") if tail else ""))
    return out


# ==================================================================== (b) runaway guards
GIGANTIC_LINES = 10**9


def _runaway_programs(tmp: Path) -> dict[str, tuple[str, str, dict]]:
    """name -> (description, program text or "<generated>", machine options)."""
    (tmp / "REC.nc").write_text("P100=P100+1\n#CALL REC.nc\nM17\n")
    (tmp / "RECL.nc").write_text("P100=P100+1\nL RECL.nc\nM17\n")
    subs = {"subroutine_paths": [str(tmp)]}
    return {
        "while": ("`$WHILE 1==1` ... `$ENDWHILE` (counter only)", "P1=0\n$WHILE 1==1\nP1=P1+1\n$ENDWHILE\nM30\n", {}),
        "call": ("global subroutine calling itself with `#CALL`", "P100=0\n#CALL REC.nc\nM30\n", subs),
        "l": ("global subroutine calling itself with `L`", "P100=0\nL RECL.nc\nM30\n", subs),
        "nr": ("`G91 G1 X0.001 F1000 NR1000000000`", "G91 G1 X0.001 F1000 NR1000000000\nM30\n", {}),
        "rpt": ("`#RPT [N10, N20, 1000000000]` over two moves",
                "N10: G91 G1 X0.001 F1000\nN20: G1 X-0.001\n#RPT [N10, N20, 1000000000]\nM30\n", {}),
        "goto": ("endless `$GOTO` loop over two moves", "N10: G91 G1 X0.001 F1000\nG1 X-0.001\n$GOTO N10\nM30\n", {}),
        "msg": ("endless `$GOTO` loop over a `#MSG` (a note per pass)", "N10: #MSG [\"pass\"]\n$GOTO N10\nM30\n", {}),
        "gigantic": (f"a generated program of {GIGANTIC_LINES:,} G1 lines, streamed line by line", "<generated>", {}),
    }


def _gigantic_lines():
    for k in range(GIGANTIC_LINES):
        yield f"G90 G1 X{k % 1000 * 0.01:.2f} Y{k // 1000 % 1000 * 0.01:.2f} F3000"
    yield "M30"


def runaway_case(name: str, limits: dict) -> dict:
    """Run one runaway program through ``fagorcnc.interpret`` (streamed, nothing planned) in this process."""
    import resource

    with tempfile.TemporaryDirectory() as tmp:
        _, text, machine = _runaway_programs(Path(tmp))[name]
        machine = dict(machine, limits=limits)
        t0 = time.perf_counter()
        if text == "<generated>":
            run = fagorcnc.Run(_gigantic_lines(), "<generated>", fagorcnc.load_machine(machine))
        else:
            run = fagorcnc.interpret(text, machine)
        records = sum(1 for _ in run)
        seconds = time.perf_counter() - t0
        errors = [(d.code, d.message) for d in run.diagnostics if d.is_error]
    return {"name": name, "records": records, "seconds": seconds, "errors": errors,
            "rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}


@dataclass
class RunawayResult:
    name: str
    description: str
    limits: dict
    codes: list[str]
    message: str
    records: int
    seconds: float
    rss_mib: float
    note: str = ""


def run_runaway(max_blocks: int, max_loop: int | None, max_seconds: float,
                timeout: float = 900.0) -> list[RunawayResult]:
    """Every runaway program in its own process (a hang is a timeout, not a stuck benchmark).

    ``max_loop``: None keeps the default ``max_loop_iterations``; ``max_blocks`` replaces the default 100 000 000
    for the gigantic program, which only the block limit stops with the defaults (the time the default would
    take is extrapolated); ``max_seconds`` is the time limit of the endless ``$GOTO`` loops (none by default,
    ``fagorcnc check`` applies 120 s)."""
    defaults = fagorcnc.load_machine(None).limits
    with tempfile.TemporaryDirectory() as tmp:
        programs = _runaway_programs(Path(tmp))
    out = []
    for name, (description, _text, _machine) in programs.items():
        limits: dict = {}
        if name == "while" and max_loop is not None:
            limits["max_loop_iterations"] = max_loop
        if name in ("goto", "msg"):
            limits["max_seconds"] = max_seconds
        if name == "gigantic":
            limits["max_blocks"] = max_blocks
        cmd = [sys.executable, str(Path(__file__).resolve()), "--runaway-case", name, "--limits", json.dumps(limits)]
        try:
            proc = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=timeout, check=False)
            data = json.loads(proc.stdout.strip().splitlines()[-1]) if proc.returncode == 0 else None
        except subprocess.TimeoutExpired:
            data, proc = None, None
        if data is None:
            why = (f"timed out after {timeout:g} s" if proc is None
                   else f"exited {proc.returncode}: {proc.stderr[-300:]}")
            out.append(RunawayResult(name, description, limits, [], why, 0, timeout, 0.0))
            continue
        codes = [c for c, _ in data["errors"]]
        note = ""
        if "max_blocks" in limits and codes == ["INT080"] and data["seconds"] > 0:
            rate = max_blocks / data["seconds"]
            note = (f"{rate:,.0f} blocks/s: the default {defaults.max_blocks:,} would stop it after about "
                    f"{defaults.max_blocks / rate / 60:.0f} min")
        out.append(RunawayResult(name, description, limits, codes, data["errors"][0][1] if data["errors"] else "",
                                 data["records"], data["seconds"], data["rss_mib"], note))
    return out


# ==================================================================== (d) file safety
def run_file_safety(timeout: float = 600.0) -> tuple[int, int, float, str]:
    """tests/test_file_safety.py: (passed, failed, seconds, pytest's summary line)."""
    t0 = time.monotonic()
    proc = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "tests/test_file_safety.py"],
                          cwd=ROOT, capture_output=True, text=True, timeout=timeout, check=False)
    seconds = time.monotonic() - t0
    line = next((ln for ln in reversed(proc.stdout.splitlines()) if re.search(r"\d+ (passed|failed)", ln)), "")
    passed = int(m.group(1)) if (m := re.search(r"(\d+) passed", line)) else 0
    failed = sum(int(x) for x in re.findall(r"(\d+) (?:failed|error)", line))
    if proc.returncode not in (0, 1) and not failed:
        failed = 1
    return passed, failed, seconds, line.strip("= ")


# ==================================================================== the report
def _duration(seconds: float) -> str:
    return f"{seconds:.0f} s" if seconds < 120 else f"{int(seconds // 60)} min {seconds % 60:02.0f} s"


def markdown(args, fuzz, runaway, campaign, safety, total: float) -> str:
    out = [f"<!-- robustness figures: `python benchmarks/robustness.py{' --quick' if args.quick else ''}` "
           f"({os.cpu_count()} cores, {_duration(total)}) -->"]
    if fuzz is not None:
        out += ["", f"**Fuzzing** (hypothesis, {args.examples:,} examples per property, the suites' `slow` "
                "variants left out; a crash is a failing property):", "",
                "| suite | properties | inputs tried | crashes | time |", "|---|---:|---:|---:|---:|"]
        for f in fuzz:
            out.append(f"| {f.suite} (`{f.path}`) | {f.properties} | {f.inputs:,} | {len(f.failed)} | "
                       f"{_duration(f.seconds)} |")
        out.append(f"| total | {sum(f.properties for f in fuzz)} | {sum(f.inputs for f in fuzz):,} | "
                   f"{sum(len(f.failed) for f in fuzz)} | {_duration(sum(f.seconds for f in fuzz))} |")
        for f in fuzz:
            out += [f"- crash: {x}" for x in f.failed[:5]]
    if runaway is not None:
        out += ["", "**Runaway guards** (`fagorcnc.interpret`, streamed, each program in its own process; limits "
                "not shown are the defaults):", "",
                "| program | limit | stopped by | records | time | peak RSS |", "|---|---|---|---:|---:|---:|"]
        for r in runaway:
            limit = ", ".join(f"`{k} = {v:,}`" for k, v in r.limits.items()) or "defaults"
            code = ", ".join(r.codes) or "nothing"
            out.append(f"| {r.description} | {limit} | {code} {r.message} | {r.records:,} | {r.seconds:.1f} s | "
                       f"{r.rss_mib:.0f} MiB |")
        out += [f"- {r.name}: {r.note}" for r in runaway if r.note]
    if campaign is not None:
        out += ["", f"**Link faults** (`tests/test_fault_campaign.py`, here with {campaign.planned} faults, seed "
                f"{args.seed}; the operator recovers after each):", ""]
        out += campaign_summary(campaign)
    if safety is not None:
        passed, failed, seconds, _summary = safety
        out += ["", f"**File safety** (`tests/test_file_safety.py`): {passed} passed, {failed} failed "
                f"({seconds:.0f} s)."]
    out += ["", f"Total run time: {_duration(total)}."]
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="small budgets (about a minute)")
    ap.add_argument("--examples", type=int, help="hypothesis examples per property (default 1000, quick 100)")
    ap.add_argument("--faults", type=int, help="faults in the link campaign (default 100, quick 20)")
    ap.add_argument("--segments", type=int, default=10_000, help="moves in the campaign's stream (default 10000)")
    ap.add_argument("--seed", type=int, default=8060, help="seed of the campaign (default 8060)")
    ap.add_argument("--max-blocks", type=int, help="max_blocks for the programs only the block limit stops "
                    "(default 1000000, quick 100000; the machine default is 100000000)")
    ap.add_argument("--sections", default="fuzz,runaway,faults,files",
                    help="comma-separated subset of fuzz,runaway,faults,files")
    ap.add_argument("--runaway-case", help=argparse.SUPPRESS)
    ap.add_argument("--limits", default="{}", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.runaway_case:
        print(json.dumps(runaway_case(args.runaway_case, json.loads(args.limits))))
        return 0
    args.examples = args.examples or (100 if args.quick else 1000)
    args.faults = args.faults if args.faults is not None else (20 if args.quick else 100)
    max_blocks = args.max_blocks or (100_000 if args.quick else 1_000_000)
    sections = set(args.sections.split(","))
    logging.getLogger("pymodbus").setLevel(logging.CRITICAL)

    def say(text: str) -> None:
        print(text, file=sys.stderr, flush=True)

    t0 = time.monotonic()
    fuzz = runaway = campaign = safety = None
    if "fuzz" in sections:
        say(f"(a) fuzzing, {args.examples} examples per property ...")
        fuzz = run_fuzz(args.examples)
        for f in fuzz:
            say(f"  {f.suite}: {f.inputs} inputs, {len(f.failed)} failures, {f.seconds:.0f} s ({f.summary})")
    if "runaway" in sections:
        say(f"(b) runaway programs (max_blocks {max_blocks:,}) ...")
        runaway = run_runaway(max_blocks, 100_000 if args.quick else None, 2.0 if args.quick else 10.0)
        for r in runaway:
            say(f"  {r.name}: {r.codes} after {r.records} records, {r.seconds:.1f} s")
    if "faults" in sections:
        say(f"(c) link-fault campaign, {args.faults} faults over {args.segments} moves ...")
        campaign = run_campaign(moves=args.segments, faults=args.faults, seed=args.seed, progress=say)
        for v in campaign.violations[:10]:
            say(f"  violation: {v}")
        for e in campaign.unexpected[:5]:
            say(f"  unexplained error: {e}")
    if "files" in sections:
        say("(d) file safety ...")
        safety = run_file_safety()
    total = time.monotonic() - t0
    print(markdown(args, fuzz, runaway, campaign, safety, total))
    bad = (any(f.failed for f in fuzz or ()) or any(r.codes == [] for r in runaway or ())
           or (campaign is not None and (campaign.violations or campaign.comparison.lost or campaign.aborted
                                         or not campaign.comparison.ordered or campaign.comparison.duplicated))
           or (safety is not None and safety[1]))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
