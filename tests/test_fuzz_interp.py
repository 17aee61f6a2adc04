"""Fuzzing the interpreter: :func:`fagorcnc.simulate` and :func:`fagorcnc.interpret` never raise.

Every problem of a program must come back as diagnostics.  Inputs: programs
assembled from a pool of realistic valid and semi-valid blocks (motion,
planes, origins, scaling, rotation, feed modes, tools, parameters and
variables with hostile expressions, ``$`` structures, labels and jumps,
``#`` sentences, local subroutines and calls), and the shipped demo programs
``programs/*.nc`` with random line and character edits.  For every input,
:func:`check` runs both entry points and verifies:

* no Python exception escapes;
* each diagnostic is a :class:`~fagorcnc.Diagnostic` with a code of
  :data:`~fagorcnc.CODES`, a known severity, ``line >= 1`` and ``col >= 1``;
* ``ok`` is "no diagnostic has severity error";
* the run stops at the first error: a program with syntax errors yields no
  record; in the streaming run no record follows the moment an error
  diagnostic exists; and for straight-line programs (no subroutine, loop,
  jump or #RPT, so records come in line order) no record comes from a line
  after the first interpreter error;
* :func:`fagorcnc.dry_run` (the streamed check) gives simulate()'s diagnostics,
  verdict, ending, move count and cycle time, and PLN100 where the planned path
  leaves the soft limits between end points (which simulate() does not plan).

Budgets come from the Hypothesis profile (``tests/conftest.py``);
``FAGORCNC_HYPOTHESIS_PROFILE=fuzz`` runs 20000 examples per property.  The
machine has small runaway limits so generated endless loops end fast.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest
from helpers import edit_text
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import fagorcnc
from fagorcnc import CODES, Diagnostic
from fagorcnc.path.compensation import LOOKAHEAD as COMPENSATION_LOOKAHEAD

PROGRAMS = Path(__file__).resolve().parents[1] / "programs"
PROGRAM_TEXTS = [p.read_text(encoding="utf-8") for p in sorted(PROGRAMS.glob("*.nc"))]
MACHINE = {"limits": {"max_loop_iterations": 200, "max_blocks": 5000}}
SEVERITIES = {"error", "warning", "info"}
MOVES = {"rapid", "linear", "arc"}

# Anything that can send execution backwards or into another routine: records
# then do not come in line order (and subroutine records carry their own lines).
NOT_STRAIGHT = re.compile(r"^\s*%|\$|#RPT|#[PM]?CALL|\bLL?\b|G1[89]\d|M17|M29|#RET", re.IGNORECASE | re.MULTILINE)


def _check_diagnostics(diagnostics: list) -> None:
    for d in diagnostics:
        assert isinstance(d, Diagnostic), d
        assert d.code in CODES, d
        assert d.severity in SEVERITIES, d
        assert isinstance(d.line, int) and d.line >= 1, d
        assert isinstance(d.col, int) and d.col >= 1, d
        assert isinstance(d.message, str) and d.message, d
        str(d)
        d.render()


def _first_interp_error(diagnostics: list) -> Diagnostic | None:
    errors = [d for d in diagnostics if d.is_error and d.code.startswith("INT")]
    return errors[0] if errors else None


def _plunge(record) -> bool:
    """A move under radius compensation that leaves the position in the plane unchanged."""
    comp = getattr(record, "comp", None)
    if not comp:
        return False
    a, o = comp[-1]
    return record.start.get(a) == record.end.get(a) and record.start.get(o) == record.end.get(o)


def check(text: str) -> None:
    """Run ``text`` through :func:`simulate` and :func:`interpret` and verify the invariants."""
    assert "\n" in text  # never taken for a file name
    # ---- simulate
    result = fagorcnc.simulate(text, machine=MACHINE)
    _check_diagnostics(result.diagnostics)
    assert result.ok == (not any(d.severity == "error" for d in result.diagnostics))
    assert isinstance(result.cycle_time, float)
    if result.program is not None and not result.program.ok:
        assert result.moves == [], "a program with syntax errors must not run"
    if not result.ok and not NOT_STRAIGHT.search(text):
        first = _first_interp_error(result.diagnostics)
        if first is not None:
            late = [m for m in result.moves if m.line > first.line]
            assert not late, f"records after the error on line {first.line}: {late[:3]}"
    for m in result.moves:
        assert m.line >= 1
    # ---- streaming
    run = fagorcnc.interpret(text, machine=MACHINE)
    records = []
    error_seen_at = None
    late_moves = 0
    for record in run:
        records.append(record)
        if error_seen_at is not None and record.kind in MOVES:
            # the corner-aid stage holds one move back and radius compensation its look-ahead (the
            # moves it may drop as too short for the tool, and the plunges and retracts after them,
            # until the next move in the plane): moves of blocks before the error may still come out
            # after it, never a move of a later block
            late_moves += not _plunge(record)
            assert late_moves <= 1 + COMPENSATION_LOOKAHEAD, \
                f"move {record} yielded after the error {error_seen_at} was reported"
            assert record.line < int(error_seen_at.split(":")[1]) or NOT_STRAIGHT.search(text), record
        if error_seen_at is None:
            errors = [d for d in run.diagnostics if d.is_error]
            if errors:
                error_seen_at = str(errors[0])
    diagnostics = run.diagnostics
    _check_diagnostics(diagnostics)
    assert run.ok == (not any(d.severity == "error" for d in diagnostics))
    if not run.ok and not NOT_STRAIGHT.search(text):
        first = _first_interp_error(diagnostics)
        if first is not None:
            late = [m for m in records if m.line > first.line]
            assert not late, f"records after the error on line {first.line}: {late[:3]}"
    # ---- the streamed dry run (fagorcnc check, a real machine's check first) says what simulate() says
    dry = fagorcnc.dry_run(text, machine=MACHINE)
    envelope = [d for d in dry.diagnostics if d.code == "PLN100"]
    assert [str(d) for d in dry.diagnostics if d.code != "PLN100"] == [str(d) for d in result.diagnostics]
    assert (dry.ok, dry.executed, dry.ended_by) == (result.ok and not envelope, result.program.ok, result.ended_by)
    assert dry.moves == sum(m.kind not in ("aux", "dwell") for m in result.moves)
    assert dry.cycle_time == result.cycle_time or math.isclose(dry.cycle_time, result.cycle_time, rel_tol=1e-12)


# ---------------------------------------------------------------- numbers and expressions
SPECIAL_NUMBERS = [0, 0.0, -0.0, 1, -1, 2, 10, -10, 0.5, -0.5, 90, 180, 360, 1000, 1000.0001, -1000.0001,
                   1e30, -1e30, 1e-12, -1e-12, 4294967295, 4294967296, 99999999, 1e15]
# 309 digits and more read as infinity; 330 zeros after the point as 0
RAW_NUMBERS = ["1" + "0" * 309, "-" + "9" * 309, "0." + "0" * 330 + "1", "12.", ".5", "007", "-.0", "0.", "4294967296"]


def fmt(v: float | int) -> str:
    """A number as Fagor source text (no exponent notation)."""
    if isinstance(v, int):
        return str(v)
    s = repr(v)
    if "e" in s:
        s = f"{v:.20f}".rstrip("0")
    return s


numbers = st.one_of(
    st.sampled_from(SPECIAL_NUMBERS).map(fmt),
    st.integers(-2000, 2000).map(fmt),
    st.floats(-2000, 2000, allow_nan=False, allow_infinity=False).map(fmt),
    st.sampled_from(SPECIAL_NUMBERS).map(fmt),
    st.integers(-2000, 2000).map(fmt),
    st.sampled_from(RAW_NUMBERS),
)
small_ints = st.integers(-5, 120).map(str)
PARAMS = ["P0", "P1", "P2", "P3", "P5", "P10", "P25", "P26", "P99", "P100", "P101", "P299", "P300", "P10000"]
V_READ = ["V.A.PPOS.X", "V.A.POS.Z", "V.A.ORG.X", "V.A.ORGT[1].X", "V.G.FIX", "V.TM.TOR", "V.G.GS[1]",
          "V.G.HGS1", "V.SP.SPEED", "V.A.SPEED.S", "V.P.X", "V.S.Y", "V.G.PLANE",
          # unknown / odd ones
          "V.A.POS.W", "V.G.NOSUCH", "V.Q.WHAT", "V.A.ORGT[0].X", "V.A.ORGT[1000].Y", "V.G.GS[-1]",
          "V.G.FIXT[1].X", "V.[2].G.FIX", "V.P.UNSET", "V.S.UNSET", "V.G.HGS9", "V.TM.TOL[2]"]
V_WRITE = ["V.P.X", "V.S.Y", "V.G.FIX", "V.TM.TOR", "V.A.ORGT[1].X", "V.A.ORGT[99].Z", "V.A.PPOS.X",
           "V.G.NOSUCH", "V.A.POS.W", "V.P.COUNT", "V.G.FIXT[1].X"]
FUNCS1 = ["SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "ABS", "SQR", "SQRT", "LOG", "LN", "EXP", "DEXP", "INT",
          "FRACT", "ROUND", "FUP", "INV", "-"]
BINOPS = ["+", "-", "*", "/", "**", "MOD", "==", "!=", "<", "<=", ">", ">=", "&", "|", "^"]

leaves = st.one_of(numbers, st.sampled_from(PARAMS), st.sampled_from(V_READ),
                   st.sampled_from(["TRUE", "FALSE", "EXIST[P1]", "EXIST[V.P.X]", "EXIST[P[P2]]"]))


def _extend(children):
    return st.one_of(
        st.tuples(children, st.sampled_from(BINOPS), children).map(lambda t: f"[{t[0]} {t[1]} {t[2]}]"),
        st.tuples(st.sampled_from(FUNCS1), children).map(lambda t: f"{t[0]}[{t[1]}]"),
        st.tuples(children, children).map(lambda t: f"ARG[{t[0]}, {t[1]}]"),
        children.map(lambda e: f"P[{e}]"),
    )


expressions = st.recursive(leaves, _extend, max_leaves=6)
# a word value: a number, a parameter or a bracketed expression
values = st.one_of(numbers, numbers, st.sampled_from(["P1", "P2", "P100"]),
                   expressions.map(lambda e: e if e.startswith("[") else f"[{e}]"))


def words(letters: str, min_size: int = 0, max_size: int | None = None):
    """Words of some of ``letters`` (in random order, each at most once) with random values."""
    return st.lists(st.tuples(st.sampled_from(list(letters)), values), min_size=min_size, max_size=max_size,
                    unique_by=lambda t: t[0]).map(lambda ws: " ".join(f"{a}{v}" for a, v in ws))


def join(*parts) -> st.SearchStrategy[str]:
    """A block made of the given parts (strings or strategies), space separated, empty parts dropped."""
    strategies = [p if isinstance(p, st.SearchStrategy) else st.just(p) for p in parts]
    return st.tuples(*strategies).map(lambda ps: " ".join(p for p in ps if p))


def maybe(s) -> st.SearchStrategy[str]:
    return st.one_of(st.just(""), s if isinstance(s, st.SearchStrategy) else st.just(s))


# ---------------------------------------------------------------- blocks
motion_g = st.sampled_from(["G0", "G1", "G2", "G3", "G8", "G9", "G00", "G01", "G02", "G03", ""])
motion = join(motion_g, words("XYZIJKRQF", 0, 5), maybe(st.integers(-2, 49).map(lambda n: f"NR{n}")))
modal = st.lists(st.sampled_from(["G90", "G91", "G70", "G71", "G17", "G18", "G19", "G94", "G40", "G05",
                                  "G07", "G60", "G61"]), min_size=1, max_size=3).map(" ".join)
origins = st.one_of(
    st.sampled_from(["G53", "G54", "G55", "G56", "G57", "G58", "G59", "G159", "G159=", "G92", "G158"]),
    small_ints.map(lambda n: f"G159={n}"),
    small_ints.map(lambda n: f"G159 ={n}"),
    join("G92", words("XYZ", 1)),
    join("G158", words("XYZ", 0)),
)
planes = st.one_of(
    join("G20", words("XYZ", 0, 3)),
    join("G20 X1 Y2 Z3"),
    join("G30", words("IJ", 0, 2)),
)
special_g = st.one_of(
    st.integers(-1, 2).map(lambda n: f"G157 X{n}"),
    join("G157", words("XYZ", 0, 2)),
    join("G174", words("XYZ", 0, 2)),
    join(st.sampled_from(["G198", "G199"]), words("XYZ", 0, 2)),
    join(st.sampled_from(["G10", "G11", "G12", "G13", "G14"]), words("XYZ", 0, 2)),
    join("G72", maybe(join("S", values).map(lambda s: s.replace(" ", "")))),
    values.map(lambda v: f"#SCALE [{v}]"),
    join("G73", words("QIJ", 0, 3)),
    join("G74", words("XYZ", 0, 3)),
    join(st.sampled_from(["G04", "G4"]), words("K", 0, 1)),
    join(st.sampled_from(["G93", "G94", "G95"]), words("FS", 0, 2), st.sampled_from(["", "M3", "M4", "M5"]),
         maybe(motion)),
    join(st.sampled_from(["G96", "G97", "G192"]), words("S", 0, 1), st.sampled_from(["", "M3", "M5"])),
    join(st.sampled_from(["M3", "M4", "M5", "M19", "M8", "M9", "M1", "M0"]), words("S", 0, 1)),
    st.sampled_from(["G41", "G42", "G43", "G44", "G36 R5", "G37 R5", "G38 R5", "G39 R5", "G51 E0.01",
                     "G63", "G33 Z-10 K1", "G31 X1", "G999", "G-1", "G160 X1", "G180", "G180 P0=1",
                     "G180 A2", "G181 X1", "G500", "M1 M2 M3 M4 M5 M6 M7 M8", "X1 X2", "?1=1", "?9=1"]),
)
tools = join(st.integers(-2, 120).map(lambda n: f"T{n}"), maybe(st.integers(-1, 20).map(lambda n: f"D{n}")),
             st.sampled_from(["M6", "M06", ""]))
assign_ops = st.sampled_from(["=", "=", "=", "+=", "-=", "*=", "/="])
assignments = st.one_of(
    join(st.sampled_from(PARAMS), assign_ops, expressions).map(lambda s: s.replace(" ", "")),
    st.tuples(expressions, assign_ops, expressions).map(lambda t: f"P[{t[0]}] {t[1]} {t[2]}"),
    st.tuples(st.sampled_from(V_WRITE), assign_ops, expressions).map(lambda t: f"{t[0]} {t[1]} {t[2]}"),
    st.lists(st.tuples(st.sampled_from(PARAMS), expressions), min_size=2, max_size=3).map(
        lambda ps: " ".join(f"{p}={e}" for p, e in ps)),
)


@st.composite
def messages(draw) -> str:
    kw = draw(st.sampled_from(["#MSG", "#ERROR", "#WARNING", "#WARNINGSTOP"]))
    if draw(st.integers(0, 5)) == 0:
        return f"{kw} [{draw(values)}]" if draw(st.booleans()) else kw
    text = " ".join(draw(st.lists(st.sampled_from(["%D", "part", "%D%D", "F=", "%", "%d", "100%"]), max_size=4)))
    data = draw(st.lists(expressions, max_size=3))
    return f'{kw} ["{text}"' + "".join(f", {e}" for e in data) + "]"


sentences = st.one_of(
    messages(),
    join("#MCS", words("XYZ", 0, 3)),
    st.sampled_from(["#MCS ON", "#MCS OFF", "G0 #MCS Z0", "#MCS G0 Z10"]),
    values.map(lambda v: f"#TIME {v}"),
    st.sampled_from(["#HSC ON", "#HSC OFF", "#HSC ON [CONTERROR 0.01]", "#HSC ON [CONTERROR 0]", "#RTCP ON",
                     "#RTCP OFF", "#TOOL AX [Z+]", "#TOOL AX [X-]", "#TOOL AX [Y+]", "#KIN ID[1]", "#KIN ID[0]",
                     "#CS OFF", "#SLOPE [0,0]", "#DELETE V.P.X", "#DELETE V.S.Y", "#DELETE V.G.FIX",
                     "#CD ON", "#PATH \"/tmp\""]),
    st.integers(-2, 99).map(lambda n: f"#KIN ID[{n}]"),
)
LABEL_DEFS = ["[L1]", "[L2]", "N10:", "N10: G0 X1", "N20: G1 X2 F100", "N30:", "N10 G0 X3", "N20 P1=P1+1"]
jumps = st.one_of(
    st.sampled_from(["$GOTO [L1]", "$GOTO [L2]", "$GOTO [NOWHERE]", "$GOTO N10", "$GOTO N20", "$GOTO N99",
                     "$GOTO N[P1]", "#RPT [N10, N20, 2]", "#RPT [N10, N30]", "#RPT [N20, N10, 1]",
                     "#RPT [N10, N20, 0]", "#RPT [N10, N99, 2]"]),
    st.tuples(expressions, st.sampled_from(["[L1]", "[L2]", "[NOWHERE]", "N10", "N20"])).map(
        lambda t: f"$IF {t[0]} $GOTO {t[1]}"),
    st.integers(-2, 49).map(lambda n: f"#RPT [N10, N20, {n}]"),
)
SUBS = ["SUB1", "SUB2", "SUB3", "MISSING"]
calls = st.one_of(
    st.sampled_from(SUBS).map(lambda s: f"LL {s}"),
    join(st.sampled_from(["#CALL", "#PCALL", "#MCALL"]), st.sampled_from([*SUBS, "GLOBAL.NC", "DIR/X.NC"]),
         words("ABCXP", 0, 3)),
    st.sampled_from(["#MDOFF", "M17", "M29", "#RET", "L GLOBAL.NC", "LL", "M30", "M02"]),
)
simple_blocks = st.one_of(
    motion, motion, motion, modal, origins, planes, special_g, special_g, tools, assignments, assignments,
    sentences, st.sampled_from(LABEL_DEFS), jumps, calls,
    st.sampled_from(["", "; comment", "(comment) G0 X1", "/G1 X5 F100", "$BREAK", "$CONTINUE", "$ENDIF",
                     "$ELSE"]),
)


# ---------------------------------------------------------------- structures
COUNTERS = ["P20", "P21", "P22", "P23", "P110", "V.P.I"]


@st.composite
def body(draw, depth: int = 0, max_items: int = 8) -> list[str]:
    lines: list[str] = []
    for _ in range(draw(st.integers(0, max_items))):
        if depth < 2 and draw(st.integers(0, 4)) == 0:
            lines += draw(structure(depth + 1))
        else:
            lines.append(draw(simple_blocks))
    return lines


def _cond(draw) -> str:
    return draw(st.one_of(expressions, st.sampled_from(["P1==1", "P2 > 0", "V.G.PLANE == 17", "1", "0"])))


@st.composite
def structure(draw, depth: int) -> list[str]:
    kind = draw(st.sampled_from(["if", "while", "for", "do", "switch"]))
    inner = body(depth, max_items=4)
    counter = draw(st.sampled_from(COUNTERS))
    n = draw(st.integers(-1, 49))
    if kind == "if":
        lines = [f"$IF {_cond(draw)}", *draw(inner)]
        for _ in range(draw(st.integers(0, 2))):
            lines += [f"$ELSEIF {_cond(draw)}", *draw(inner)]
        if draw(st.booleans()):
            lines += ["$ELSE", *draw(inner)]
        closer = ["$ENDIF"]
    elif kind == "while":
        step = draw(st.sampled_from([f"{counter}={counter}+1", f"{counter} += 1", ""]))  # "" runs away
        lines = [f"{counter}=0", f"$WHILE {counter} < {n}", *draw(inner), step]
        closer = ["$ENDWHILE"]
    elif kind == "for":
        a, b = draw(numbers), draw(st.sampled_from([str(n), *SPECIAL_NUMBERS[:6]]))
        s = draw(st.sampled_from(["1", "-1", "2", "0.5", "0", "P1", "1000"]))
        lines = [f"$FOR {counter} = {a}, {b}, {s}", *draw(inner)]
        closer = ["$ENDFOR"]
    elif kind == "do":
        lines = [f"{counter}=0", "$DO", *draw(inner), f"{counter}={counter}+1"]
        closer = [f"$ENDDO {counter} < {n}"]
    else:
        lines = [f"$SWITCH {draw(expressions)}"]
        for case in draw(st.lists(st.integers(-1, 3), max_size=3)):
            lines += [f"$CASE {case}", *draw(inner)]
            if draw(st.booleans()):
                lines.append("$BREAK")
        if draw(st.booleans()):
            lines += ["$DEFAULT", *draw(inner)]
        closer = ["$ENDSWITCH"]
    if draw(st.integers(0, 15)) == 0:
        closer = []  # structure not closed
    return lines + closer


END_LINES = st.sampled_from(["M30", "M30", "M02", "M2", "", "M17", "#RET"])


@st.composite
def programs(draw) -> str:
    lines: list[str] = []
    subs = draw(st.lists(st.sampled_from([*SUBS[:3], "SUB1"]), max_size=3))
    for name in subs:
        lines.append(f"%L {name}")
        lines += draw(body(1, max_items=5))
        lines.append(draw(st.sampled_from(["M17", "M29", "#RET", "", "M17"])))
    if subs or draw(st.booleans()):
        header = draw(st.sampled_from(["%MAIN", "%MAIN", "", "%L"]))
        if header:
            lines.append(header)
    lines += draw(body(0, max_items=14))
    lines.append(draw(END_LINES))
    return "\n".join(lines) + "\n"


@st.composite
def straight_programs(draw) -> str:
    """No subroutine, loop, jump or #RPT: records come in line order."""
    pool = st.one_of(motion, motion, modal, origins, planes, special_g, tools, assignments, sentences)
    lines = draw(st.lists(pool, max_size=20))
    lines.append(draw(st.sampled_from(["M30", "M02", ""])))
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------- mutations of the demo programs
EDIT_CHARS = st.one_of(
    st.sampled_from(list(" \t\r\n:;=()[]+-.,*/$#%\"0123456789GLMNPXYZVIJKRQFSTD")),
    st.characters(),
)


def _edit(draw, text: str) -> str:
    return edit_text(draw, text, EDIT_CHARS)


@st.composite
def mutated_programs(draw) -> str:
    lines = draw(st.sampled_from(PROGRAM_TEXTS)).splitlines()
    for _ in range(draw(st.integers(0, 4))):  # line-level edits
        i = draw(st.integers(0, len(lines) - 1))
        op = draw(st.sampled_from(["delete", "duplicate", "move", "replace", "insert"]))
        if op == "delete":
            del lines[i]
        elif op == "duplicate":
            lines.insert(i, lines[i])
        elif op == "move":
            lines.insert(draw(st.integers(0, len(lines))), lines.pop(i))
        elif op == "replace":
            lines[i] = draw(simple_blocks)
        else:
            lines.insert(i, draw(simple_blocks))
        if not lines:
            lines = [""]
    text = "\n".join(lines) + "\n"
    for _ in range(draw(st.integers(0, 6))):  # character-level edits
        text = _edit(draw, text)
    return text if "\n" in text else text + "\n"


# ---------------------------------------------------------------- properties
@given(programs())
def test_generated_programs(text: str) -> None:
    check(text)


@given(straight_programs())
def test_straight_programs_stop_at_the_error(text: str) -> None:
    check(text)


@given(st.lists(st.one_of(assignments, sentences, jumps), max_size=10).map(lambda ls: "\n".join([*ls, "M30\n"])))
def test_expressions_and_sentences(text: str) -> None:
    check(text)


@given(mutated_programs())
def test_mutated_demo_programs(text: str) -> None:
    check(text)


@pytest.mark.slow
@settings(max_examples=max(1500, settings.default.max_examples),
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(st.one_of(programs(), mutated_programs()))
def test_interpreter_fuzz_long(text: str) -> None:
    check(text)


# ---------------------------------------------------------------- deterministic cases
@pytest.mark.parametrize("text", PROGRAM_TEXTS, ids=[p.name for p in sorted(PROGRAMS.glob("*.nc"))])
def test_demo_programs_default_machine(text: str) -> None:
    result = fagorcnc.simulate(text, machine=None)
    _check_diagnostics(result.diagnostics)
    assert result.ok, [str(d) for d in result.diagnostics]
    run = fagorcnc.interpret(text, machine=None)
    assert len(list(run)) == len(result.moves)
    assert run.ok


@pytest.mark.parametrize("text", [
    "P1=1/0\nG1 X10 F100\nM30\n",
    "P1=SQRT[-1]\nM30\n",
    "P1=10**10000\nM30\n",
    "P1=P[-1]\nM30\n",
    "P1=P[0.5]\nM30\n",
    "P1=V.Q.WHAT\nM30\n",
    "P20=0\n$WHILE P20 < 5\nG0 X1\n$ENDWHILE\nM30\n",
    "$GOTO [NOWHERE]\nM30\n",
    "[L1]\n$GOTO [L1]\n",
    "%L SUB1\nLL SUB1\nM17\n%MAIN\nLL SUB1\nM30\n",
    "%MAIN\n#CALL MISSING\nM30\n",
    "G180\nM30\n",
    "#MSG [\"%D %D %D\", 1]\n#ERROR [\"%D\"]\nM30\n",
    "G159=120\nG159=-5\nM30\n",
    "G1 X1 F100 NR49\nM30\n",
    "1" + "0" * 400 + "\n",
    # crashes found by the properties and fixed since (KeyError in the streaming source,
    # OverflowError on an infinite parameter index, T/M/NR/N/G159/G74 value)
    "$IF 0\nM30\n",
    "%MAIN\n#MCS OFF\nG0 R10 J0\nG0\n$IF 0\n$ENDIF\n$IF 0\nG0\nG0\nG0\nM30\n",
    "P1=P[" + "1" + "0" * 309 + "]\nM30\n",
    "T" + "1" + "0" * 309 + "\nM30\n",
    "M" + "1" + "0" * 309 + "\nM30\n",
    "G1 X1 F100 NR" + "1" + "0" * 309 + "\nM30\n",
    "$GOTO N" + "1" + "0" * 309 + "\nM30\n",
    "G159=" + "1" + "0" * 309 + "\nM30\n",
    "G74 X" + "1" + "0" * 309 + "\nM30\n",
])
def test_regression_examples(text: str) -> None:
    check(text)


# Crashes found by these properties (the exception each raised before the fix).  A number
# of 309 digits or more reads as infinity; "P1 *= P1" could also reach it without any diagnostic.
INF = "1" + "0" * 309
NEAR_MAX = "9" * 308
CRASHES = {
    # ValueError: math domain error (math.sin/math.cos of infinity)
    "sin-inf": f"P1=SIN[{INF}]\nM30\n",
    "cos-inf": f"P1=COS[{INF}]\nM30\n",
    "sin-inf-by-multiplication": f"P1={NEAR_MAX}\nP1*=P1\nP2=SIN[P1]\nM30\n",
    # ValueError: math domain error (math.fmod in TAN)
    "tan-inf": f"P1=TAN[{INF}]\nM30\n",
    # OverflowError: cannot convert float infinity to integer
    "round-inf": f"P1=ROUND[{INF}]\nM30\n",
    "int-inf": f"P1=INT[{INF}]\nM30\n",
    "fract-inf": f"P1=FRACT[{INF}]\nM30\n",
    "fup-inf": f"P1=FUP[{INF}]\nM30\n",
    # ValueError: math domain error (rotation by an infinite angle)
    "g73-inf": f"G73 Q{INF}\nG1 X1 F100\nM30\n",
    "polar-angle-inf": f"G30 I0 J0\nG1 R10 Q{INF} F100\nM30\n",
    # IndexError: string index out of range ("P0.5" gives a word with an empty address)
    "pcall-p-decimal": "#PCALL SUB P0.5\nM30\n",
    "mcall-p-decimal": "#MCALL SUB P1.5\nM30\n",
}


@pytest.mark.parametrize("text", list(CRASHES.values()), ids=list(CRASHES))
def test_regression_crashes(text: str) -> None:
    check(text)


def test_numbers_format_without_exponent() -> None:
    for v in SPECIAL_NUMBERS:
        s = fmt(v)
        assert "e" not in s
        assert math.isclose(float(s), float(v), rel_tol=1e-9, abs_tol=1e-30)



# ---------------------------------------------------------------- deep expressions (issue 30 item 3)
# Each wrapper nests the expression one level deeper (an operator, a function, an index); "-[...]"
# of a plain number is folded into the number by the parser, so it may add no level.
DEEP_WRAPPERS = {   # wrapper -> the levels it adds (operators, functions, indexes)
    "SIN[{}]": 1, "ABS[{}]": 1, "INT[{}]": 1, "P[ABS[INT[{}]] MOD 3]": 4, "-[{}]": 1, "[{} + 1]": 1, "[2 * {}]": 1,
    "[{} == 1]": 1, "V.A.ORGT[ABS[INT[{}]] MOD 5 + 1].X": 5, "ARG[1, {}]": 1, "[{} ** 1]": 1, "EXP[{} MOD 2]": 2,
}


@st.composite
def deep_expressions(draw) -> tuple[str, int, int]:
    """(expression, levels, folded wrappers) of a random nesting of up to 300 levels."""
    expr = draw(st.sampled_from(["1", "P1", "0.5", "V.G.FIX", "TRUE"]))
    levels = folded = 0
    for wrapper in draw(st.lists(st.sampled_from(sorted(DEEP_WRAPPERS)), min_size=1, max_size=300)):
        expr = wrapper.format(expr)
        levels += DEEP_WRAPPERS[wrapper]
        folded += wrapper == "-[{}]"
    return expr, levels, folded


@settings(max_examples=max(30, settings.default.max_examples // 3),
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(deep_expressions(), st.sampled_from(["P2 = {}", "G1 X{} F100", "$IF {} == 1", "#MSG [\"%D\", {}]"]))
def test_deep_expressions(case, template) -> None:
    from fagorcnc.syntax.parser import MAX_EXPRESSION_DEPTH

    expr, levels, folded = case
    line = template.format(expr if not template.startswith("G1") else f"[{expr}]")
    text = "P1 = 1\n" + line + ("\n$ENDIF" if template.startswith("$IF") else "") + "\nM30\n"
    check(text)
    deep = [d for d in fagorcnc.parse_text(text).diagnostics if d.code == "SYN040"]
    if levels < MAX_EXPRESSION_DEPTH - 2:   # a few levels of the block itself (word, call) aside
        assert not deep, (levels, text[:200])
    if levels - folded > MAX_EXPRESSION_DEPTH:
        assert deep, (levels, text[:200])
