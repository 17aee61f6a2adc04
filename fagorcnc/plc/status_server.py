"""Status server: the CNC state for a PLC over Modbus TCP, in the RosettaCNC layout (seed 004).

While a program runs, a :class:`StatusServer` is a Modbus TCP *slave* that a
PLC (the master) polls for positions, state, alarm and the current line, and
through which it can raise alarms and warnings.  It runs in two background
threads (the pymodbus event loop and a ~20 Hz poller of ``backend.status()``)
and uses nothing of the back-end but ``status()`` and ``raise_alarm(code,
message)`` -- or ``stop()`` when the back-end has no ``raise_alarm`` -- so it
serves the simulator and the InterpCNC card alike::

    be = SimulatorBackend(machine, realtime=1.0)
    with StatusServer(be, machine, port=5020, holding_writes=True) as server:
        report = fagorcnc.run("part.nc", machine, backend=be, progress=server.progress_callback())
        server.finished(report.ok)

**Addressing.**  The table below uses the seed's 1-based reference numbers
(seed 004 L48-L168).  On the wire, register 30001 is *input register address 0*
(function 04) and 40001 is *holding register address 0* (functions 03, 06, 16,
22, 23): ``address = reference - 30001`` or ``reference - 40001``.  The input
block is 30001-30097 and the holding block 40001-40034; the gaps of the seed's
table (30038-30046, 30095, 40017, 40033) read as 0 (30035-30037: fagorcnc's end of
run, below).  Coils and discrete inputs do not exist (exception 01).  The server answers every unit id unless
``device_id`` is set (RosettaCNC lets the slave id be configured, seed 004 L20).

======================  =========  ==============================================================
register                size       content
======================  =========  ==============================================================
30001                   W          interface level: 1 (seed 004 L24-L26, L49)
30002                   W          fagorcnc version: high byte major, low byte minor (L51-L53)
30003                   L          serial number (``serial_number``, default 0) (L55)
30005, 30007, 30009     L          machine position X, Y, Z, µm (L57-L59)
30011 ... 30021         L          target position X Y Z A B C, µm or 1/1000 degree (L61-L66)
30023 ... 30033         L          program position X Y Z A B C (L68-L73)
30035                   W          fagorcnc: end reason of the last run, :data:`END_REASONS` (0 while running)
30036                   L          fagorcnc: line the last run ended at (0 when it does not apply)
30047 ... 30057         L          working offset X Y Z A B C (L75-L80)
30059 ... 30069         L          actual velocity X Y Z A B C, mm/min or degree/min (L82-L87)
30071                   W          main state, :class:`MainState` (L89-L105)
30072                   W          b0 all axes homed, b1 program ended successfully (L107-L109)
30073, 30074, 30075     W          alarm code, alarm info A, alarm info B (L111-L113)
30076                   L          current program line (L115)
30078                   W          b0-b7 buffer level %, b8-b15 program transferred % (L117)
30079                   W          virtual outputs: 0 (fagorcnc has none) (L119)
30080 ... 30094         L          shared memory G100 P1000: 0 (not in the Fagor dialect) (L125-L132)
30096                   L          current G-code command: 0 (the seed does not define its encoding) (L134)
40001 ... 40008         W          custom alarms 1-8: non-zero raises (L137-L144)
40009 ... 40016         W          custom warnings 1-8: non-zero signals (L146-L153)
40018 ... 40032         L          shared memory written by the PLC: stored only (L155-L162)
40034                   W          virtual inputs: stored only (L164)
======================  =========  ==============================================================

**Values.**  Positions are machine coordinates in µm (mm/1000; rotary axes in
1/1000 degree) and velocities mm/min (degree/min), rounded to the nearest
integer, signed 32-bit two's complement.  *Program position* = machine position
minus *working offset*; the working offset is, in this order: what the
``offsets`` callable returns (``{axis: mm}``), else machine minus part
coordinate of the last motion block reported through :meth:`update` (the whole
origin chain plus tool length compensation), else 0.  *Target position* is the
end of the last motion segment reported through :meth:`update` (the machine
position when none was).  Program transferred % is the planned time sent over
the planned total when the runner gives one, else the line of the last
segment over the program's line count (``program``).  b0 "all axes homed" is
always 1: fagorcnc has no homing cycle and treats machine coordinates as
referenced.

**Word order of [L] values.**  The seed does not say (seed 004 L55 and on only
mark them [L]).  We put the **high word first** (word at the lower address =
bits 31..16, "big" in pymodbus' ``convert_from_registers``), the usual Modbus
order; ``word_order="little"`` serves a PLC that expects low word first.

**No torn 32-bit values.**  RosettaCNC answers "busy" while it rewrites its
registers (seed 004 L169).  We never need to: the whole input-register image is
composed as a new list and swapped in under a lock, and pymodbus' ``action``
callback (which runs in the server's event loop before every access) copies
one complete image into the block the reply is cut from.  A reply therefore
always comes from one snapshot; the server never answers exception 06 (busy),
which a RosettaCNC master tolerates anyway.

**Requests.**  At most 32 registers per read (seed 004 L173): more is answered
with exception 03 (illegal data value).  Holding registers can always be read;
writes only when ``holding_writes=True`` ("Enable write operations", seed 004
L170), otherwise exception 01 (illegal function).

**End of a run.**  :meth:`StatusServer.finished` publishes how the run ended (30072 b1, and
30035/30036 in the gap the seed's table leaves, [CONSTRUCTION]) and :meth:`StatusServer.linger`
keeps serving that final state ``linger`` seconds (default :data:`DEFAULT_LINGER`) before it
stops, so a PLC polling every 20 ms can tell a finished program from an alarm or a crash.

**Refusals change nothing.**  Function 23 (read/write) writes only once its read part is valid
(pymodbus hands over the write before it checks the read range); functions 20, 21 and 24
(file records, read FIFO), which pymodbus would answer from no table, are refused with
exception 01; pymodbus' log records get a NullHandler, so a malformed frame (0x84...) prints
nothing on the run's standard error.

**Main state** (30071).  Back-end states map as ``idle`` -> 3 Idle, ``run`` ->
6 Run, ``pause`` -> 7 Pause, ``alarm`` (or any alarm code, or any custom alarm
register non-zero) -> 2 Alarm, ``closed`` -> ``closed_state`` (3 Idle by
default: the runner opens the back-end at the start of a run and closes it at
the end, so between runs "closed" means "ready, no program running"; pass
``closed_state=MainState.INIT`` to publish 0 instead); anything else -> 0 Init.

**Alarms from the PLC.**  Writing a non-zero value *v* to 4000*n* (n = 1..8)
calls ``backend.raise_alarm(9000 + n, message)`` (or ``backend.stop()``), in a
worker thread, before the write is acknowledged: the simulator stops at once
and the run's ``send`` raises :class:`~fagorcnc.backends.BackendError`, so
:func:`fagorcnc.run` returns ``stopped_by == "alarm"``.  30073 then shows
9000 + n, 30074 n and 30075 *v*.  The alarm is *level*-sensitive: while the
register stays non-zero, a run that starts (or continues) is stopped again
within one poll.  Writing 0 does not acknowledge the back-end's alarm (that is
the operator's ``resume`` or the next run).  Every alarm and warning write is
recorded as a :class:`PlcSignal` in :attr:`StatusServer.alarms` /
:attr:`StatusServer.warnings` and passed to ``on_signal``.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import math
import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from enum import IntEnum
from os import PathLike
from pathlib import Path
from typing import Literal

from pymodbus.constants import ExcCodes
from pymodbus.pdu import ExceptionResponse, ModbusPDU
from pymodbus.pdu.device import ModbusDeviceIdentification
from pymodbus.pdu.file_message import ReadFifoQueueRequest, ReadFileRecordRequest, WriteFileRecordRequest
from pymodbus.server import ModbusTcpServer
from pymodbus.simulator import DataType, SimData, SimDevice

from ..backends.base import Status
from ..config.machine import Machine

__all__ = [
    "CUSTOM_ALARM_CODE", "DEFAULT_LINGER", "END_REASONS", "HOLDING_COUNT", "INPUT_COUNT", "INTERFACE_LEVEL",
    "MAX_READ", "MainState", "PlcSignal",
    "StatusServer", "StatusServerError", "decode_long", "encode_long", "hr_address", "ir_address", "parse_address",
]

log = logging.getLogger(__name__)

# ---------------------------------------------------------------- register table (seed 004 L48-L168)
IR_BASE = 30001                       # input register 30001 = address 0
HR_BASE = 40001                       # holding register 40001 = address 0

IR_MODBUS_INTERFACE_LEVEL = 30001     # seed 004 L49   [W]
IR_FIRMWARE_VERSION = 30002           # seed 004 L51   [W] b15..b08 version, b07..b00 release
IR_SERIAL_NUMBER = 30003              # seed 004 L55   [L]
IR_MACHINE_POSITION_X = 30005         # seed 004 L57   [L] X, Y, Z only (L57-L59) [mm/1000]
IR_TARGET_POSITION_X = 30011          # seed 004 L61   [L] X Y Z A B C (L61-L66)
IR_PROGRAM_POSITION_X = 30023         # seed 004 L68   [L] X Y Z A B C (L68-L73)
IR_WORKING_OFFSET_X = 30047           # seed 004 L75   [L] X Y Z A B C (L75-L80)
IR_ACT_VELOCITY_X = 30059             # seed 004 L82   [L] X Y Z A B C (L82-L87) [mm/min]
IR_MAIN_CNC_STATE = 30071             # seed 004 L89   [W]
IR_CNC_STATES = 30072                 # seed 004 L107  [W] b00 all axes homed, b01 program ended successfully
IR_ALARM_CODE = 30073                 # seed 004 L111  [W]
IR_ALARM_INFO_FIELD_A = 30074         # seed 004 L112  [W]
IR_ALARM_INFO_FIELD_B = 30075         # seed 004 L113  [W]
IR_GCODE_LINE = 30076                 # seed 004 L115  [L]
IR_EXECUTION_INFO = 30078             # seed 004 L117  b00-b07 buffer level %, b08-b15 program transferred %
IR_VIRTUAL_OUTPUTS = 30079            # seed 004 L119
IR_SHARED_MEMORY_01 = 30080           # seed 004 L125  [L] x 8 (L125-L132)
IR_GCODE_CMD = 30096                  # seed 004 L134  [L]

HR_CUSTOM_ALARM_01 = 40001            # seed 004 L137  x 8 (L137-L144)
HR_CUSTOM_WARNING_01 = 40009          # seed 004 L146  x 8 (L146-L153)
HR_SHARED_MEMORY_01 = 40018           # seed 004 L155  [L] x 8 (L155-L162)
HR_VIRTUAL_INPUTS = 40034             # seed 004 L164

# [CONSTRUCTION] fagorcnc's own registers in the gap the seed's table leaves (30035-30046 read as 0 in
# RosettaCNC, seed 004 L73-L75): why the last run ended, and at which line -- the table itself only has b1
# "program ended successfully" of 30072, which cannot tell an error from an alarm or a crash.
IR_END_REASON = 30035                 # [W] END_REASONS; 0 while a run is under way or before the first
IR_END_LINE = 30036                   # [L] line the run ended at (0 when it does not apply)

INTERFACE_LEVEL = 1                   # seed 004 L26: "version 1 is currently available"
INPUT_COUNT = IR_GCODE_CMD + 2 - IR_BASE        # 97 registers: 30001..30097
HOLDING_COUNT = HR_VIRTUAL_INPUTS + 1 - HR_BASE  # 34 registers: 40001..40034
MAX_READ = 32                         # seed 004 L173: at most 32 registers per read
CUSTOM_ALARMS = 8                     # seed 004 L34: "max 8 alarms and 8 warnings"
#: Alarm code published (and given to ``raise_alarm``) for custom alarm n: ``CUSTOM_ALARM_CODE + n``.
CUSTOM_ALARM_CODE = 9000

#: 30035: how the last run ended (the causes of :class:`fagorcnc.summary.Ending`).
END_REASONS: Mapping[str, int] = {
    "M30": 1, "M02": 2, "end of file": 3, "error": 4, "alarm": 5, "link lost": 6, "stopped by the user": 7,
    "not started": 8,
}
#: Seconds the server stays up after the end of the run by default (:meth:`StatusServer.linger`): a PLC
#: polling every 20 ms to 1 s reads the final state and the end reason before the port closes.
DEFAULT_LINGER = 3.0
#: Functions pymodbus would answer without the register table (read FIFO answers dummy values, file
#: records): refused with exception 01, like every function the table does not have.
REFUSED_FUNCTIONS = (20, 21, 24)

AXIS_SLOTS = ("X", "Y", "Z", "A", "B", "C")      # order of the 6-axis groups (seed 004 L61-L66)
MACHINE_POSITION_AXES = ("X", "Y", "Z")           # the machine position has three slots only (L57-L59)

_READ_CODES = frozenset({3, 4, 6, 22, 23})        # functions that read (6 and 22 read back after writing)
_BIT_CODES = frozenset({1, 2, 5, 15})             # coils and discrete inputs: not in the table
_INT32 = 1 << 32


def ir_address(reference: int) -> int:
    """Wire address (function 04) of input register ``reference`` (30001 -> 0)."""
    return reference - IR_BASE


def hr_address(reference: int) -> int:
    """Wire address (functions 03/06/16) of holding register ``reference`` (40001 -> 0)."""
    return reference - HR_BASE


class MainState(IntEnum):
    """Main CNC state, register 30071 (seed 004 L89-L105)."""

    INIT = 0
    INIT_FIELDBUS = 1
    ALARM = 2
    IDLE = 3
    HOMING = 4
    JOG = 5
    RUN = 6
    PAUSE = 7
    LIMIT = 8
    MEASURING_TOOL = 9
    SCAN_3D = 10
    SAFETY_IDLE = 11
    CHANGE_TOOL = 12
    SAFETY = 13
    WAITING_MAIN_POWER = 14
    RETRACT_TOOL = 15


#: fagorcnc back-end states (``backends.base.STATES``) to main states; "closed" is the server's ``closed_state``.
STATE_CODES: Mapping[str, MainState] = {
    "idle": MainState.IDLE, "run": MainState.RUN, "pause": MainState.PAUSE, "alarm": MainState.ALARM,
}

WordOrder = Literal["big", "little"]


def encode_long(value: int, word_order: WordOrder = "big") -> tuple[int, int]:
    """A signed or unsigned 32-bit value as two registers, in address order.

    Out-of-range values saturate to the int32 range (-2**31 .. 2**31-1) unless
    they fit an unsigned 32-bit value.
    """
    value = int(value)
    if value < -(1 << 31):
        value = -(1 << 31)
    elif value >= _INT32:
        value = (1 << 31) - 1
    raw = value % _INT32
    high, low = raw >> 16, raw & 0xFFFF
    return (high, low) if word_order == "big" else (low, high)


def decode_long(words: tuple[int, int] | list[int], word_order: WordOrder = "big", *, signed: bool = True) -> int:
    """The 32-bit value of two registers read in address order (inverse of :func:`encode_long`)."""
    first, second = words[0], words[1]
    high, low = (first, second) if word_order == "big" else (second, first)
    raw = (high << 16) | low
    return raw - _INT32 if signed and raw >= 1 << 31 else raw


def parse_address(text: str, default_host: str = "127.0.0.1") -> tuple[str, int]:
    """``"5020"``, ``":5020"`` or ``"0.0.0.0:502"`` -> (host, port), for a ``--status-server`` option."""
    host, sep, port = text.rpartition(":")
    if not sep:
        host = ""
    try:
        number = int(port)
    except ValueError:
        raise ValueError(f"status server address {text!r}: expected [HOST:]PORT") from None
    if not 0 <= number <= 65535:
        raise ValueError(f"status server address {text!r}: port must be 0..65535")
    return (host or default_host), number


@dataclass(frozen=True)
class PlcSignal:
    """A custom alarm or warning written by the PLC.

    ``kind``: ``"alarm"`` or ``"warning"``; ``number``: 1..8; ``value``: the
    value written (0 = the PLC cleared it); ``register``: 40001..40016;
    ``code``/``message``: the alarm given to the back-end (0 / "" for warnings
    and clears); ``time``: ``time.monotonic()`` when it arrived.
    """

    kind: str
    number: int
    value: int
    register: int
    code: int = 0
    message: str = ""
    time: float = 0.0


class StatusServerError(RuntimeError):
    """The status server could not start (address in use, no permission for a port below 1024...)."""


Offsets = Callable[[], Mapping[str, float]]
SignalCallback = Callable[[PlcSignal], None]


class StatusServer:
    """A RosettaCNC-style Modbus TCP status server for one back-end (see the module docstring).

    ``backend``: anything with ``status()`` (and ``raise_alarm(code, message)``
    or ``stop()``); ``machine``: gives the axis names (None: the keys of the
    status' ``position``); ``host``/``port``: where to listen (port 0 picks a
    free port, see :attr:`port`); ``holding_writes``: accept writes to the
    holding registers; ``program``: the program being run (path or text), for
    "program transferred %" when the runner gives no planned total;
    ``offsets``: callable returning the current working offsets ``{axis: mm}``;
    ``word_order``: of [L] values, ``"big"`` = high word first;
    ``device_id``: the unit id to answer (0 = any); ``serial_number``: 30003;
    ``closed_state``: main state published while the back-end is closed;
    ``poll_interval``: seconds between polls of ``backend.status()``;
    ``alarm_texts``: {n: text} for custom alarm n (seed 004 L34);
    ``on_signal``: called with every :class:`PlcSignal` (from a server thread:
    keep it short).
    """

    def __init__(self, backend, machine: Machine | None = None, *, host: str = "127.0.0.1", port: int = 502,
                 holding_writes: bool = False, program: str | PathLike | None = None, offsets: Offsets | None = None,
                 word_order: WordOrder = "big", device_id: int = 0, serial_number: int = 0,
                 closed_state: int = MainState.IDLE, poll_interval: float = 0.05,
                 alarm_texts: Mapping[int, str] | None = None, on_signal: SignalCallback | None = None,
                 linger: float = DEFAULT_LINGER) -> None:
        if word_order not in ("big", "little"):
            raise ValueError("word_order must be 'big' (high word first) or 'little'")
        self.backend = backend
        self.machine = machine
        self.host, self.port = host, port
        self.holding_writes = holding_writes
        self.offsets = offsets
        self.word_order: WordOrder = word_order
        self.device_id = device_id
        self.serial_number = serial_number
        self.closed_state = int(closed_state)
        self.poll_interval = poll_interval
        self.alarm_texts = dict(alarm_texts or {})
        self.on_signal = on_signal
        if not (linger >= 0 and math.isfinite(linger)):
            raise ValueError("linger must be 0 or a positive number of seconds")
        self.linger_seconds = float(linger)
        self.alarms: list[PlcSignal] = []
        self.warnings: list[PlcSignal] = []
        self._program_lines = _count_lines(program)
        self._axes: tuple[str, ...] = tuple(machine.axis_names) if machine is not None else ()

        self._lock = threading.Lock()                 # guards everything below
        self._status = Status(state="closed")
        self._status_stamp = -1.0
        self._target: dict[str, float] | None = None
        self._record_offsets: dict[str, float] | None = None
        self._transferred = 0                         # %
        self._ended_ok = False
        self._end_reason = 0                          # IR_END_REASON
        self._end_line = 0
        self._pending_write: tuple[int, list[int]] | None = None   # function 23: applied once its read is valid
        self._custom_info: dict[int, int] = {}        # custom alarm n -> value written
        self._holding = [0] * HOLDING_COUNT
        self._image = [0] * INPUT_COUNT
        self._built_at = -1.0
        self._last_enforced = -1.0

        self._loop: asyncio.AbstractEventLoop | None = None
        self._stopping: asyncio.Event | None = None
        self._serve_thread: threading.Thread | None = None
        self._poll_thread: threading.Thread | None = None
        self._poll_stop = threading.Event()
        self._ready = threading.Event()
        self._error: BaseException | None = None
        self._publish(self._status, -1.0, force=True)

    # ------------------------------------------------------------ lifecycle
    def start(self, timeout: float = 5.0) -> StatusServer:
        """Listen and start polling; returns self.  Raises :class:`StatusServerError` if it cannot listen."""
        if self._serve_thread is not None:
            raise RuntimeError("the status server is already started")
        _quiet_pymodbus()
        self.refresh()
        self._serve_thread = threading.Thread(target=self._serve, name="fagorcnc-status-server", daemon=True)
        self._serve_thread.start()
        if not self._ready.wait(timeout) or self._error is not None:
            error = self._error
            self.stop(timeout)
            where = f"{self.host}:{self.port}"
            raise StatusServerError(f"the status server cannot listen on {where}: "
                                    f"{error or 'timed out'} (port in use, or below 1024 without privileges?)")
        self._poll_thread = threading.Thread(target=self._poll, name="fagorcnc-status-poll", daemon=True)
        self._poll_thread.start()
        return self

    def stop(self, timeout: float = 5.0) -> None:
        """Stop serving (connections are closed) and join the threads.  Safe to call twice; a server starts once."""
        self._poll_stop.set()
        loop, stopping = self._loop, self._stopping
        if loop is not None and stopping is not None and not loop.is_closed():
            with contextlib.suppress(RuntimeError):      # the loop closed meanwhile
                loop.call_soon_threadsafe(stopping.set)
        for thread in (self._poll_thread, self._serve_thread):
            if thread is not None and thread is not threading.current_thread():
                thread.join(timeout)
                if thread.is_alive():
                    log.warning("status server: thread %s did not stop within %.1f s", thread.name, timeout)

    @property
    def running(self) -> bool:
        """True while the server listens."""
        return self._serve_thread is not None and self._serve_thread.is_alive() and self._error is None

    def __enter__(self) -> StatusServer:
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()

    # ------------------------------------------------------------ feeding it
    def update(self, segment=None, status: Status | None = None, total: float | None = None) -> None:
        """Progress callback of :func:`fagorcnc.run`: ``(segment, status, total_time)``.

        Records what only the runner knows -- the segment's end (target
        position), its block's working offset, the planned time sent over the
        planned ``total`` (s) -- and publishes ``status`` (read from the
        back-end when None).  Cheap: the image is rebuilt at most every 5 ms.
        """
        stamp = time.monotonic()
        if status is None:
            status = self.backend.status()
        if segment is not None:
            target, offsets, transferred = self._segment_info(segment, total)
            with self._lock:
                if target is not None:
                    self._target = target
                if offsets is not None:
                    self._record_offsets = offsets
                if transferred is not None:
                    self._transferred = transferred
        self._publish(status, stamp, force=False)

    def progress_callback(self, then: Callable[..., None] | None = None) -> Callable[..., None]:
        """A ``progress`` callback for :func:`fagorcnc.run` that feeds :meth:`update`, then calls ``then``."""

        def progress(segment, status, total) -> None:
            self.update(segment, status, total)
            if then is not None:
                then(segment, status, total)

        return progress

    def finished(self, ok: bool, ending=None) -> None:
        """The run is over: ``ok`` sets 30072 b1 "program ended successfully" (and 100 % transferred);
        ``ending`` (a :class:`fagorcnc.summary.Ending`, e.g. ``report.ending``) gives 30035 the end reason
        (:data:`END_REASONS`) and 30036 the line.  They stay until the next run starts."""
        cause = getattr(ending, "cause", None)
        with self._lock:
            self._ended_ok = bool(ok)
            if ok:
                self._transferred = 100
            self._end_reason = END_REASONS.get(cause, 0) if cause is not None else (1 if ok else 4)
            self._end_line = int(getattr(ending, "line", 0) or 0)
        self.refresh()

    def linger(self, seconds: float | None = None) -> None:
        """Keep serving the final state for ``seconds`` (default: the ``linger`` given to the constructor),
        then stop: a PLC polling the server sees how the run ended before the port closes.  Ctrl-C
        (KeyboardInterrupt) cuts the wait short; the server is stopped either way."""
        wait = self.linger_seconds if seconds is None else seconds
        try:
            if wait > 0 and self.running:
                self._poll_stop.wait(wait)   # set by stop(): nothing to wait for then
        finally:
            self.stop()

    def refresh(self) -> None:
        """Read ``backend.status()`` now and publish it (what the poller does every ``poll_interval``)."""
        stamp = time.monotonic()
        try:
            status = self.backend.status()
        except Exception as exc:     # a failing link must not kill the server: keep the last image
            log.debug("status server: backend.status() failed: %s", exc)
            return
        self._publish(status, stamp, force=True)
        self._enforce_custom_alarms(status)

    # ------------------------------------------------------------ what a PLC sees
    def input_registers(self) -> list[int]:
        """A copy of the current input-register image (index = reference - 30001)."""
        with self._lock:
            return list(self._image)

    def holding_registers(self) -> list[int]:
        """A copy of the holding registers (index = reference - 40001)."""
        with self._lock:
            return list(self._holding)

    def active_warnings(self) -> dict[int, int]:
        """Custom warnings the PLC holds set: {n (1..8): value}."""
        regs = self.holding_registers()
        base = hr_address(HR_CUSTOM_WARNING_01)
        return {n + 1: v for n, v in enumerate(regs[base:base + CUSTOM_ALARMS]) if v}

    def shared_memory(self) -> list[int]:
        """The 8 signed 32-bit values the PLC wrote to 40018-40032 (stored only; fagorcnc has no M167)."""
        regs = self.holding_registers()
        base = hr_address(HR_SHARED_MEMORY_01)
        return [decode_long(regs[base + 2 * i:base + 2 * i + 2], self.word_order) for i in range(8)]

    # ------------------------------------------------------------ the register image
    def _segment_info(self, segment, total: float | None):
        """(target, working offsets, transferred %) from a planned segment; None where unknown."""
        target = offsets = transferred = None
        piece = getattr(segment, "piece", None)
        if getattr(segment, "kind", None) == "motion" and piece is not None:
            names = self._axes or tuple(self._status.position)
            target = {a: float(v) for a, v in zip(names, piece.end, strict=False)}
        record = getattr(segment, "record", None)
        end, end_part = getattr(record, "end", None), getattr(record, "end_part", None)
        if isinstance(end, Mapping) and isinstance(end_part, Mapping):
            offsets = {a: float(end[a]) - float(end_part[a]) for a in end if a in end_part}
        if total:
            done = float(segment.t0) + float(segment.duration)
            transferred = _percent(done / total)
        elif self._program_lines:
            transferred = _percent(int(segment.line) / self._program_lines)
        return target, offsets, transferred

    def _publish(self, status: Status, stamp: float, *, force: bool) -> None:
        """Keep ``status`` if it is the newest seen, and swap in a new image (every call when ``force``)."""
        offsets = None
        if self.offsets is not None:
            try:
                offsets = dict(self.offsets())
            except Exception as exc:
                log.debug("status server: offsets() failed: %s", exc)
        with self._lock:
            if stamp >= self._status_stamp:
                self._status, self._status_stamp = status, stamp
                if status.state == "run":     # a (new) run is under way: its end is not known yet
                    self._ended_ok = False
                    self._end_reason = self._end_line = 0
            now = time.monotonic()
            if not force and now - self._built_at < 0.005:
                return
            if offsets is None:
                offsets = self._record_offsets or {}
            image = self._compose(self._status, offsets)
            self._image, self._built_at = image, now      # one reference swap: readers see old or new

    def _compose(self, st: Status, offsets: Mapping[str, float]) -> list[int]:
        """The whole input-register image for one status (called with the lock held)."""
        regs = [0] * INPUT_COUNT

        def word(ref: int, value: int) -> None:
            regs[ref - IR_BASE] = max(0, min(0xFFFF, int(value)))

        def long(ref: int, value: float) -> None:
            regs[ref - IR_BASE], regs[ref - IR_BASE + 1] = encode_long(round(value), self.word_order)

        word(IR_MODBUS_INTERFACE_LEVEL, INTERFACE_LEVEL)
        word(IR_FIRMWARE_VERSION, _version_word())
        long(IR_SERIAL_NUMBER, self.serial_number)

        position = st.position
        target = st.target or self._target or position   # the back-end's own, when it knows it
        for i, axis in enumerate(AXIS_SLOTS):
            pos = position.get(axis, 0.0)
            off = offsets.get(axis, 0.0)
            if axis in MACHINE_POSITION_AXES:
                long(IR_MACHINE_POSITION_X + 2 * i, 1000.0 * pos)
            long(IR_TARGET_POSITION_X + 2 * i, 1000.0 * target.get(axis, pos))
            long(IR_PROGRAM_POSITION_X + 2 * i, 1000.0 * (pos - off))
            long(IR_WORKING_OFFSET_X + 2 * i, 1000.0 * off)
            long(IR_ACT_VELOCITY_X + 2 * i, 60.0 * st.velocity.get(axis, 0.0))

        custom = self._active_custom_alarm()
        alarm_code, info_a, info_b = int(st.alarm), 0, 0
        if not alarm_code and custom:
            alarm_code = CUSTOM_ALARM_CODE + custom
        n = alarm_code - CUSTOM_ALARM_CODE
        if 1 <= n <= CUSTOM_ALARMS:
            info_a, info_b = n, self._custom_info.get(n, 0)
        if st.state == "alarm" or alarm_code:
            state = MainState.ALARM
        elif st.state == "closed":
            state = self.closed_state
        else:
            state = STATE_CODES.get(st.state, MainState.INIT)
        word(IR_MAIN_CNC_STATE, state)
        word(IR_CNC_STATES, 0b01 | (0b10 if self._ended_ok else 0))
        word(IR_END_REASON, self._end_reason)
        long(IR_END_LINE, self._end_line)
        word(IR_ALARM_CODE, alarm_code)
        word(IR_ALARM_INFO_FIELD_A, info_a)
        word(IR_ALARM_INFO_FIELD_B, info_b)
        long(IR_GCODE_LINE, st.line)
        word(IR_EXECUTION_INFO, _percent(st.buffer_level) | (self._transferred << 8))
        return regs

    def _active_custom_alarm(self) -> int:
        """The lowest custom alarm number whose register is non-zero, 0 if none (lock held)."""
        base = hr_address(HR_CUSTOM_ALARM_01)
        return next((n + 1 for n in range(CUSTOM_ALARMS) if self._holding[base + n]), 0)

    # ------------------------------------------------------------ alarms from the PLC
    def _raise_custom_alarm(self, n: int, value: int) -> None:
        """Stop the run: ``raise_alarm`` when the back-end has it, else ``stop``; then publish."""
        code = CUSTOM_ALARM_CODE + n
        text = self.alarm_texts.get(n) or f"PLC custom alarm {n}"
        message = f"{text} (HR {HR_CUSTOM_ALARM_01 + n - 1} = {value})"
        with self._lock:
            self._custom_info[n] = value
            self._last_enforced = time.monotonic()
        raise_alarm = getattr(self.backend, "raise_alarm", None)
        if callable(raise_alarm):
            raise_alarm(code, message)
        else:
            self.backend.stop()
        self.refresh()

    def _enforce_custom_alarms(self, status: Status) -> None:
        """Level semantics: a custom alarm register still set stops motion that (re)started."""
        if status.state not in ("run", "pause") or status.alarm:
            return
        with self._lock:
            n = self._active_custom_alarm()
            value = self._holding[hr_address(HR_CUSTOM_ALARM_01) + n - 1] if n else 0
            recent = time.monotonic() - self._last_enforced < 0.25
        if n and not recent:
            self._raise_custom_alarm(n, value)

    def _signal(self, signal: PlcSignal) -> None:
        (self.alarms if signal.kind == "alarm" else self.warnings).append(signal)
        if self.on_signal is not None:
            try:
                self.on_signal(signal)
            except Exception:
                log.exception("status server: on_signal callback failed")

    # ------------------------------------------------------------ Modbus side (server thread)
    async def _action(self, function_code: int, _start: int, address: int, count: int, registers: list[int],
                      set_values: list[int] | list[bool] | None) -> ExcCodes | None:
        """pymodbus calls this before every access; the reply is cut from ``registers`` right after."""
        pending, self._pending_write = self._pending_write, None   # only the read of the same request takes it
        if function_code in _BIT_CODES:
            return ExcCodes.ILLEGAL_FUNCTION
        if set_values is None:
            if function_code not in _READ_CODES:
                return ExcCodes.ILLEGAL_FUNCTION
            if count > MAX_READ:                     # seed 004 L173
                return ExcCodes.ILLEGAL_VALUE
            if function_code == 23 and pending is not None:
                # the read part is valid: now the write happens, before the read (Modbus: write first)
                refused = await self._write(*pending)
                if refused is not None:
                    return refused
            with self._lock:                         # one complete snapshot into the reply block
                source = self._image if function_code == 4 else self._holding
                registers[:len(source)] = source
            return None
        if not self.holding_writes:                  # seed 004 L170
            return ExcCodes.ILLEGAL_FUNCTION
        if function_code == 23:
            # read/write multiple: pymodbus hands us the write before it checks the read range (a bad read is
            # answered 02 without calling us again); a refused request must change nothing, so the write
            # waits for the read part of the same request
            self._pending_write = (address, [int(v) for v in set_values])
            return None
        return await self._write(address, [int(v) for v in set_values])

    async def _write(self, address: int, values: list[int]) -> ExcCodes | None:
        """A write to holding registers ``address``.. : store, then act on alarms and warnings."""
        now = time.monotonic()
        with self._lock:
            old = self._holding[address:address + len(values)]
            self._holding[address:address + len(values)] = values
        alarm_base, warning_base = hr_address(HR_CUSTOM_ALARM_01), hr_address(HR_CUSTOM_WARNING_01)
        raised: list[tuple[int, int]] = []
        for i, (before, value) in enumerate(zip(old, values, strict=True)):
            where = address + i
            if alarm_base <= where < alarm_base + CUSTOM_ALARMS and (value or before):
                n = where - alarm_base + 1
                code = CUSTOM_ALARM_CODE + n if value else 0
                text = (self.alarm_texts.get(n) or f"PLC custom alarm {n}") if value else ""
                self._signal(PlcSignal("alarm", n, value, HR_BASE + where, code, text, now))
                if value:
                    raised.append((n, value))
            elif warning_base <= where < warning_base + CUSTOM_ALARMS and value != before:
                self._signal(PlcSignal("warning", where - warning_base + 1, value, HR_BASE + where, time=now))
        try:
            for n, value in raised:
                await asyncio.to_thread(self._raise_custom_alarm, n, value)
            if not raised:
                self._publish(self._status, -1.0, force=True)    # custom alarm cleared: new image
        except Exception:
            log.exception("status server: raising the PLC alarm failed")
            return ExcCodes.DEVICE_FAILURE
        return None

    def _device(self) -> SimDevice:
        """Separate blocks (coils, discrete inputs, holding, input); the bit blocks only exist to refuse."""
        bits = [SimData(0, values=0, datatype=DataType.BITS)]
        holding = [SimData(0, count=HOLDING_COUNT, values=0, datatype=DataType.REGISTERS)]
        inputs = [SimData(0, count=INPUT_COUNT, values=0, datatype=DataType.REGISTERS)]
        return SimDevice(id=self.device_id, simdata=(bits, list(bits), holding, inputs), action=self._action)

    def _serve(self) -> None:
        try:
            asyncio.run(self._main())
        except BaseException as exc:       # pragma: no cover - reported through start()
            self._error = exc
        finally:
            self._ready.set()

    async def _main(self) -> None:
        self._loop = asyncio.get_running_loop()
        self._stopping = asyncio.Event()
        identity = ModbusDeviceIdentification(info_name={
            "VendorName": "fagorcnc", "ProductName": "fagorcnc status server (RosettaCNC interface level 1)"})
        server = ModbusTcpServer(self._device(), address=(self.host, self.port), identity=identity,
                                 custom_pdu=[_refusal(code) for code in REFUSED_FUNCTIONS])
        try:
            await server.serve_forever(background=True)
        except (RuntimeError, OSError) as exc:
            self._error = exc
            await server.shutdown()
            return
        sockets = getattr(server.transport, "sockets", None)
        if sockets:
            self.port = sockets[0].getsockname()[1]
        self._ready.set()
        try:
            await self._stopping.wait()
        finally:
            await server.shutdown()

    def _poll(self) -> None:
        while not self._poll_stop.wait(self.poll_interval):
            try:
                self.refresh()
            except Exception:    # never let the poller die silently
                log.exception("status server: poll failed")


def _quiet_pymodbus() -> None:
    """pymodbus logs what a client sends wrong ("Unable to decode frame", a traceback for a request its
    datastore code fails on): with no handler of the application's, Python's last-resort handler would print
    them on the run's standard error.  A NullHandler keeps them in the logging system (an application that
    configures logging still sees them) and off the terminal."""
    logger = logging.getLogger("pymodbus")
    if not any(isinstance(h, logging.NullHandler) for h in logger.handlers):
        logger.addHandler(logging.NullHandler())


def _refusal(code: int) -> type[ModbusPDU]:
    """A request class for function ``code`` that answers exception 01 (illegal function) and touches nothing."""
    base = {20: ReadFileRecordRequest, 21: WriteFileRecordRequest, 24: ReadFifoQueueRequest}[code]

    async def datastore_update(self, _context, _device_id) -> ModbusPDU:
        return ExceptionResponse(self.function_code, ExcCodes.ILLEGAL_FUNCTION)

    return type(f"Refused{base.__name__}", (base,), {"datastore_update": datastore_update})


def _version_word() -> int:
    """fagorcnc's version for 30002: major in the high byte, minor ("release") in the low byte."""
    from ..version import __version__

    parts = [*__version__.split("."), "0"][:2]
    major, minor = (int(p) if p.isdigit() else 0 for p in parts)
    return (min(major, 255) << 8) | min(minor, 255)


def _percent(fraction: float) -> int:
    return max(0, min(100, round(100.0 * float(fraction))))


def _count_lines(program: str | PathLike | None) -> int:
    """Lines of the program (a path, or program text), 0 when unknown."""
    if program is None:
        return 0
    text = str(program)
    if isinstance(program, PathLike) or ("\n" not in text and Path(text).is_file()):
        try:
            text = Path(program).read_text(encoding="utf-8", errors="replace")
        except OSError:
            return 0
    return len(text.splitlines())
