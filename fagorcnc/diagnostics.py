"""Diagnostics: every problem fagorcnc reports, with a stable code.

A diagnostic names the file, line and column (1-based), a stable code a CI
user can filter on, a severity and a message written for a machinist.
``str(diagnostic)`` gives ``file:line:col: CODE message``;
:meth:`Diagnostic.render` adds the source line with a caret under the column.

Codes are grouped by stage: ``SYN`` syntax of a block, ``STR`` program
structure (headers, subroutines, labels, ``$`` nesting), ``INT`` the
interpreter, ``CFG`` the machine configuration.  Later stages add their own
prefixes (``PLN`` the planner, ``BCK`` a back-end while it runs).  A code, once published, keeps its meaning.
"""

from __future__ import annotations

from dataclasses import dataclass

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
    "PLN001": "motion cannot be planned within the machine limits",
    # fagorcnc check: verification of the planned motion
    "PLN100": "planned path (arc or corner blend) beyond a software limit",
    "PLN101": "planned cycle time over the limit (--max-cycle-time)",
    "CFG001": "invalid machine configuration",
    "CFG003": "auxiliary function the back-end has no output for",
    "CFG002": "parameter file (parameter_file) cannot be read",
    "CFG004": "a planned move the back-end cannot send (checked before a real run)",
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
