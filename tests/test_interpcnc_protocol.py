"""InterpCNC V3 protocol (seed 000): exact register words of every command, decoding, translation, options.

No I/O here; the Modbus side is in test_interpcnc_stream.py / _faults.py / _rtu.py.
"""

from __future__ import annotations

import math
import struct

import numpy as np
import pytest

import fagorcnc
from fagorcnc.backends.base import BackendError
from fagorcnc.backends.interpcnc import InterpCncBackend
from fagorcnc.backends.interpcnc import protocol as proto
from fagorcnc.backends.interpcnc import registers as regs
from fagorcnc.backends.interpcnc.translate import Encoder, chord_count, segment_moves

F = proto.float_words


# ---------------------------------------------------------------- value encodings
def test_32_bit_values_are_sent_low_word_first():
    # every LW/HW table of seed 000 (e.g. L530, L546) puts the low word at the lower address
    assert proto.u32_words(0x12345678) == [0x5678, 0x1234]
    assert proto.i32_words(-2) == [0xFFFE, 0xFFFF]
    assert proto.i32_words(-(1 << 31)) == [0x0000, 0x8000]
    assert proto.words_i32(0xFFFE, 0xFFFF) == -2
    assert proto.decode_i32_list([0x5678, 0x1234, 0xFFFF, 0xFFFF]) == [0x12345678, -1]
    with pytest.raises(proto.ProtocolError):
        proto.u32_words(1 << 32)


def test_floats_are_ieee754_single_low_word_first():
    bits = struct.unpack(">I", struct.pack(">f", 12.2))[0]
    assert bits == 0x41433333
    assert F(12.2) == [0x3333, 0x4143]
    assert F(-1.0) == [0x0000, 0xBF80]
    assert proto.words_float(0x3333, 0x4143) == proto.float32(12.2)
    with pytest.raises(proto.ProtocolError):
        F(math.nan)


def test_strings_two_characters_per_register_first_in_low_byte():
    # seed 000 L905-L915 / L858: "G0" -> 0x3047
    assert proto.pack_string("G0") == [0x3047]
    assert proto.pack_string("G") == [0x0047]           # odd length: padded with 0
    assert proto.unpack_string([0x3047, 0x0031], 3) == "G01"
    with pytest.raises(proto.ProtocolError):
        proto.pack_string("G0 X1 é")


def test_command_1000_with_the_seed_example_g01_x12_2_f3000():
    # seed 000 L872-L876: "G01 X12.2 F3000", length 15
    words = proto.encode_gcode("G01 X12.2 F3000")
    assert words[:2] == [1000, 15]
    assert words[2:] == [0x3047, 0x2031, 0x3158, 0x2E32, 0x2032, 0x3346, 0x3030, 0x0030]
    seed = [0x3047, 0x2031, 0x3158, 0x2E32, 0x2032, 0x4620, 0x3033, 0x3030]
    assert words[2:7] == seed[:5]                        # "G01 X12.2 " agrees word for word
    # the seed's last three words (" F", "30", "00") spell the text with two spaces before F:
    # its example is 16 characters although it announces 15.  The packing rule is what we implement.
    assert proto.pack_string("G01 X12.2  F3000") == seed
    assert len(words) == 2 + math.ceil(15 / 2)           # Grbl buffer use 2 + length/2 (L878)
    assert proto.parse_command(words).args["text"] == "G01 X12.2 F3000"


# ---------------------------------------------------------------- buffered commands
def test_command_1001_feed_is_a_float_despite_the_u16_text():
    # L882 says unsigned 16 bits, the table says float (L887) and the buffer use is 3 registers (L890)
    assert proto.encode_feed(3000) == [1001, *F(3000.0)]
    assert len(proto.encode_feed(3000)) == 3
    assert proto.parse_command(proto.encode_feed(1234.5)).args["feed"] == 1234.5


def test_command_1002_mask_bits_follow_card_axes_xyzabc():
    # L908-L916: bit 0 X ... bit 5 C, bit 6 rapid; floats in increasing axis order
    assert proto.encode_line({"X": 12.2, "Z": 1.0}) == [1002, 0b101, *F(12.2), *F(1.0)]
    assert proto.encode_line({"Z": 1.0, "X": 12.2}) == [1002, 0b101, *F(12.2), *F(1.0)]
    assert proto.encode_line({"A": 90.0}, rapid=True) == [1002, 0x40 | 0b1000, *F(90.0)]
    assert len(proto.encode_line({"X": 1, "Y": 2, "Z": 3})) == 2 + 2 * 3   # buffer use (L918)
    with pytest.raises(proto.ProtocolError):
        proto.encode_line({"U": 1.0})
    cmd = proto.parse_command(proto.encode_line({"Y": -3.5}, rapid=True))
    assert cmd.args == {"rapid": True, "targets": {"Y": -3.5}} and cmd.size == 4


def test_command_1003_arc_direction_and_ij():
    words = proto.encode_arc_xy(10.0, 0.0, 5.0, 0.0, ccw=False)
    assert words == [1003, 0, *F(10.0), *F(0.0), *F(5.0), *F(0.0)]   # 0 = CW (L928)
    assert proto.encode_arc_xy(1, 2, 3, 4, ccw=True)[1] == 1
    assert len(words) == 10
    assert proto.parse_command(words).args == {"ccw": False, "x": 10.0, "y": 0.0, "i": 5.0, "j": 0.0}


def test_command_1010_synchronised_actions_are_four_registers():
    assert proto.encode_digital_output(3, True) == [1010, 1, 3, 1]
    assert proto.encode_analog_output(0, 10000) == [1010, 2, 0, 10000]
    assert proto.encode_register_write(3000, 65535) == [1010, 3, 3000, 65535]
    assert proto.encode_action(regs.ACTION_THC_ON_SAMPLED, 250) == [1010, 5, 250, 0]
    for bad in ((1, 256, 0), (1, 0, 2), (2, 8, 0), (2, 0, 10001), (3, 1999, 0), (9, 0, 0)):
        with pytest.raises(proto.ProtocolError):
            proto.encode_action(*bad)


def test_command_1011_dwell_is_split_into_65535_ms_pieces():
    assert proto.encode_dwell(0.5) == [[1011, 500]]
    assert proto.encode_dwell(150.0) == [[1011, 65535], [1011, 65535], [1011, 18930]]
    assert proto.encode_dwell(0.0) == []
    assert sum(w[1] for w in proto.encode_dwell(1000.0004)) == 1_000_000
    with pytest.raises(proto.ProtocolError):
        proto.encode_dwell(-1)


def test_command_1012_waits():
    assert proto.encode_wait_input(7, 3, 2000) == [1012, 1, 2000, 1, 3, 7]
    assert proto.encode_wait_analog(1, 2, 4500, 100, alarm_on_timeout=False) == [1012, 2, 100, 0, 2, 4500, 1]
    assert proto.encode_wait_value(103003, 3, 0, 500) == [1012, 3, 500, 1, 3, 0, *proto.u32_words(103003)]
    assert proto.parse_command(proto.encode_wait_value(103003, 3, 0, 500)).args["address"] == 103003


# ---------------------------------------------------------------- immediate commands
def test_command_1100_override_uses_the_heading_id_not_the_table_misprint_1005():
    assert proto.encode_override(120, 50) == [1100, 120, 50]
    assert regs.CMD_OVERRIDE == 1100 and regs.CMD_OVERRIDE_TABLE_MISPRINT == 1005
    with pytest.raises(proto.ProtocolError):
        proto.parse_command([1005, 100, 100])


def test_command_1110_homing_and_1111_jog_speed_in_metres_per_minute():
    assert proto.encode_home() == [1110, 0]
    assert proto.encode_home(3) == [1110, 3]
    # L1195: the jog speed is in m/min, while 1001 takes mm/min
    words = proto.encode_jog({"X": 5.0, "Z": -1.0}, 3000.0)
    assert words == [1111, 0x40 | 0b101, *F(3.0), *F(5.0), *F(-1.0)]
    assert proto.encode_jog({"Y": 10.0}, 600.0, relative=False)[1] == 0b10
    assert proto.parse_command(words).args["speed_m_per_min"] == 3.0


def test_command_1200_direct_functions():
    assert proto.encode_ack_alarm() == [1200, 88]
    assert proto.encode_resume() == [1200, 129]
    assert proto.encode_pause() == [1200, 130]
    assert proto.encode_stop() == [1200, 255]
    assert proto.encode_direct(138) == [1200, 138]
    with pytest.raises(proto.ProtocolError):
        proto.encode_direct(131)


def test_documented_inconsistencies_are_pinned():
    # 107 vs 108: the table of command 108 misprints its id as 107 (L683); the heading says 108 (L661)
    assert proto.encode_probe_mask(1, 0xFF, 0, 100, 200, 100, -5000)[0] == 108
    assert proto.encode_probe(1, 4, 1, 100, 200, 100, 5000)[0] == 107
    # probe results: the table (L406) says IR 1350, the texts (L257, L640, L677) 1330
    assert (regs.IR_PROBE_POSITION, regs.IR_PROBE_POSITION_TEXT) == (1350, 1330)
    # TCP clients: 6 (L85) vs "10 maxi" in the IR 1220 text (L303)
    assert (regs.MAX_TCP_CLIENTS, regs.MAX_TCP_CLIENTS_IR1220_TEXT) == (6, 10)
    # 1001 float (not u16), 1111 m/min vs 1001 mm/min, 1100 vs 1005: see the tests above
    assert regs.CMD_PROBE_MASK == 108


# ---------------------------------------------------------------- decoding
def test_status_word_and_alarm_codes_in_plain_language():
    assert proto.decode_status(0b1_0000_1001) == ["alarm", "cycle running", "emergency stop active"]
    assert proto.decode_status(0) == []
    assert set(regs.ALARMS) == set(range(19))                      # 0..18 (L430)
    assert "soft limit" in proto.alarm_message(2)
    assert "emergency stop" in proto.alarm_message(10)
    assert "1012" in proto.alarm_message(18)
    assert proto.alarm_message(99) == "unknown alarm code 99"
    assert proto.describe_alarm(2).startswith("alarm 2 (soft limit")


def test_parse_command_rejects_garbage():
    for words in ([], [4242], [1002, 0], [1002, 0x80, 0, 0], [1003, 2] + [0] * 8, [1200, 7], [1010, 1, 0]):
        with pytest.raises(proto.ProtocolError):
            proto.parse_command(words)


# ---------------------------------------------------------------- translation
def _segments(text: str):
    result = fagorcnc.simulate(text)
    assert result.ok, result.diagnostics
    return result.machine, list(result.segments(keep_profiles=False))


def test_xy_arcs_become_1003_split_at_180_degrees_with_ij_relative_to_the_start():
    machine, segs = _segments("G90 G0 X10 Y0\nG1 F600\nG3 X-10 Y0 I-10 J0\n")
    arcs = [s for s in segs if s.kind == "motion" and s.record.kind == "arc"]
    moves = [m for s in arcs for m in segment_moves(s, (0, 1), 0.005)]
    assert all(m.is_arc and m.ccw for m in moves)
    enc = Encoder(machine.axis_names, {a: a for a in machine.axis_names})
    enc.encode(segment_moves(segs[0], (0, 1), 0.005))
    words = enc.encode(moves)
    cmds = [proto.parse_command(w) for w in words]
    arc_cmds = [c for c in cmds if c.cid == 1003]
    assert arc_cmds and cmds[0].cid == 1001                          # feed first
    x, y = 10.0, 0.0
    for c in arc_cmds:                                               # centre (0, 0) every time
        assert abs(x + c.args["i"]) < 1e-5 and abs(y + c.args["j"]) < 1e-5
        x, y = c.args["x"], c.args["y"]
    assert x == -10.0 and abs(y) < 1e-9


def test_full_circle_is_never_one_1003_command():
    _, segs = _segments("G90 G0 X10 Y0\nG1 F600\nG2 X10 Y0 I-10 J0\n")
    moves = [m for s in segs if s.kind == "motion" and s.record.kind == "arc"
             for m in segment_moves(s, (0, 1), 0.005)]
    sweeps = []
    for m in moves:
        a0 = math.atan2(m.start[1], m.start[0])
        a1 = math.atan2(m.end[1], m.end[0])
        sweeps.append((a0 - a1) % (2 * math.pi))
    assert len(moves) >= 2 and all(0 < s <= math.pi + 1e-9 for s in sweeps)
    assert math.isclose(sum(sweeps), 2 * math.pi, rel_tol=1e-9)


def test_helix_and_other_planes_become_chords_within_the_tolerance():
    _, segs = _segments("G90 G0 X10 Y0 Z0\nG1 F600\nG3 X-10 Y0 Z-2 I-10 J0\nG18 G2 X10 Z-2 I10 K0\n")
    tol = 0.005
    for s in (s for s in segs if s.kind == "motion" and s.record.kind == "arc"):
        moves = segment_moves(s, (0, 1), tol)
        assert all(not m.is_arc for m in moves)
        assert len(moves) == chord_count(s.piece, tol)
        # the curve between chord ends stays within the tolerance of the chord
        ss = np.linspace(0, s.piece.length, 400)
        q, _, _, _ = s.piece.derivatives(ss)
        pts = np.array([m.end for m in moves])
        starts = np.array([m.start for m in moves])
        for p in q:
            d = min(_point_segment(p, a, b) for a, b in zip(starts, pts, strict=True))
            assert d <= tol * 1.01
        assert np.allclose(moves[-1].end, s.piece.end)


def _point_segment(p, a, b):
    d = b - a
    t = 0.0 if not d.any() else min(1.0, max(0.0, float((p - a) @ d / (d @ d))))
    return float(np.linalg.norm(p - (a + t * d)))


def test_a_line_carries_only_the_axes_that_change_and_feed_only_when_it_changes():
    machine, segs = _segments("G90 G1 X1 Y0 F3000\nG1 X2\nG1 X2 Y1 F3000\nG1 X3 Y2 F1000\nG0 Z5\n")
    enc = Encoder(machine.axis_names, {a: a for a in machine.axis_names})
    cmds = []
    for s in segs:
        cmds += [proto.parse_command(w) for w in enc.encode(segment_moves(s, (0, 1), 0.005))]
    kinds = [(c.cid, tuple(c.args.get("targets", {}))) for c in cmds]
    assert kinds[0] == (1001, ())
    assert kinds[1] == (1002, ("X", "Y", "Z"))                     # first move: every axis
    assert kinds[2:] == [(1002, ("X",)), (1002, ("Y",)), (1001, ()), (1002, ("X", "Y")), (1002, ("Z",))]
    assert cmds[-1].args["rapid"] and not cmds[-2].args["rapid"]


# ---------------------------------------------------------------- options
def test_options_validation_names_the_key():
    machine = fagorcnc.simulate("G0 X0\n").machine
    cases = [
        ({"hots": "x"}, "hots"),
        ({"port": 70000}, "port"),
        ({"chordal_tolerance": 0}, "chordal_tolerance"),
        ({"outputs": {"M3": {"type": 9}}}, "outputs.M3.type"),
        ({"outputs": {"M3": {"type": 1, "output": 0}}}, "outputs.M3.value"),
        ({"outputs": {"M3": {"type": 1, "output": 0, "value": 1, "scale": 2}}}, "outputs.M3.scale"),
        ({"outputs": {"S": {"type": 2, "output": 0}}}, "outputs.S"),
        ({"outputs": {"Q3": {"type": 1, "output": 0, "value": 1}}}, "outputs.Q3"),
        ({"outputs": {"T": {"type": 3, "register": 3990, "scale": 1}}}, "outputs.T.register"),  # the markers
        # seed 000 L564: the position counters are never changed during a move; L476: the card's parameters
        ({"outputs": {"T": {"type": 3, "register": 2401, "scale": 1}}}, "outputs.T.register"),
        ({"outputs": {"T": {"type": 3, "register": 32010, "scale": 1}}}, "outputs.T.register"),
        ({"outputs": {"T": {"type": 3, "register": 62000, "scale": 1}}}, "outputs.T.register"),
        ({"resolution": {"W": 100}}, "resolution.W"),
        ({"outputs": {"M3": [], "M03": []}}, "outputs.M03"),
        ({"axis_map": {"Z": "Q"}}, "axis_map.Z"),
        ({"marker_register": 4000}, "marker_register"),
        ({"strict_outputs": "yes"}, "strict_outputs"),
    ]
    for options, key in cases:
        with pytest.raises(BackendError) as err:
            InterpCncBackend(machine, **options)
        assert key in str(err.value), (options, str(err.value))


def test_a_register_action_may_write_user_registers_and_overrides():
    machine = fagorcnc.simulate("G0 X0\n").machine
    for register in (2150, 2412, 2430, 3000, 3989, 3993, 4000, 4999, 31999, 36000, 61999):
        InterpCncBackend(machine, outputs={"T": {"type": 3, "register": register, "scale": 1}})


def test_outputs_schema_and_unmapped_functions_are_reported_before_streaming():
    machine, segs = _segments("G90 G0 X0 Y0\nM3 S1200\nM8\nT5\nG1 X1 F100\nM5\nM30\n")
    backend = InterpCncBackend(machine, outputs={
        "m03": {"type": 1, "output": 0, "value": 1},                  # read as M3
        "M5": [{"type": 1, "output": 0, "value": 0}, {"type": 2, "output": 0, "value": 0}],
        "S": {"type": 2, "output": 0, "scale": 10},
    })
    problems = backend.check(segs)
    assert [p.split(":")[0] for p in problems] == ["line 3", "line 4"]     # M8 and T5; M30 is ignored by default
    assert "M8" in problems[0] and "T5" in problems[1]
    s = backend.actions_for("S", 1200)[0]
    assert s.resolve(1200) == (10000, True)                            # 12000 mV clamped to 10000
    assert len(backend.actions_for("M", 5)) == 2
    strict = InterpCncBackend(machine, strict_outputs=True, outputs={})
    assert strict.check(segs)


def test_machine_table_is_read_and_keyword_options_override_it():
    machine = fagorcnc.simulate("G0 X0\n").machine
    machine.backends = {"interpcnc": {"host": "10.0.0.7", "port": 1502, "resolution": 800}}
    backend = InterpCncBackend(machine, port=15020)
    assert (backend.options.host, backend.options.port) == ("10.0.0.7", 15020)
    assert backend.options.resolution == {"X": 800.0, "Y": 800.0, "Z": 800.0}
    assert backend.name == "interpcnc"
