"""An InterpCNC V3 emulator: a real Modbus server (pymodbus) around the card model of :mod:`.card`.

It listens on 127.0.0.1 by default (TCP framing, or RTU framing over TCP so
that a serial client can reach it through pyserial's ``socket://`` URLs) and
runs in a background thread with its own asyncio loop::

    with Emulator(port=0, speed=50) as emu:       # port 0: a free port, see emu.port
        ...                                       # stream to 127.0.0.1:emu.port
        emu.executed()                            # the executed log

Every request first brings the card model up to date (time is lazy), so the
registers a client reads are current; a background tick keeps time moving
between requests.  Fault injection for tests: :meth:`Emulator.drop_connection`,
:meth:`fail_next` (Modbus exception replies), :meth:`delay_next` (the
request is applied, the reply comes late), :meth:`hold_full` (the card
stops consuming: the buffer fills up), :meth:`raise_alarm` / :meth:`schedule_alarm`; card options
``report_full_after`` (IR 3000 reads 0 for ever after that many buffered commands) and ``extra_moving``
(axes-moving bits that never clear) make a card that misbehaves.

**Lock-step** (``clock=VirtualClock(request_time)``): the card's time moves only
by ``request_time`` per Modbus request and by the sleeps of a client sharing the
clock (``backend.clock = clock; backend.sleep = clock.sleep``), so "does the
stream keep up at N x real time over a link of that round trip?" has an answer
that does not depend on how loaded the test machine is.  Functions 22 (mask
write) and 23 (read/write) write holding registers like 6 and 16: their writes
reach the card model (a command at 2000 included).

:class:`EmulatorProcess` runs the same emulator in a child process (as a
real card runs beside the PC, without sharing the client's interpreter).

``python -m fagorcnc.backends.interpcnc.emulator --port 5020 --speed 1``
(or ``fagorcnc emulate`` once wired into the CLI) runs it until Ctrl-C.
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import math
import multiprocessing
import threading
import time
from collections.abc import Callable

from pymodbus.constants import ExcCodes
from pymodbus.framer import FramerType
from pymodbus.server import ModbusTcpServer
from pymodbus.simulator import DataType, SimData, SimDevice

from . import registers as regs
from .card import Card, Executed

_READS = {1: "c", 2: "d", 3: "h", 4: "i"}
_WRITES = {5: "c", 15: "c", 6: "h", 16: "h"}
#: functions that read and write holding registers: pymodbus calls the action once to read, once with the values
_READ_WRITE = (22, 23)


class VirtualClock:
    """Seconds that pass only when told: ``request_time`` for each Modbus request the emulator serves, and the
    duration of every :meth:`sleep` of a client sharing it (thread-safe; callable like ``time.monotonic``)."""

    def __init__(self, request_time: float = 0.0) -> None:
        if not request_time >= 0:
            raise ValueError("request_time must be 0 or more seconds")
        self.request_time = request_time
        self._now = 0.0
        self._lock = threading.Lock()

    def __call__(self) -> float:
        return self._now

    def advance(self, seconds: float) -> None:
        with self._lock:
            self._now += max(seconds, 0.0)

    def sleep(self, seconds: float) -> None:
        """A client's wait: the time passes at once."""
        self.advance(seconds)


class Emulator:
    """An emulated card served over Modbus (see the module docstring).

    ``speed`` runs the motion faster than real time; ``framer`` is "socket"
    (Modbus TCP) or "rtu" (RTU frames over the TCP stream); ``unit`` = 0
    answers every unit id.  Other keywords go to :class:`~.card.Card`
    (``buffer_size``, ``planner_size``, ``rapid_speed`` mm/min,
    ``resolution`` pulses/mm, ``limits`` {axis: (min, max)}, ``watch_register``, ``keep_buffers_on_alarm``).
    """

    def __init__(self, host: str = "127.0.0.1", port: int = 0, *, speed: float = 1.0, framer: str = "socket",
                 unit: int = 0, tick: float = 0.002, clock: VirtualClock | None = None, **card_options) -> None:
        if framer not in ("socket", "rtu"):
            raise ValueError("framer must be 'socket' or 'rtu'")
        self.host, self.port, self.framer, self.unit, self.tick = host, port, framer, unit, tick
        self.virtual = clock
        if clock is not None:   # virtual time never lags: nothing to drop (see card.Card.max_lag)
            card_options = {"clock": clock, "max_lag": math.inf, **card_options}
        self.card = Card(speed=speed, **card_options)
        self.lock = threading.Lock()
        self.requests = 0
        self._fail: list = [0, ExcCodes.DEVICE_FAILURE, True, 0]     # [count, code, writes only, let pass first]
        self._delay: list = [0, 0.0, True, 0]                        # [count, seconds, writes only, let pass first]
        self._drop_after: int | None = None
        self._loop: asyncio.AbstractEventLoop | None = None
        self._server: ModbusTcpServer | None = None
        self._thread: threading.Thread | None = None
        self._ticker: asyncio.Task | None = None

    # ------------------------------------------------------------ life cycle
    def start(self, timeout: float = 5.0) -> Emulator:
        """Start serving in a background thread; returns when listening (``port`` is then the real port)."""
        ready = threading.Event()
        errors: list[BaseException] = []
        self._loop = asyncio.new_event_loop()

        def run() -> None:
            asyncio.set_event_loop(self._loop)
            try:
                self._loop.run_until_complete(self._listen())
            except BaseException as exc:   # reported to start()
                errors.append(exc)
                ready.set()
                return
            ready.set()
            self._loop.run_forever()
            self._loop.run_until_complete(self._loop.shutdown_asyncgens())
            self._loop.close()

        self._thread = threading.Thread(target=run, name=f"interpcnc-emulator:{self.port}", daemon=True)
        self._thread.start()
        if not ready.wait(timeout) or errors:
            self.stop()
            raise RuntimeError(f"the InterpCNC emulator could not listen on {self.host}:{self.port}: "
                               f"{errors[0] if errors else 'timeout'}")
        return self

    async def _listen(self) -> None:
        device = SimDevice(id=self.unit, action=self._action, simdata=(
            [SimData(0, count=512, values=False, datatype=DataType.BITS)],
            [SimData(0, count=400, values=False, datatype=DataType.BITS)],
            [SimData(0, count=65535, datatype=DataType.REGISTERS)],
            [SimData(0, count=65535, datatype=DataType.REGISTERS)],
        ))
        framer = FramerType.RTU if self.framer == "rtu" else FramerType.SOCKET
        self._server = ModbusTcpServer(device, address=(self.host, self.port), framer=framer)
        await self._server.serve_forever(background=True)
        self.port = self._server.transport.sockets[0].getsockname()[1]
        self._ticker = asyncio.create_task(self._tick())

    async def _tick(self) -> None:
        while True:
            await asyncio.sleep(self.tick)
            with self.lock:
                self.card.advance()

    def stop(self, timeout: float = 5.0) -> None:
        """Stop serving and join the thread (idempotent)."""
        loop, thread = self._loop, self._thread
        if loop is None or thread is None:
            return
        if loop.is_running():
            async def shutdown() -> None:
                if self._server is not None:
                    for conn in list(self._server.active_connections.values()):
                        conn.close()
                    await self._server.shutdown()
                others = [t for t in asyncio.all_tasks() if t is not asyncio.current_task()]
                for task in others:              # the ticker, replies still delayed by a fault
                    task.cancel()
                await asyncio.gather(*others, return_exceptions=True)
            with contextlib.suppress(Exception):
                asyncio.run_coroutine_threadsafe(shutdown(), loop).result(timeout)
            loop.call_soon_threadsafe(loop.stop)
        thread.join(timeout)
        self._loop = self._thread = None

    def __enter__(self) -> Emulator:
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()

    # ------------------------------------------------------------ Modbus
    async def _action(self, fc: int, start: int, address: int, count: int, registers: list,
                      values: list | None) -> ExcCodes | None:
        is_write = fc in _WRITES or (fc in _READ_WRITE and values is not None)
        # 22 reads then writes, 23 writes then reads: one request, two calls
        second = (fc == 23 and values is None) or (fc == 22 and values is not None)
        if self.virtual is not None and not second:
            self.virtual.advance(self.virtual.request_time)
        with self.lock:
            self.requests += not second
            if self._due(self._fail, is_write):
                return self._fail[1]
            touches_command = (is_write and fc not in (5, 15)) and address <= regs.HR_COMMAND < address + count
            if touches_command and self._drop_after is not None:
                if self._drop_after == 0:
                    self._drop_after = None
                    self._drop()
                    return ExcCodes.DEVICE_FAILURE
                self._drop_after -= 1
            card = self.card
            card.clients = len(self._server.active_connections) if self._server else 0
            if is_write:
                code = self._write(fc, address, list(values or []))
                if code is not None:
                    return ExcCodes(code)
            else:
                card.advance()
                card.refresh()
                self._read(fc, start, address, count, registers)
            delay = self._delay[1] if self._due(self._delay, is_write) else 0.0
        if delay:
            await asyncio.sleep(delay)
        return None

    @staticmethod
    def _due(fault: list, is_write: bool) -> bool:
        """Whether a fault armed by fail_next/delay_next strikes this request (and count it)."""
        if fault[0] <= 0 or not (is_write or not fault[2]):
            return False
        if fault[3] > 0:
            fault[3] -= 1
            return False
        fault[0] -= 1
        return True

    def _write(self, fc: int, address: int, values: list) -> int | None:
        if fc in (5, 15):                       # coils 0-95: digital outputs (L239)
            for k, v in enumerate(values):
                if address + k < 256:
                    self.card.outputs[address + k] = bool(v)
            return None
        return self.card.write(address, [int(v) for v in values])

    def _read(self, fc: int, start: int, address: int, count: int, registers: list) -> None:
        card = self.card
        if fc in (3, 4, *_READ_WRITE):
            image = card.ir if fc == 4 else card.hr
            registers[address - start:address - start + count] = image[address:address + count]
            return
        bits = card.outputs if fc == 1 else card.inputs + self._status_bits()
        first = address // 16 - start
        for k in range((address % 16 + count + 15) // 16):
            base = (address // 16 + k) * 16
            registers[first + k] = sum(1 << b for b in range(16) if base + b < len(bits) and bits[base + b])

    def _status_bits(self) -> list[bool]:
        word = self.card.ir[regs.IR_STATUS_BITS]
        return [bool(word >> k & 1) for k in range(16)]

    def _drop(self) -> None:
        if self._server is not None:
            for conn in list(self._server.active_connections.values()):
                conn.close()

    # ------------------------------------------------------------ faults (thread-safe)
    def drop_connection(self, after_commands: int = 0) -> None:
        """Close the client connections instead of accepting the command write number ``after_commands + 1``
        (counted from now); the dropped command is not applied."""
        with self.lock:
            self._drop_after = after_commands

    def drop_now(self) -> None:
        """Close every client connection at once."""
        if self._loop is not None:
            self._loop.call_soon_threadsafe(self._drop)

    def fail_next(self, n: int = 1, code: ExcCodes = ExcCodes.DEVICE_FAILURE, *, writes_only: bool = True,
                  after: int = 0) -> None:
        """Answer the next ``n`` requests (writes only by default) with Modbus exception ``code``, not applied;
        ``after``: let that many such requests through first."""
        with self.lock:
            self._fail = [n, code, writes_only, after]

    def delay_next(self, n: int = 1, seconds: float = 1.0, *, writes_only: bool = True, after: int = 0) -> None:
        """Apply the next ``n`` requests at once but answer them ``seconds`` late (a reply lost in transit);
        ``after``: let that many such requests through first."""
        with self.lock:
            self._delay = [n, seconds, writes_only, after]

    def hold_full(self, seconds: float) -> None:
        """Stop consuming commands for ``seconds``: a streaming client fills the buffer and must wait."""
        with self.lock:
            self.card.hold_full(seconds)

    def raise_alarm(self, code: int) -> None:
        """Raise alarm ``code`` now (e.g. 2 soft limit, 10 emergency stop): motion stops, buffers purged (unless the
        card was made with ``keep_buffers_on_alarm``)."""
        with self.lock:
            self.card.advance()
            self.card.raise_alarm(code)

    def schedule_alarm(self, code: int, move: int) -> None:
        """Raise alarm ``code`` half-way through the ``move``-th move started from now."""
        with self.lock:
            self.card.schedule_alarm(code, move)

    def set_speed(self, speed: float) -> None:
        """Change the motion speed factor (time already run keeps its factor)."""
        if speed <= 0:
            raise ValueError("speed factor must be positive")
        with self.lock:
            self.card.advance()
            self.card.speed = speed

    def release_estop(self) -> None:
        with self.lock:
            self.card.release_estop()

    # ------------------------------------------------------------ inspection (thread-safe)
    def executed(self) -> list[Executed]:
        """A copy of the executed log."""
        with self.lock:
            self.card.advance()
            return list(self.card.log)

    def inspect(self, fn: Callable[[Card], object]) -> object:
        """Run ``fn(card)`` under the lock (for tests reading several values consistently)."""
        with self.lock:
            self.card.advance()
            return fn(self.card)

    def wait_idle(self, timeout: float = 10.0) -> bool:
        """Wait until nothing is queued or moving; False on timeout."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            with self.lock:
                self.card.advance()
                c = self.card
                if not c.queue and not c.planner and c.jog is None:
                    return True
            time.sleep(0.005)
        return False


def report(emu: Emulator) -> dict:
    """The emulator's executed log and counters, as plain data."""
    def take(card: Card) -> dict:
        return {"log": list(card.log), "aborted": list(card.aborted), "underruns": card.underruns,
                "overflows": card.overflows, "discarded": card.discarded, "arc_errors": card.arc_errors,
                "outputs": list(card.outputs), "analog": list(card.analog), "time": card.time,
                "requests": emu.requests, "lag_events": card.lag_events}
    return emu.inspect(take)


class EmulatorProcess:
    """The emulator in a child process (spawned), so that it does not share the client's interpreter lock.

    Like any spawned process, it needs the ``if __name__ == "__main__":``
    guard in the script that starts it.

    A real card runs beside the client; in one Python process the two would
    compete for the GIL and the client's throughput would depend on the
    emulator's load.  Keywords are those of :class:`Emulator`.  :meth:`call`
    runs an :class:`Emulator` method in the child (fault injection);
    :meth:`stop` returns :func:`report`.
    """

    def __init__(self, **options) -> None:
        self.options = options
        self.port = 0
        self._conn = None
        self._proc = None

    def start(self, timeout: float = 30.0) -> EmulatorProcess:
        ctx = multiprocessing.get_context("spawn")
        self._conn, child = ctx.Pipe()
        self._proc = ctx.Process(target=_child, args=(child, self.options), name="interpcnc-emulator", daemon=True)
        self._proc.start()
        child.close()
        try:
            if not self._conn.poll(timeout):
                raise EOFError
            answer = self._conn.recv()
        except (EOFError, OSError):
            answer = "the emulator process did not start (scripts need an `if __name__ == '__main__':` guard)"
        if isinstance(answer, str):
            self.kill()
            raise RuntimeError(answer)
        self.port = answer
        return self

    def call(self, method: str, *args, timeout: float = 10.0):
        """Run ``Emulator.<method>(*args)`` in the child and return its (picklable) result."""
        self._conn.send((method, *args))
        if not self._conn.poll(timeout):
            raise RuntimeError(f"the emulator process did not answer {method}")
        return self._conn.recv()

    def stop(self, timeout: float = 10.0) -> dict:
        """Stop the child; returns its :func:`report`."""
        try:
            return self.call("stop", timeout=timeout)
        finally:
            self.kill(timeout)

    def kill(self, timeout: float = 5.0) -> None:
        if self._proc is not None:
            self._proc.join(timeout)
            if self._proc.is_alive():
                self._proc.kill()
                self._proc.join(timeout)
            self._proc = None
        if self._conn is not None:
            self._conn.close()
            self._conn = None

    def __enter__(self) -> EmulatorProcess:
        return self.start()

    def __exit__(self, *exc) -> None:
        if self._proc is not None:
            with contextlib.suppress(Exception):
                self.stop()
        self.kill()


def _child(conn, options: dict) -> None:
    try:
        emu = Emulator(**options).start()
    except Exception as exc:   # reported to the parent
        conn.send(f"{type(exc).__name__}: {exc}")
        return
    conn.send(emu.port)
    try:
        while True:
            try:
                method, *args = conn.recv()
            except EOFError:
                return
            if method == "stop":
                conn.send(report(emu))
                return
            conn.send(report(emu) if method == "report" else getattr(emu, method)(*args))
    finally:
        emu.stop()


def main(argv: list[str] | None = None) -> int:
    """``fagorcnc emulate``: serve an emulated InterpCNC until interrupted."""
    ap = argparse.ArgumentParser(prog="fagorcnc emulate", description="Serve an emulated SOPROLEC InterpCNC V3 "
                                 "(Modbus TCP, or RTU framing over TCP with --rtu).")
    ap.add_argument("--host", default="127.0.0.1", help="address to bind (default 127.0.0.1)")
    ap.add_argument("--port", type=int, default=5020, help="TCP port (default 5020; the card itself uses 502)")
    ap.add_argument("--speed", type=float, default=1.0, help="motion speed factor (default 1 = real time)")
    ap.add_argument("--rtu", action="store_true", help="RTU framing (reach it with serial=\"socket://HOST:PORT\")")
    ap.add_argument("--resolution", type=float, default=1000.0, help="pulses per mm of every axis (default 1000)")
    ap.add_argument("--rapid", type=float, default=10000.0, help="rapid speed, mm/min (default 10000)")
    args = ap.parse_args(argv)
    if args.speed <= 0:
        ap.error("--speed must be positive")
    emu = Emulator(args.host, args.port, speed=args.speed, framer="rtu" if args.rtu else "socket",
                   resolution=args.resolution, rapid_speed=args.rapid)
    try:
        emu.start()
    except RuntimeError as exc:
        print(exc)
        return 1
    print(f"InterpCNC emulator listening on {emu.host}:{emu.port} ({'RTU' if args.rtu else 'TCP'} framing, "
          f"speed x{args.speed:g}); Ctrl-C to stop", flush=True)
    try:
        while True:
            time.sleep(0.5)
    except KeyboardInterrupt:
        pass
    finally:
        emu.stop()
    return 0


if __name__ == "__main__":   # pragma: no cover
    raise SystemExit(main())
