"""Diagnostics: every problem fagorcnc reports, with a stable code.

A diagnostic names the file, line and column (1-based), a stable code a CI
user can filter on, a severity and a message written for a machinist.
``str(diagnostic)`` gives ``file:line:col: CODE message``;
:meth:`Diagnostic.render` adds the source line with a caret under the column.

Codes are grouped by stage: ``SYN`` syntax of a block, ``STR`` program
structure (headers, subroutines, labels, ``$`` nesting), ``INT`` the
interpreter, ``CFG`` the machine configuration, ``KIN`` kinematics and coordinate
transformations (fagorcnc.kinematics).  Later stages add their own prefixes.  A code, once published, keeps its meaning.
interpreter, ``CFG`` the machine configuration.  Later stages add their own
prefixes (``PLN`` the planner, ``BCK`` a back-end while it runs).  A code, once published, keeps its meaning.
"""

from __future__ import annotations

from dataclasses import dataclass

#: The code prefixes, by stage or feature: a code is its prefix and three digits.
PREFIXES: dict[str, str] = {
    "SYN": "syntax of a block",
    "STR": "program structure: headers, subroutines, labels, $ nesting",
    "INT": "the interpreter",
    "MAC": "macros (#DEF)",
    "CYC": "canned cycles",
    "KIN": "kinematics and coordinate transformations",
    "CAM": "constructs CAM posts write (compatibility policy) and the machinist's lint",
    "CFG": "the machine configuration and what a back-end can do",
    "BCK": "a back-end while it runs",
    "PLN": "the planner and the planned motion",
    "CHK": "fagorcnc check",
    "CLI": "the fagorcnc command's tools",
}

#: Every code the front end emits, with a one-line description.
CODES: dict[str, str] = {
    "SYN001": "unexpected character",
    "SYN002": "unexpected word or symbol",
    "SYN003": "block ends too early",
    "SYN004": "comment '(' not closed on its line",
    "SYN005": "lower-case letter where the language needs a capital",
    "SYN006": "expression with an operator must be in [ ] as an ISO word value",
    "SYN007": "only one # sentence per block",
    "SYN008": "only one $ instruction per block (except $IF ... $GOTO)",
    "SYN009": "'/' or 'N..:' not at the start of the block",
    "SYN010": "invalid label or name (1-14 letters and digits)",
    "SYN011": "block number out of range 0..4294967295",
    "SYN012": "unknown # sentence",
    "SYN013": "unknown or missing keyword of a # sentence",
    "SYN014": "# sentence must be alone in its block",
    "SYN015": "function with the wrong number of arguments",
    "SYN016": "bracket list used where a single value is expected",
    "SYN017": "#COMMENT BEGIN without #COMMENT END",
    "SYN018": "#COMMENT END without #COMMENT BEGIN",
    "SYN019": "unknown function",
    "SYN020": "text where a block was expected",
    "SYN021": "text string not closed",
    "SYN022": "unknown $ instruction",
    "SYN023": "not a program text file (NUL bytes: binary, or UTF-16 without a byte-order mark)",
    # hardening (issue 30): limits of what a block or a file may hold
    "SYN040": "expression nested too deeply",
    "SYN041": "line longer than fagorcnc reads (16384 characters)",
    "STR001": "local subroutines defined but no program header %name",
    "STR002": "local subroutine defined after the program body",
    "STR003": "subroutine does not end with M17, M29 or #RET",
    "STR004": "duplicate jump label or block number",
    "STR005": "$ instruction without its opening instruction",
    "STR006": "$ structure not closed",
    "STR007": "$ instruction in the wrong place in its structure",
    "STR008": "duplicate local subroutine name",
    "STR009": "$BREAK or $CONTINUE outside a loop",
    "STR010": "second program header",
    "STR011": "bare program name taken as the program header",
    "STR012": "the file has no block to execute (fagorcnc check)",
    # interpreter
    "INT010": "unknown G function",
    "INT011": "G function not supported by fagorcnc yet",
    "INT012": "incompatible G functions in one block",
    "INT013": "origin change while #MCS ON is active",
    "INT014": "G157 value other than 0 or 1",
    "INT015": "G159 without a valid entry number",
    "INT016": "G174 with other than one axis",
    "INT017": "dwell without a valid time",
    "INT018": "G30 with only one of I, J",
    "INT019": "negative polar radius",
    "INT020": "unknown spindle",
    "INT021": "more than 7 M or H functions in one block",
    "INT022": "generic axis ?n that designates no axis",
    "INT023": "axis or letter written twice in one block",
    "INT024": "axis that does not exist on this machine",
    "INT025": "word not meaningful in this block",
    "INT026": "unidirectional rotary axis moved the wrong way",
    "INT027": "negative spindle speed",
    "INT028": "NR in a block without motion",
    "INT029": "invalid feed",
    "INT030": "numeric overflow",
    "INT031": "bitwise operator on a value that is not 0..4294967295",
    "INT032": "function argument out of its domain",
    "INT033": "division by zero",
    "INT034": "not a number",
    "INT035": "parameter index not an integer",
    "INT036": "value must be a whole number",
    "INT037": "value out of range",
    "INT040": "parameter read before it has a value",
    "INT041": "parameter outside the configured ranges",
    "INT042": "too many local parameter levels",
    "INT043": "user variable read before it has a value",
    "INT044": "unknown variable",
    "INT045": "table entry or fixture number out of range",
    "INT046": "axis of a variable does not exist",
    "INT047": "channel of a variable does not exist",
    "INT048": "write to a read-only variable",
    "INT049": "#DELETE of something that is not a user variable",
    "INT050": "tool not in the tool table",
    "INT051": "tool offset D not defined for the tool",
    "INT060": "G01/G02/G03 without a feed",
    "INT061": "arc without centre or radius",
    "INT062": "arc start and end radius differ",
    "INT063": "motion not allowed in #MCS",
    "INT064": "arc radius impossible for the end point",
    "INT065": "feed per revolution without spindle speed",
    "INT066": "invalid G20 plane definition",
    "INT067": "invalid G74 home search",
    "INT068": "G08/G09 arc without what it needs",
    "INT069": "invalid G31 or helix pitch",
    "INT070": "#ERROR in the program",
    "INT071": "malformed # sentence",
    "INT072": "$FOR step 0",
    "INT073": "jump target not found",
    "INT074": "jump into a $ structure",
    "INT075": "invalid #RPT range",
    "INT076": "#WARNING in the program",
    "INT077": "#MSG in the program",
    "INT078": "# sentence not computed by fagorcnc yet",
    "INT079": "# sentence without effect offline",
    "INT080": "runaway program: block limit reached",
    "INT081": "runaway loop: iteration limit reached (a loop, or an NR or #RPT count above it)",
    "INT082": "runaway program: interpretation time limit reached",
    "INT083": "too many warnings and notes: the rest are not reported",
    "INT085": "corner aid G36-G39 impossible here",
    "INT086": "radius compensation impossible or not supported here",
    # radius compensation: profile modified (seed 002 L9455-L9459) and missing tool offsets (issue 21)
    "INT120": "radius compensation: a block too short for the tool is not executed (profile modified)",
    "INT121": "radius compensation: an arc the tool cannot follow is not executed (profile modified)",
    "INT122": "radius compensation: a gap narrower than the tool is not machined (profile modified)",
    "INT123": "tool offset not in the tool table",
    "INT090": "local subroutine calls one defined after it",
    "INT091": "local subroutine not defined",
    "INT092": "global subroutine file has errors",
    "INT093": "global subroutine not found",
    "INT094": "invalid subroutine argument",
    "INT095": "subroutine nesting too deep",
    "INT096": "OEM G function without a subroutine",
    "INT097": "end of subroutine outside a subroutine",
    "INT098": "program ends without M02 or M30",
    "INT099": "global subroutine without M17/M29/#RET",
    "INT100": "position beyond a software limit",
    "INT110": "invalid #HSC statement",
    "INT111": "invalid #ROUNDPAR or #SLOPE statement",
    "INT112": "invalid acceleration, jerk or feed-forward percentage",
    "INT113": "corner or override function in the wrong block",
    "INT114": "G193 needs linear acceleration",
    "INT115": "corner rounding type not modelled",
    "INT116": "local subroutine called by its number with an L in front (#CALL L100)",
    "INT117": "invalid #SWTOUT or #PWMOUT statement (laser functions)",
    "INT118": "function that must be alone in its block is not (G30, #MCS ON/OFF)",
    "INT119": "function that needs another channel or an interrupt subroutine (#EXBLK to channel n, #REPOS)",
    "INT170": "manual intervention G200: the program waits for the operator (offline nothing moves by hand)",
    "INT171": "invalid manual intervention (G200-G202 #AXIS, #CONTJOG, #INCJOG, #MPG, #SET OFFSET, #SYNC POS)",
    # axis configuration of the channel and coupled axes (interp/axes.py; seed 002 ch. 21.1.6-21.1.8)
    "INT200": "axis that is not in the channel's axis configuration (#FREE AX, #SET AX, #RENAME AX)",
    "INT202": "#CALL AX to a position another axis holds",
    "INT203": "parked axis (#PARK) referenced",
    "INT204": "invalid #SET AX, #CALL AX, #FREE AX or #LINK axis list (an axis the machine does not have)",
    "INT205": "axis that may not change channel (AXISEXCH 0)",
    "INT206": "axis configuration or coupling changed where fagorcnc cannot compute it (G41/G42, a transformation)",
    "INT207": "invalid #RENAME AX",
    "INT208": "invalid #PARK or #UNPARK (the element is in use)",
    "INT209": "#LINK against the manual's restrictions",
    "INT210": "coupled slave axis (#LINK) programmed",
    "INT211": "coupled slave axis on an arc of its master's plane (not computed)",
    "INT213": "parked spindle (#PARK) programmed",
    # G112 parameter sets (seed 002 L9307-L9360; axes.X.sets in the machine file)
    "INT214": "invalid G112: a parameter set the axis does not have, or no axis named",
    "INT215": "G112 parameter set of a spindle: kept, but fagorcnc does not time spindle positioning",
    # curves #POLY, #SPLINE/#ASPLINE and independent moves #MOVE (interp/curves.py, interp/independent.py)
    "INT220": "invalid #POLY statement (axes and coefficients, SP, EP)",
    "INT221": "#POLY that cannot run here (G00 active, a transformation, not starting where the tool is)",
    "INT222": "curve that needs more chords than the sampling allows",
    "INT223": "invalid #SPLINE or #ASPLINE statement",
    "INT224": "#SPLINE OFF with too few points (3, or 2 with both tangents defined)",
    "INT225": "spline with radius compensation and the linear transition G137",
    "INT226": "move a spline cannot take (#POLY/#MOVE in it, a transformation, G93)",
    "INT227": "invalid #MOVE statement",
    "INT228": "#MOVE without F and no POSFEED for the axis in the machine file",
    "INT229": "#MOVE on an axis that cannot move independently",
    "INT230": "#MOVE reached while its axis still runs a positioning: started from rest after it",
    "INT231": "#MOVE INF runs to the travel limit",
    # #MOVE alongside the general motion (plan/independent.py): INT232-INT239
    "INT232": "general move of an axis a #MOVE positioned, before #SYNC POS",
    "INT233": "the program end waits for an independent axis (#MOVE) to stop",
    "INT234": "#SYNC POS waits for the independent axes to stop",
    "INT235": "execution read of an axis a #MOVE may still be positioning (fagorcnc gives the end of it)",
    # threading G33 and rigid tapping G63 (issue 26 item 1): INT180-INT189
    "INT180": "G33 thread pitch missing or invalid",
    "INT181": "G33 thread does not advance along the axis of its pitch",
    "INT182": "threading or tapping without the spindle turning at a known speed",
    "INT183": "thread or tap feed above what the axes can run: the pitch cannot be kept",
    "INT184": "G33 entry angle Q1 invalid",
    "INT185": "invalid G63 rigid tapping block",
    "INT186": "threading or tapping combined with a function fagorcnc does not compute with it",
    "INT187": "joined threads meet at a corner: the pitch is not kept while the axes stop there",
    "INT188": "passes of one thread begin at different spindle speeds",
    "INT189": "spindle override limited in a thread (THREADOVR, feed forward not above 90 %)",
    # macros, #DEF (seed 002 ch. 21.1.16)
    "MAC001": "macro used before it is defined",
    "MAC002": "more than 50 macros",
    "MAC003": "invalid macro name (1-30 letters and digits)",
    "MAC004": "macro text longer than 140 characters",
    "MAC005": "arithmetic operation not complete inside one macro",
    "MAC006": "the block with its macros expanded is not a valid block",
    "MAC007": "macros nested too deep (a macro that names itself)",
    "MAC008": "invalid #DEF or #INIT MACROTAB statement",
    # canned cycles G80-G88, G160-G165, G210 (fagorcnc/interp/cycles; spec 09 §1.5)
    "CYC001": "canned cycle without its depth (I; G83: I and J)",
    "CYC002": "canned cycle of zero depth (the bottom is on the reference plane)",
    "CYC003": "canned cycle with radius compensation G41/G42 active",
    "CYC004": "canned cycle parameter missing or out of its range",
    "CYC005": "pocket or bore smaller than the tool",
    "CYC006": "letter needed both as an axis and as a cycle parameter",
    "CYC007": "multiple machining G160-G165 with no canned cycle or modal subroutine active",
    "CYC008": "multiple machining G160-G165 definition inconsistent",
    "CYC009": "canned cycle with provisional semantics (G210)",
    "CYC010": "influence-zone block that moves the longitudinal axis: run as a plain move, without the cycle",
    "CYC011": "hole cycle with the spindle stopped",
    "CYC012": "canned cycle point positioned by an arc",
    # thread milling G211/G212 and the tapping marks (issue 22, second part; range CYC020-CYC039)
    "CYC020": "thread milling canned cycle with provisional semantics (G211/G212)",
    # the variable catalogue (issue 26 item 10; seed 002 ch. 22, fagorcnc/interp/mpvars.py, vcatalogue.py)
    "INT240": "variable defined by the manual that fagorcnc does not implement",
    "INT241": "variable read by the PLC or the interface only, not by a part program",
    "INT242": "parameter set of an axis that does not exist (NPARSETS)",
    "INT243": "variable not valid for this kind of axis or spindle (linear, rotary, spindle)",
    "INT244": "variable without its index or its axis/spindle selector",
    "INT245": "machine parameter the machine file does not give ([machine_parameters])",
    # the spindle configuration of the channel (issue 26, spindles): INT246-INT252
    "INT246": "spindle that is not in the channel's spindle configuration (#FREE SP, #SET SP, #RENAME SP)",
    "INT247": "invalid #SET SP, #CALL SP or #FREE SP spindle list",
    "INT248": "spindle that may not change channel (AXISEXCH 0) or cannot leave it now (it turns, C axis, G33...)",
    "INT249": "invalid #RENAME SP",
    # the rest of the variable catalogue (issue 26 item 10): INT253-INT259
    "INT253": "active tool offset with per-axis offsets (TOFL/TOFLW) fagorcnc does not apply",
    "INT254": "radius compensation with a turning tool (tip radius and shape factor LOCODE not computed)",
    "INT255": "tool variable not valid for this kind of tool (TOR.. of a turning tool, LOCODE of a milling tool)",
    "INT256": "V.G.DYNOVR written outside MINDYNOVR..MAXDYNOVR",
    "INT257": "V.G.DYNOVR written on a machine file that gives no MINDYNOVR/MAXDYNOVR",
    "INT258": "write this machine cannot take (V.TM.NUMOFDT: offsets to invent; FINEORGT without FINEORG)",
    # hardening (issue 30): what the machine or the host cannot give, refused with a diagnostic
    "INT150": "the active plane needs an axis this machine does not have",
    "INT151": "global subroutine file cannot be read (name too long, link loop, not a regular file, permission)",
    "PLN001": "motion cannot be planned within the machine limits",
    # fagorcnc check: verification of the planned motion
    "PLN100": "planned path (arc or corner blend) beyond a software limit",
    "PLN101": "planned cycle time over the limit (--max-cycle-time)",
    "CFG001": "invalid machine configuration",
    "CFG003": "auxiliary function the back-end has no output for",
    "CFG002": "parameter file (parameter_file) cannot be read",
    "CFG004": "a planned move the back-end cannot send (checked before a real run)",
    # CAM posts' constructs and the machinist's lint (severity from the machine's [compat] policy,
    # fagorcnc/config/compat.py; README "CAM posts")
    "CAM001": "G51 A.. E.. (the 8055's look-ahead, not an 8060/8065 G function): no effect",
    "CAM002": "G61 alone in its block: no effect",
    "CAM003": "G500/G501 run as fagorcnc's built-in smoothing off/on",
    "CAM004": "program name with characters the manual does not allow (_ . blanks, over 14)",
    "CAM006": "T.. L<name>: global subroutine call glued to the T word, no file: run as the M function",
    "CAM007": "keyword in a # sentence's brackets not in the manual's spelling (capitals)",
    "CAM010": "G number with a leading zero before two digits (G011 reads as G11)",
    "CAM013": "G58 after another work offset (G58 is absolute origin 5: it replaces it)",
    "CAM014": "move at feed with the spindle stopped",
    "CAM020": "G500-G599 subroutine with no file and no mapping in the machine file",
    "CAM021": "invalid argument of a built-in G500-G599 behaviour",
    # kinematics and coordinate transformations (fagorcnc/kinematics, seed 002 ch. 14-17): KIN001-KIN099
    "KIN001": "#KIN ID: kinematics number not set up (1..6)",
    "KIN002": "kinematics changed while #RTCP or #TLC is active",
    "KIN003": "statement needs a kinematics (#KIN ID) of the right kind",
    "KIN004": "#RTCP and #TLC cannot be active together",
    "KIN005": "malformed coordinate-transformation statement",
    "KIN006": "#CS/#ACS system number outside 1..5",
    "KIN007": "#CS/#ACS definition: MODE outside 1..6 or wrong number of values",
    "KIN008": "#CS/#ACS ON of a system that is not defined",
    "KIN009": "a second unnamed #CS/#ACS while one is active",
    "KIN010": "KEEP, 0/1, FIRST/SECOND or SOL2 where the mode or statement does not take it",
    "KIN011": "more than 10 #ACS and #CS active",
    "KIN012": "#CS/#ACS OFF with none active: nothing changes",
    "KIN013": "no position of the rotary axes gives the tool orientation asked for",
    "KIN020": "move too close to a singular pose to keep the tool tip on the path",
    "KIN021": "joint position beyond a software limit inside a transformed move",
    "KIN022": "arc in an inclined plane run as joint-space lines",
    "KIN023": "machine variable of a kinematics fagorcnc does not hold (TDATA)",
    "KIN024": "kinematics statement on a machine without rotary axes: the identity kinematics",
    "KIN025": "move that does not continue the transformed moves before it",
    "KIN030": "#CYL without the cylinder radius",
    # (KIN031 no longer emitted since kin2: #CYL radius 0 is computed, KIN070-KIN072)
    "KIN031": "#CYL with radius 0 (the tool's distance to the centre) not computed",
    "KIN032": "#FACE/#CYL axes: not in the channel, or not one rotary axis and linear ones",
    "KIN033": "#FACE/#CYL kinematics number not of a C-axis type",
    "KIN034": "#FACE/#CYL with another C axis or a coordinate transformation active",
    "KIN035": "#FACE/#CYL with a work offset on the C axis active",
    "KIN040": "#ANGAX: transformation number missing or not set up",
    "KIN041": "suspended #ANGAX with scaling, rotation or mirror active",
    # (KIN042 since kin2: emitted for #ANGAX and axes outside the RTCP only; the rest is computed)
    "KIN042": "G74 homing with #ANGAX, #RTCP (axes outside it) or another transformation active",
    "KIN050": "tangential axis not a modulo rotary axis, or an axis of the plane",
    "KIN051": "tangential control: angle outside ±359.9999, no axis nor F, G145 K not 0 or 1",
    "KIN052": "tangential control with compensation, corner aids or a transformation not computed",
    "KIN053": "axis under tangential control programmed",
    "KIN060": "#CAX: spindle without a C axis in the machine file, or another axis name",
    "KIN061": "C axis of a spindle programmed without #CAX",
    "KIN062": "speed programmed for a spindle working as C axis",
    # kinematics, second round (kin2: #CYL radius 0, G74 under a transformation): KIN070-KIN099
    "KIN070": "#CYL with a negative radius",
    "KIN071": "#CYL radius 0 without a C-axis kinematics (type 43) of that axis to give the rotation line",
    "KIN072": "#CYL radius 0 with the tool tip on the rotation line",
    "KIN073": "G74 of the C axis of #FACE (followed over whole turns) not computed",
    # the user's tools (fagorcnc diff, expand, check's CI configuration): CLI001-CLI049
    "CLI001": "fagorcnc diff: the two paths cannot be compared (a rotary axis moves, no motion)",
    "CLI002": "fagorcnc expand --golden: the expansion differs from the golden file",
    "CLI010": "suppression comment naming a code fagorcnc does not have",
    "CLI011": "invalid [tool.fagorcnc] configuration or --select/--ignore code",
    "CLI012": "an error cannot be suppressed or ignored: the control stops there",
    # InterpCNC streaming (issues 25, 29, 30): CFG030-CFG049, BCK001-BCK049
    "CFG030": "a transformation the back-end cannot reproduce is active (#KIN, #RTCP, #CS ...): nothing is sent",
    "BCK001": "the card consumed nothing for stall_timeout seconds although it holds commands",
    "BCK002": "the card's axes-moving bits stayed set stop_timeout seconds after its buffers emptied",
}


@dataclass(frozen=True, slots=True)
class Diagnostic:
    """One reported problem.

    Attributes:
        file: source file name as given by the caller (``"<string>"`` for text).
        line: 1-based line number.
        col: 1-based column number.
        code: stable code, a key of :data:`CODES` (or of a later stage's table).
        severity: ``"error"``, ``"warning"`` or ``"info"``.
        message: explanation for a machinist.
        source: the source line, for :meth:`render` (may be empty).
    """

    file: str
    line: int
    col: int
    code: str
    severity: str
    message: str
    source: str = ""

    def __str__(self) -> str:
        sev = "" if self.severity == "error" else f"{self.severity}: "
        return f"{self.file}:{self.line}:{self.col}: {self.code} {sev}{self.message}"

    def render(self) -> str:
        """``file:line:col: CODE message`` followed by the source line and a caret."""
        head = str(self)
        if not self.source:
            return head
        src = self.source.rstrip("\r\n").expandtabs(1)
        caret = " " * max(0, min(self.col - 1, len(src))) + "^"
        return f"{head}\n    {src}\n    {caret}"

    @property
    def is_error(self) -> bool:
        return self.severity == "error"


def error(file: str, line: int, col: int, code: str, message: str, source: str = "") -> Diagnostic:
    """Shorthand for an error diagnostic."""
    return Diagnostic(file, line, col, code, "error", message, source)


def warning(file: str, line: int, col: int, code: str, message: str, source: str = "") -> Diagnostic:
    """Shorthand for a warning diagnostic."""
    return Diagnostic(file, line, col, code, "warning", message, source)
