"""Register map and command ids of the SOPROLEC InterpCNC V3 (seed 000, "Protocole de communication MODBUS").

Addresses are Modbus protocol addresses (0-based, as written in the
document).  Every constant cites the seed line that defines it.  The
document contradicts itself in several places; each contradiction is
spelled out next to the constant this package uses, and the tests pin the
choice (``tests/test_interpcnc_protocol.py``).

Contradictions and the choice made:

* Command 1100 (overrides): the heading says 1100 (L1125), the table's value
  row says 1005 (L1133).  We use **1100**; the back-end avoids the question
  altogether by writing holding registers 2430/2431 (L455-L456, L1129).
* Command 108 (probe on several inputs): its table repeats id 107 (L683).
  We use **108** (heading L661, table of contents L39).
* Probe results: the command texts say input registers 1330-1341 (L640,
  L677, also the example L257), the input-register table lists 1350-1361
  (L406-L417).  We use the table, **1350**.
* Command 1001 (feed): the text says unsigned 16 bits (L882), the table
  says float (L887) and the buffer use is 3 registers (L890), which only
  fits a 32-bit value.  We send a **float** (2 registers).
* Command 1111 (jog): the speed is in **m/min** (L1195) while 1001 takes
  mm/min (L880).  The encoder takes mm/min and converts.
* TCP server clients: at most **6** (L85); the input register 1220 text
  says 10 (L303).
* Buffered CNC commands are said to be numbered 1000-1999 and immediate
  ones 2000-2999 (L828-L830), but the immediate commands documented are
  1100-1200 (L1125-L1225).  The ids of the command descriptions win.
* Planner free space: the table puts it in input register 3002 and the
  planner size in 2992 (L425, L428); the prose says the free space is in
  2992 (L850).  We read **3002** for free space and 2992 for the size.
* Extended addresses (index table, command 1012): L460 and L1113-L1115 give
  input registers 0-65535 and holding registers 100000-165535, but the
  worked example (L775) and the PLC note (L250) use 100000+ for *input*
  registers and plain addresses for holding registers.  This package does
  not use the index table for that reason; :func:`encode_wait_value` takes
  the extended address as given.  The back-end's gate (a 1012 wait on a
  user register) follows the 1012 description itself: 100000 + r; its default register
  (``DEFAULT_MARKER_REGISTER``) is chosen so that a card reading it the other way stops with alarm 18
  at the first gate instead of opening gates by itself.
* Command 1000 example (L872-L876): "G01 X12.2 F3000" has 15 characters but
  the example shows 8 registers whose sixth word 0x4620 is " F": the words
  spell "G01 X12.2  F3000" (two spaces).  The packing rule (first character
  in the low byte, L858, L870) is unambiguous and is what we implement.
"""

from __future__ import annotations

# ---------------------------------------------------------------- transport
#: Default Modbus TCP port of the card (seed 000 L83; standard Modbus port).
DEFAULT_TCP_PORT = 502
#: Maximum simultaneous TCP clients in server mode (L85).  Input register 1220's
#: description says "10 maxi" (L303): the document is inconsistent; 6 is the rule.
MAX_TCP_CLIENTS = 6
MAX_TCP_CLIENTS_IR1220_TEXT = 10
#: UDP discovery port and request payload (L89-L91).
DISCOVERY_UDP_PORT = 58080
DISCOVERY_REQUEST = b"0 1"
#: USB CDC identifiers (L107).
USB_VID, USB_PID = 0x0483, 0x5740
#: Function 16 writes at most 123 registers (Modbus specification); the
#: command buffer is 150 registers long (L447), so longer commands are split.
MAX_WRITE_REGISTERS = 123

# ---------------------------------------------------------------- input registers (3X), L244-L439
IR_INPUTS = 1000                 # IN0..IN255 as 16 words (L259)
IR_STATUS_BITS = 1016            # axis moving (low byte) / direction (high byte) (L260)
IR_AXIS_POSITION = 1030          # AXE1..AXE6 position counters, pulses, int32 LW first (L264)
IR_AXIS_SPEED = 1042             # current axis speeds, int32 (L265)
IR_TARGET_POSITION = 1060        # current target positions (L266)
IR_TARGET_SPEED = 1072           # current target speeds (L267)
IR_ANALOG_INPUTS = 1090          # AIN0..AIN7 (L268)
IR_CPU_LOAD = 1100               # (L269)
IR_FIRMWARE_VERSION = 1115       # high, 1116 low (L275-L276)
IR_TCP_CLIENTS = 1220            # TCP clients connected (L303)
#: Probe positions per axis, int32 (table L406-L417).  The probe command texts
#: say 1330-1341 (L257, L640, L677): inconsistent, the table wins.
IR_PROBE_POSITION = 1350
IR_PROBE_POSITION_TEXT = 1330
IR_CNC_BUFFER_SIZE = 2990        # size of the CNC Modbus command buffer, registers (L423)
IR_GRBL_BUFFER_SIZE = 2991       # size of the Grbl command buffer (L424)
IR_PLANNER_SIZE = 2992           # size of the CNC planner buffer, entries (L425)
IR_CNC_BUFFER_FREE = 3000        # free registers in the CNC Modbus buffer, max 4096 (L426)
IR_GRBL_BUFFER_FREE = 3001       # free space in the Grbl buffer, max 1024 (L427)
IR_PLANNER_FREE = 3002           # free planner entries, max 35 (L428)
IR_CNC_STATUS = 3003             # CNC status bits, see STATUS_BITS (L429)
IR_ALARM_CODE = 3004             # CNC alarm code, see ALARMS (L430)
IR_CNC_FEED = 3010               # current CNC feed, uint32 mm/min, 3010-3011 (L431)
IR_THC_STATUS = 3012             # (L432)
IR_ARC_VOLTAGE = 3013            # int32 mV, 3013-3014 (L435)

#: The five registers a streaming client polls in one request (3000-3004).
POLL_FIRST, POLL_COUNT = IR_CNC_BUFFER_FREE, 5

# ---------------------------------------------------------------- holding registers (4X), L441-L480
HR_COMMAND = 2000                # command buffer 2000-2149: id then arguments (L447, L484)
HR_COMMAND_SIZE = 150
HR_ANALOG_OUTPUTS = 2150         # AOUT0..AOUT7, mV (L448)
HR_DIGITAL_OUTPUTS = 2160        # OUT0..OUT95, 16 per register (L449)
HR_USER_BITS = 2166              # (L450)
HR_AXIS_POSITION = 2400          # position counters, int32 (L453)
HR_AXIS_SPEED = 2412             # pulses/s (L454)
HR_FEED_OVERRIDE = 2430          # CNC feed override % (L455)
HR_RAPID_OVERRIDE = 2431         # CNC rapid override % (L456)
HR_THC_SETPOINT = 2444           # uint32 mV (L457)
HR_INDEX_TABLE = 2800            # 50 x 32-bit indexes (L460, L742)
HR_INDEXED_VALUES = 2900         # (L743)
HR_USER_RAM = 3000               # user registers in RAM, 3000-3999 (L463)
HR_USER_RAM_LAST = 3999
#: Default ``marker_register`` (the back-end's sequence number, move index and gate: this and the next two).
#: High in user RAM, for two reasons.  1012's extended address follows one of two contradictory conventions
#: (holding registers at 100000 + r: L460, L1113-L1115; *input* registers at 100000 + r: L250, the worked example
#: L775-L791, L1291).  Under the second, a gate on holding 3002 would watch IR 3002, the planner free space, and
#: open by itself; no input register is documented between 3014 and 11000 (map L259-L435), so a gate on 3992 read
#: the wrong way watches a register that stays 0 and the first gate never opens: alarm 18, loud, instead of outputs
#: run at random.  And an embedded PLC Basic program (L71-L75, L842) most likely uses the first user registers.
DEFAULT_MARKER_REGISTER = 3990
HR_USER_SAVED = 4000             # saved user registers 4000-4999 (L464) - written to flash: not for markers
HR_PARAMETERS = 32000            # card parameters, index 0-1999, 32 bits each (L177-L179, L476)
PARAM_AXIS_RESOLUTION = 1100     # parameters 1100-1105: axis resolutions (L900)

# ---------------------------------------------------------------- command ids
# axis-level immediate commands (L496-L734)
CMD_STOP_AXIS = 100
CMD_STOP_AXES = 101
CMD_SET_POSITION = 105
CMD_PROBE = 107
#: The table of command 108 repeats 107 (L683); heading L661 says 108.
CMD_PROBE_MASK = 108
CMD_FORCE_INPUT = 110
CMD_PLC_BASIC = 200
# buffered CNC commands (L854-L1121): go through the CNC Modbus buffer, synchronised with the planner
CMD_GCODE = 1000                 # to the Grbl buffer, not the Modbus one (L862)
CMD_FEED = 1001
CMD_LINE = 1002
CMD_ARC_XY = 1003
CMD_SYNC_ACTION = 1010
CMD_DWELL = 1011
CMD_WAIT = 1012
BUFFERED_COMMANDS = frozenset({CMD_FEED, CMD_LINE, CMD_ARC_XY, CMD_SYNC_ACTION, CMD_DWELL, CMD_WAIT})
# immediate CNC commands (L1123-L1225)
CMD_OVERRIDE = 1100
CMD_OVERRIDE_TABLE_MISPRINT = 1005   # L1133
CMD_PAUSE = 1101                 # prefer 1200/130 (L1137)
CMD_RESUME = 1102                # prefer 1200/129 (L1149)
CMD_HOME = 1110
CMD_JOG = 1111
CMD_DIRECT = 1200

# sub-codes of command 1200 (L1217-L1225)
DIRECT_ACK_ALARM = 88
DIRECT_RESUME = 129
DIRECT_PAUSE = 130               # also stops the spindle; buffers kept
DIRECT_STOP_JOG = 133
DIRECT_FEED_OVERRIDE_100 = 138
DIRECT_RAPID_OVERRIDE_100 = 143
DIRECT_SPINDLE_OVERRIDE_100 = 153
DIRECT_STOP = 255                # stop with deceleration, purges command and planner buffers
DIRECT_CODES = frozenset({88, 129, 130, 133, 138, 143, 153, 255})

# synchronised action types of command 1010 (L947-L1005)
ACTION_DIGITAL = 1               # output 0-255, value 0/1
ACTION_ANALOG = 2                # output 0-7, 0-10000 mV
ACTION_REGISTER = 3              # holding register 2000-65535, value 0-65535
ACTION_THC_ON = 4
ACTION_THC_ON_SAMPLED = 5
ACTION_THC_STOP = 6
ACTION_THC_PAUSE = 7
ACTION_THC_RESUME = 8

# ---------------------------------------------------------------- command 1012 (L1017-L1121)
WAIT_VALUE = 3                   # wait type 3: a Modbus value
WAIT_ABOVE = 2                   # wait until the value is above the threshold (L1105)
EXTENDED_HOLDING = 100000        # 1012's 32-bit address of holding register r is 100000 + r (L1115)

# 1002 / 1111 axis mask (L908-L916, L1197-L1205)
CARD_AXES = ("X", "Y", "Z", "A", "B", "C")   # bit 0..5
MASK_RAPID = 0x40                # 1002: bit 6 = maximum speed
MASK_RELATIVE = 0x40             # 1111: bit 6 = relative positions

# ---------------------------------------------------------------- status word IR 3003 (L429)
STATUS_ALARM = 1 << 0
STATUS_TEST_MODE = 1 << 1
STATUS_HOMING = 1 << 2
STATUS_CYCLE = 1 << 3
STATUS_PAUSED = 1 << 4
STATUS_JOG = 1 << 5
STATUS_DOOR = 1 << 6
STATUS_SLEEP = 1 << 7
STATUS_ESTOP = 1 << 8
STATUS_TOOL_CHANGE = 1 << 9

STATUS_BITS: dict[int, str] = {
    STATUS_ALARM: "alarm",
    STATUS_TEST_MODE: "G-code test mode",
    STATUS_HOMING: "homing in progress",
    STATUS_CYCLE: "cycle running",
    STATUS_PAUSED: "paused (feed hold)",
    STATUS_JOG: "jogging",
    STATUS_DOOR: "door safety active",
    STATUS_SLEEP: "sleep mode",
    STATUS_ESTOP: "emergency stop active",
    STATUS_TOOL_CHANGE: "manual tool change in progress",
}

#: Status bits that forbid starting a stream (L429): G-code test mode, homing, a feed hold, a jog, door
#: safety, sleep, a manual tool change.  The card is moving on its own or would not run (or not really run)
#: the moves: a stream then never completes, or starts from a position nobody planned.  Door safety is
#: included: L429 only names it ("Sécurité porte active"), nothing in the document says it is harmless at
#: rest.  Bit 8 (emergency stop) comes with alarm 10 and is handled as an alarm.
STATUS_NOT_READY = (STATUS_TEST_MODE | STATUS_HOMING | STATUS_PAUSED | STATUS_JOG | STATUS_DOOR | STATUS_SLEEP
                    | STATUS_TOOL_CHANGE)
#: Status bits that hold a stream in the middle (L429): a feed hold (also from a hardware input, L1141) or the door
#: safety.  The back-end then reports the state "pause", and back to "run" when they clear.
STATUS_HELD = STATUS_PAUSED | STATUS_DOOR
#: IR 1016 low byte: one bit per axis still moving (L260; L512: "check that the axes have really stopped").
AXES_MOVING_MASK = 0x00FF

# ---------------------------------------------------------------- alarm codes IR 3004 (L430)
ALARM_SOFT_LIMIT = 2
ALARM_ESTOP = 10
ALARM_WAIT_TIMEOUT = 18

#: Plain-language alarm messages, for the machinist (translated from L430).
ALARMS: dict[int, str] = {
    0: "no alarm",
    1: "limit switch hit",
    2: "soft limit: a move would leave the machine's travel",
    3: "cycle aborted",
    4: "probe: wrong initial state of the probe contact",
    5: "probe: contact not detected",
    6: "homing: initialisation error",
    7: "homing: door opened during homing",
    8: "homing: the home switch stays engaged after clearing",
    9: "homing: home switch not found within the machine travel",
    10: "emergency stop engaged",
    11: "homing required before moving",
    12: "probe: abnormal contact detected",
    13: "tool setter triggered during a cycle or a jog",
    14: "spindle-ready signal timed out",
    15: "master/slave axis gap exceeded its tolerance",
    16: "internal error of the card",
    17: "motor fault input active",
    18: "timed out waiting for an event (command 1012)",
}

#: Alarms after which the machine position can no longer be trusted (L430): a limit switch hit (1: a hard
#: stop, and continuing drives further toward the limit), homing errors and homing required (6-9, 11), the
#: tool setter triggered during a cycle or a jog (13), the master/slave gap exceeded (15: a racked gantry),
#: an internal error (16) and a motor fault (17: lost steps).  The step counters may not match the machine:
#: the interrupted program is not continued (see InterpCncBackend.resume and abandon).
ALARMS_POSITION_LOST = frozenset({1, 6, 7, 8, 9, 11, 13, 15, 16, 17})
