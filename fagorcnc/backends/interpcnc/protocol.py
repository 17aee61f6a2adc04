"""InterpCNC V3 command encoding and decoding: pure functions, no I/O.

A command is the list of 16-bit words written with Modbus function 16 at
holding register 2000: the command id first, then its arguments (seed 000
L484-L494).  32-bit values (integers and IEEE-754 single floats) take two
registers, **low word first** (the "LW"/"HW" columns of every table, e.g.
L530, L546).  pymodbus' own 32-bit helpers default to high word first, so
this module converts explicitly.  Strings are packed two characters per
register, the **first character in the low byte** (L858, L870): "G0" is
0x3047.

The ids, registers and the document's contradictions are in
:mod:`.registers`.  :func:`parse_command` is the inverse of the encoders;
the emulator uses it, so encoder and card model cannot drift apart.
"""

from __future__ import annotations

import math
import struct
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

from . import registers as regs

Words = list[int]


class ProtocolError(ValueError):
    """A value cannot be encoded, or a word list is not a valid command."""


# ---------------------------------------------------------------- 32-bit values, low word first
def u32_words(value: int) -> Words:
    """Unsigned 32-bit integer as ``[low word, high word]``."""
    if not 0 <= value <= 0xFFFFFFFF:
        raise ProtocolError(f"{value} does not fit an unsigned 32-bit register pair")
    return [value & 0xFFFF, value >> 16]


def i32_words(value: int) -> Words:
    """Signed 32-bit integer (two's complement) as ``[low word, high word]``."""
    if not -(1 << 31) <= value < (1 << 31):
        raise ProtocolError(f"{value} does not fit a signed 32-bit register pair")
    return u32_words(value & 0xFFFFFFFF)


def float_words(value: float) -> Words:
    """IEEE-754 single-precision float as ``[low word, high word]`` (12.2 -> [0x3333, 0x4143])."""
    if not math.isfinite(value):
        raise ProtocolError(f"{value} is not a finite number")
    bits = struct.unpack("<I", struct.pack("<f", value))[0]
    return [bits & 0xFFFF, bits >> 16]


def words_u32(low: int, high: int) -> int:
    return (high << 16) | low


def words_i32(low: int, high: int) -> int:
    v = words_u32(low, high)
    return v - (1 << 32) if v & 0x80000000 else v


def words_float(low: int, high: int) -> float:
    return struct.unpack("<f", struct.pack("<I", words_u32(low, high)))[0]


def float32(value: float) -> float:
    """``value`` rounded to single precision (what the card receives)."""
    return struct.unpack("<f", struct.pack("<f", value))[0]


def _u16(value: int, what: str, low: int = 0, high: int = 0xFFFF) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise ProtocolError(f"{what} must be an integer {low}..{high}, got {value!r}")
    return value


# ---------------------------------------------------------------- strings
def pack_string(text: str) -> Words:
    """ASCII text, two characters per register, first character in the low byte; odd length padded with 0."""
    try:
        raw = text.encode("ascii")
    except UnicodeEncodeError as exc:
        raise ProtocolError(f"only ASCII text can be sent to the card: {text!r}") from exc
    if len(raw) % 2:
        raw += b"\0"
    return [raw[k] | (raw[k + 1] << 8) for k in range(0, len(raw), 2)]


def unpack_string(words: Iterable[int], length: int) -> str:
    raw = bytearray()
    for w in words:
        raw += bytes((w & 0xFF, w >> 8))
    return raw[:length].decode("ascii", errors="replace")


# ---------------------------------------------------------------- buffered CNC commands (1000-1012)
def encode_gcode(line: str) -> Words:
    """Command 1000: one G-code line for the card's own interpreter (seed 000 L856-L878).

    It goes to the Grbl buffer (check input register 3001), whose use is
    2 + ceil(length/2) registers.
    """
    if len(line) > 255:
        raise ProtocolError("a G-code line sent with command 1000 is at most 255 characters")
    return [regs.CMD_GCODE, len(line), *pack_string(line)]


def encode_feed(mm_per_min: float) -> Words:
    """Command 1001: feed for the following moves, mm/min, as a float.

    The text says unsigned 16 bits (L882) but the table says float (L887)
    and the buffer use of 3 registers (L890) only fits a float: float it is.
    """
    if not mm_per_min > 0:
        raise ProtocolError(f"feed must be positive, got {mm_per_min}")
    return [regs.CMD_FEED, *float_words(mm_per_min)]


def axis_mask(axes: Iterable[str]) -> int:
    """Bits 0-5 for the card axes X Y Z A B C named in ``axes`` (L908-L915)."""
    mask = 0
    for a in axes:
        if a not in regs.CARD_AXES:
            raise ProtocolError(f"the card has no axis {a!r} (axes: {' '.join(regs.CARD_AXES)})")
        mask |= 1 << regs.CARD_AXES.index(a)
    return mask


def _targets(targets: Mapping[str, float]) -> tuple[int, Words]:
    """Mask and the floats in increasing axis order (L1183: 'dans l'ordre croissant des indexes')."""
    if not targets:
        raise ProtocolError("a move needs at least one axis target")
    mask = axis_mask(targets)
    words: Words = []
    for a in regs.CARD_AXES:
        if a in targets:
            words += float_words(targets[a])
    return mask, words


def encode_line(targets: Mapping[str, float], *, rapid: bool = False) -> Words:
    """Command 1002: linear move to absolute positions (mm) of the card axes in ``targets``.

    Bit 6 of the mask selects the maximum speed (G00) instead of the feed
    set by 1001 (L916).  Buffer use 2 + 2 x axes (L918).
    """
    mask, words = _targets(targets)
    return [regs.CMD_LINE, mask | (regs.MASK_RAPID if rapid else 0), *words]


def encode_arc_xy(x: float, y: float, i: float, j: float, *, ccw: bool) -> Words:
    """Command 1003: circular move in XY at the current feed (L920-L928).

    Direction 0 = clockwise, 1 = counter-clockwise.  ``i``/``j`` are the
    centre **relative to the start point** of the arc (the document does not
    say; this is the G-code and Grbl convention the card's own interpreter
    follows, and the emulator implements the same).
    """
    return [regs.CMD_ARC_XY, 1 if ccw else 0, *float_words(x), *float_words(y), *float_words(i), *float_words(j)]


def encode_action(kind: int, a: int = 0, b: int = 0) -> Words:
    """Command 1010: synchronised action, always 4 registers (L1005).

    It runs just before the next buffered move (L941).  ``kind`` 1 digital
    output (a = output 0-255, b = 0/1), 2 analog output (a = 0-7, b = 0-10000 mV),
    3 holding-register write (a = address 2000-65535, b = value), 4-8 THC.
    """
    _u16(kind, "synchronised action type", 1, 8)
    if kind == regs.ACTION_DIGITAL:
        _u16(a, "digital output number", 0, 255)
        _u16(b, "digital output value", 0, 1)
    elif kind == regs.ACTION_ANALOG:
        _u16(a, "analog output number", 0, 7)
        _u16(b, "analog output value (mV)", 0, 10000)
    elif kind == regs.ACTION_REGISTER:
        _u16(a, "holding register address", 2000, 65535)
        _u16(b, "register value")
    else:
        _u16(a, "action argument")
        _u16(b, "action argument")
    return [regs.CMD_SYNC_ACTION, kind, a, b]


def encode_digital_output(output: int, on: bool) -> Words:
    return encode_action(regs.ACTION_DIGITAL, output, 1 if on else 0)


def encode_analog_output(output: int, millivolts: int) -> Words:
    return encode_action(regs.ACTION_ANALOG, output, millivolts)


def encode_register_write(address: int, value: int) -> Words:
    return encode_action(regs.ACTION_REGISTER, address, value)


def encode_dwell_ms(milliseconds: int) -> Words:
    """Command 1011: buffered dwell of 0-65535 ms (L1007-L1015)."""
    return [regs.CMD_DWELL, _u16(milliseconds, "dwell (ms)")]


def encode_dwell(seconds: float) -> list[Words]:
    """A dwell of any length as 1011 commands of at most 65535 ms each (rounded to the millisecond)."""
    if seconds < 0 or not math.isfinite(seconds):
        raise ProtocolError(f"dwell must be a non-negative time, got {seconds}")
    total = round(seconds * 1000.0)
    out = []
    while total > 0:
        chunk = min(total, 0xFFFF)
        out.append(encode_dwell_ms(chunk))
        total -= chunk
    return out


def encode_wait_input(input_number: int, kind: int, timeout_ms: int, *, alarm_on_timeout: bool = True) -> Words:
    """Command 1012 type 1: wait for a digital input; kind 1 rising, 2 falling, 3 high, 4 low (L1031-L1055)."""
    return [regs.CMD_WAIT, 1, _u16(timeout_ms, "timeout (ms)"), int(alarm_on_timeout), _u16(kind, "wait kind", 1, 4),
            _u16(input_number, "input number", 0, 255)]


def encode_wait_analog(input_number: int, kind: int, millivolts: int, timeout_ms: int, *,
                       alarm_on_timeout: bool = True) -> Words:
    """Command 1012 type 2: wait for an analog input; kind 1 below, 2 above, 3 equal (L1059-L1083)."""
    return [regs.CMD_WAIT, 2, _u16(timeout_ms, "timeout (ms)"), int(alarm_on_timeout), _u16(kind, "wait kind", 1, 3),
            _u16(millivolts, "threshold (mV)", 0, 10000), _u16(input_number, "analog input", 0, 7)]


def encode_wait_value(extended_address: int, kind: int, value: int, timeout_ms: int, *,
                      alarm_on_timeout: bool = True) -> Words:
    """Command 1012 type 3: wait for a Modbus value; kind 1 below, 2 above, 3 equal (L1087-L1121).

    The extended address encodes the table (see :mod:`.registers` on the
    document's contradictory numbering); it is sent as given.
    """
    return [regs.CMD_WAIT, 3, _u16(timeout_ms, "timeout (ms)"), int(alarm_on_timeout), _u16(kind, "wait kind", 1, 4),
            _u16(value, "value"), *u32_words(extended_address)]


# ---------------------------------------------------------------- immediate CNC commands (1100-1200)
def encode_override(feed_percent: int, rapid_percent: int) -> Words:
    """Command 1100: feed and rapid override % (heading L1125; the table's 1005 at L1133 is a misprint)."""
    return [regs.CMD_OVERRIDE, _u16(feed_percent, "feed override %"), _u16(rapid_percent, "rapid override %")]


def encode_home(axis: int = 0) -> Words:
    """Command 1110: machine homing; 0 = the whole sequence from the parameters, 1-6 one axis (L1159-L1171)."""
    return [regs.CMD_HOME, _u16(axis, "homing axis", 0, 6)]


def encode_jog(targets: Mapping[str, float], speed_mm_per_min: float, *, relative: bool = True) -> Words:
    """Command 1111: jog (only when idle or jogging) to/by ``targets`` (mm) at ``speed_mm_per_min``.

    The card takes the speed in **m/min** (L1195) - unlike 1001's mm/min -
    so the value is divided by 1000 here.  Bit 6 of the mask = relative.
    """
    if not speed_mm_per_min > 0:
        raise ProtocolError(f"jog speed must be positive, got {speed_mm_per_min}")
    mask, words = _targets(targets)
    speed = float_words(speed_mm_per_min / 1000.0)
    return [regs.CMD_JOG, mask | (regs.MASK_RELATIVE if relative else 0), *speed, *words]


def encode_direct(code: int) -> Words:
    """Command 1200: direct function (L1207-L1225)."""
    if code not in regs.DIRECT_CODES:
        raise ProtocolError(f"unknown direct function {code} (known: {sorted(regs.DIRECT_CODES)})")
    return [regs.CMD_DIRECT, code]


def encode_pause() -> Words:
    return encode_direct(regs.DIRECT_PAUSE)


def encode_resume() -> Words:
    return encode_direct(regs.DIRECT_RESUME)


def encode_stop() -> Words:
    """Immediate stop with deceleration; purges the command and planner buffers (L1225)."""
    return encode_direct(regs.DIRECT_STOP)


def encode_ack_alarm() -> Words:
    return encode_direct(regs.DIRECT_ACK_ALARM)


# ---------------------------------------------------------------- axis-level commands (100-200)
def encode_probe(axis: int, input_number: int, expected: int, accel: int, speed: int, decel: int,
                 stroke_steps: int) -> Words:
    """Command 107: probe one axis on one input (L624-L659); results in IR 1350+ (see :mod:`.registers`)."""
    return [regs.CMD_PROBE, _u16(axis, "axis", 1, 6), _u16(input_number, "input", 0, 255),
            _u16(expected, "state", 0, 1), *u32_words(accel), *u32_words(speed), *u32_words(decel),
            *i32_words(stroke_steps)]


def encode_probe_mask(axis: int, and_mask: int, xor_mask: int, accel: int, speed: int, decel: int,
                      stroke_steps: int) -> Words:
    """Command 108: probe on masked inputs DIN0-31 (L661-L696).  Its table misprints the id as 107 (L683)."""
    return [regs.CMD_PROBE_MASK, _u16(axis, "axis", 1, 6), *u32_words(and_mask), *u32_words(xor_mask),
            *u32_words(accel), *u32_words(speed), *u32_words(decel), *i32_words(stroke_steps)]


def encode_set_position(axis: int, pulses: int) -> Words:
    """Command 105: set an axis position counter (never during motion, L564)."""
    return [regs.CMD_SET_POSITION, _u16(axis, "axis", 1, 6), *i32_words(pulses)]


# ---------------------------------------------------------------- decoding
def decode_status(word: int) -> list[str]:
    """Names of the bits set in the CNC status word (input register 3003)."""
    return [name for bit, name in regs.STATUS_BITS.items() if word & bit]


def alarm_message(code: int) -> str:
    """Plain-language text of an alarm code (input register 3004)."""
    return regs.ALARMS.get(code, f"unknown alarm code {code}")


def describe_alarm(code: int) -> str:
    """``"alarm 2 (soft limit: ...)"``."""
    return f"alarm {code} ({alarm_message(code)})"


def decode_i32_list(words: list[int]) -> list[int]:
    """Consecutive signed 32-bit values, low word first."""
    return [words_i32(words[k], words[k + 1]) for k in range(0, len(words) - 1, 2)]


@dataclass
class Command:
    """A decoded command: ``cid``, ``size`` (registers) and the arguments by name."""

    cid: int
    size: int
    args: dict = field(default_factory=dict)


def _floats(words: list[int], count: int, at: int) -> list[float]:
    if len(words) < at + 2 * count:
        raise ProtocolError("command too short for its floats")
    return [words_float(words[at + 2 * k], words[at + 2 * k + 1]) for k in range(count)]


def _mask_targets(mask: int, words: list[int], at: int) -> tuple[dict[str, float], int]:
    axes = [a for k, a in enumerate(regs.CARD_AXES) if mask & (1 << k)]
    if not axes:
        raise ProtocolError("axis mask selects no axis")
    vals = _floats(words, len(axes), at)
    return dict(zip(axes, vals, strict=True)), at + 2 * len(axes)


def parse_command(words: list[int]) -> Command:
    """Decode the words of one command (id first).  Raises :class:`ProtocolError`.

    ``size`` is the number of registers the command occupies (the buffer use
    of the buffered commands); words beyond it are ignored, as the card
    ignores stale registers after a command in 2000-2149.
    """
    if not words:
        raise ProtocolError("empty command")
    cid = words[0]
    if cid == regs.CMD_GCODE:
        n = words[1] if len(words) > 1 else -1
        if n < 0 or len(words) < 2 + (n + 1) // 2:
            raise ProtocolError("1000: string shorter than its length")
        return Command(cid, 2 + (n + 1) // 2, {"text": unpack_string(words[2:2 + (n + 1) // 2], n)})
    if cid == regs.CMD_FEED:
        return Command(cid, 3, {"feed": _floats(words, 1, 1)[0]})
    if cid in (regs.CMD_LINE, regs.CMD_JOG):
        if len(words) < 2:
            raise ProtocolError(f"{cid}: missing axis mask")
        mask = words[1]
        if mask & ~0x7F:
            raise ProtocolError(f"{cid}: invalid axis mask {mask:#x}")
        at = 2
        args: dict = {}
        if cid == regs.CMD_JOG:
            args["speed_m_per_min"] = _floats(words, 1, 2)[0]
            args["relative"] = bool(mask & regs.MASK_RELATIVE)
            at = 4
        else:
            args["rapid"] = bool(mask & regs.MASK_RAPID)
        targets, end = _mask_targets(mask & 0x3F, words, at)
        args["targets"] = targets
        return Command(cid, end, args)
    if cid == regs.CMD_ARC_XY:
        if len(words) < 10 or words[1] not in (0, 1):
            raise ProtocolError("1003: needs direction 0/1 and four floats")
        x, y, i, j = _floats(words, 4, 2)
        return Command(cid, 10, {"ccw": words[1] == 1, "x": x, "y": y, "i": i, "j": j})
    if cid == regs.CMD_SYNC_ACTION:
        if len(words) < 4:
            raise ProtocolError("1010: needs type, address and value")
        encode_action(words[1], words[2], words[3])   # validates ranges
        return Command(cid, 4, {"type": words[1], "a": words[2], "b": words[3]})
    if cid == regs.CMD_DWELL:
        if len(words) < 2:
            raise ProtocolError("1011: missing duration")
        return Command(cid, 2, {"ms": words[1]})
    if cid == regs.CMD_WAIT:
        return _parse_wait(words)
    if cid == regs.CMD_OVERRIDE:
        if len(words) < 3:
            raise ProtocolError("1100: needs feed and rapid overrides")
        return Command(cid, 3, {"feed": words[1], "rapid": words[2]})
    if cid in (regs.CMD_PAUSE, regs.CMD_RESUME):
        return Command(cid, 1)
    if cid == regs.CMD_HOME:
        if len(words) < 2 or words[1] > 6:
            raise ProtocolError("1110: axis must be 0..6")
        return Command(cid, 2, {"axis": words[1]})
    if cid == regs.CMD_DIRECT:
        if len(words) < 2 or words[1] not in regs.DIRECT_CODES:
            raise ProtocolError(f"1200: unknown function code {words[1] if len(words) > 1 else None}")
        return Command(cid, 2, {"code": words[1]})
    raise ProtocolError(f"unknown or unsupported command id {cid}")


def _parse_wait(words: list[int]) -> Command:
    if len(words) < 6:
        raise ProtocolError("1012: too short")
    kind = words[1]
    base = {"type": kind, "timeout_ms": words[2], "alarm": bool(words[3]), "wait": words[4]}
    if kind == 1:
        return Command(regs.CMD_WAIT, 6, {**base, "input": words[5]})
    if kind == 2 and len(words) >= 7:
        return Command(regs.CMD_WAIT, 7, {**base, "threshold": words[5], "input": words[6]})
    if kind == 3 and len(words) >= 8:
        return Command(regs.CMD_WAIT, 8, {**base, "threshold": words[5], "address": words_u32(words[6], words[7])})
    raise ProtocolError(f"1012: unknown wait type {kind}")
