"""``fagorcnc expand``: the canonical dump of what a program does, one line per executed record.

The program is interpreted and planned in one stream (:func:`fagorcnc.simulate.dry_run`) and every
record the interpreter executes (a rapid, a feed move, an arc, a dwell, an auxiliary function) is
written as soon as the planner has timed it, so memory does not grow with the program.  The output is
meant to be stored and compared (golden files of a post-processor's regression tests): every number
is written with fixed decimals (:data:`DECIMALS`), ``-0`` is written ``0``, keys and columns come in
a fixed order, and nothing depends on the clock, the machine running it or the version of fagorcnc.

Each record gives (JSON Lines keys; the CSV columns and the text format carry the same):

* ``n`` its number (1, 2, ... in execution order), ``kind`` (``rapid``, ``linear``, ``arc``,
  ``dwell``, ``aux``), ``src`` the source ``file:line`` (the file relative to the program's own
  directory when it lies there: a stored expansion does not depend on where it was made);
* ``start``/``end`` per axis, in the frame asked (``--frame part``: the tool tip in part
  coordinates, the default; ``--frame machine``: the controlled point in machine coordinates);
  arcs add ``center`` (their plane's two axes), ``dir`` (``cw``/``ccw``), ``radius`` and ``turns``;
  a dwell its ``seconds``; an auxiliary function ``fn`` and ``value`` (``M`` 3, ``T`` 1 ...); the
  part position of a dwell or an auxiliary function is in the frame of the last move (none before
  the first move);
* ``feed`` (mm/min, ``null`` at rapid) and ``feed_mode`` (``G94``/``G95``/``G93``), ``S`` the first
  spindle's speed and ``M`` its state (3, 4 or 5), ``T``/``D`` the tool in the spindle (loaded by
  the last M06) and the active offset, ``offset`` the machine-minus-part translation per axis (the
  active origin chain: G54..G59/G159, G92, fixture, plus the tool length compensation), ``modes``
  the modal functions the record was made under (its motion G00-G03, the plane of an arc, the feed
  mode, the corner mode at its end G05/G07/G50/#HSC, the radius compensation G40-G42).  All of it
  is read from the record stream itself (T, M06, D, S, M3-M5 as their records pass), never from the
  interpreter's state, which the path stage's look-ahead has already moved to the next block;
* ``t0``/``duration``: when the planned (jerk-limited) motion reaches the record and how long it
  takes (s; a record the planner does not time, such as a move of length 0, takes 0 s).

After the records come the program's diagnostics (``kind`` ``diagnostic``: ``code``, ``severity``,
``src``, ``message``) and one ``end`` line (``moves``, ``ended_by``, ``cycle_time``, ``ok``).

``--golden DIR`` compares each program's expansion with ``DIR/<program name>.<format>`` (written
there when it is missing, or with ``--update``) and prints the first record that differs, both
lines; exit 0 when everything matches, 1 otherwise.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import sys
from collections import deque
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

from ..config.machine import Machine, MachineError, load_machine
from ._shared import not_a_file

#: Decimals of every position, feed, radius and time written.
DECIMALS = 4
#: Output formats and the suffix of their golden files.
FORMATS = {"jsonl": ".jsonl", "csv": ".csv", "text": ".txt"}
FRAMES = ("part", "machine")
SCHEMA = "fagorcnc-expand/1"


def fixed(value: float | None) -> str:
    """``value`` with :data:`DECIMALS` decimals, ``-0`` as ``0``; ``null`` for None."""
    if value is None:
        return "null"
    text = f"{value:.{DECIMALS}f}"
    if text.startswith("-") and not text.strip("-0."):
        text = text[1:]
    return text


@dataclass(slots=True)
class Row:
    """One executed record and what the channel was doing when it was made."""

    n: int
    record: object
    start: dict
    end: dict
    center: dict | None
    spindle: tuple[float, int]
    tool: int
    d: int
    offset: dict
    modes: str
    t0: float | None = None
    duration: float = 0.0


_PLANES = {("X", "Y"): 17, ("Z", "X"): 18, ("Y", "Z"): 19}


def _modes(rec) -> str:
    """The modal functions a record says it was made under: its motion (G00-G03), the plane of an
    arc (G17-G19 for the main planes), the feed mode, the corner mode at its end (G05/G07/G50, HSC)
    and the radius compensation (G40-G42)."""
    kind = rec.kind
    if kind in ("aux", "dwell"):
        return ""
    if getattr(rec, "thread", None) is not None:   # a G33 thread or a G63 tap: that is its motion mode
        out = [rec.feed_mode]
    else:
        out = ["G00" if kind == "rapid" else "G01" if kind == "linear" else "G02" if rec.direction == "cw" else "G03"]
    if kind == "arc":
        plane = _PLANES.get(tuple(rec.plane[:2]))
        if plane is not None:
            out.append(f"G{plane}")
    if kind != "rapid" and rec.feed_mode and out[0] != rec.feed_mode:
        out.append(rec.feed_mode)
    dyn = rec.dyn
    corner = dyn.corner if dyn is not None else "G50"
    out.append("#HSC" if corner == "HSC" else corner)
    comp = rec.comp
    out.append("G40" if not comp else "G41" if comp[0] > 0 else "G42")   # side +1 for G41
    return " ".join(out)


class Expansion:
    """Streams a program's rows: :meth:`rows` yields each :class:`Row` once the planner has timed it.

    ``frame`` is ``"part"`` or ``"machine"``.  After the iteration, :attr:`result` is the
    :class:`~fagorcnc.simulate.DryRun` (diagnostics, cycle time, ending).
    """

    def __init__(self, source: str | Path, machine: Machine, *, frame: str = "part", block_skip: bool = False):
        if frame not in FRAMES:
            raise ValueError("frame must be 'part' or 'machine'")
        self.source, self.machine, self.frame, self.block_skip = source, machine, frame, block_skip
        self.result = None
        self._pending: deque[Row] = deque()
        self._waiting: dict[int, object] = {}   # id -> record of the rows in _pending
        self._ready: deque[Row] = deque()
        self._clock = 0.0
        self._count = 0
        self._spindle = machine.spindles[0] if machine.spindles else None
        self._offset: dict[str, float] = {}
        self._tool = self._next_tool = self._d = self._rotation = 0
        self._rotation = 5
        self._speed = 0.0

    # ------------------------------------------------------------------ watchers of the dry run
    def _on_record(self, rec, interp) -> None:
        # what the row says of the channel comes from the record stream itself, never from the
        # interpreter's state: the path stage's look-ahead has already run the next block then
        self._count += 1
        kind = rec.kind
        center = None
        if kind in ("aux", "dwell"):
            if kind == "aux":
                self._track(rec)
            if self.frame == "machine":
                start = end = rec.position
            else:   # in the frame of the last move; before the first move no part position is known
                start = end = {a: v - self._offset[a] for a, v in rec.position.items() if a in self._offset}
            offset = self._offset
        else:
            # part = machine minus a translation per axis (ChannelState.part_pos): the record's own
            offset = self._offset = {a: rec.end[a] - rec.end_part[a] for a in rec.end_part}
            if self.frame == "machine":
                start, end = rec.start, rec.end
                if kind == "arc":
                    center = {a: rec.center[a] for a in rec.plane[:2]}
            else:
                start = {a: rec.start[a] - offset.get(a, 0.0) for a in rec.start}
                end = dict(rec.end_part)
                if kind == "arc":
                    center = {a: rec.center[a] - offset.get(a, 0.0) for a in rec.plane[:2]}
        self._waiting[id(rec)] = rec   # (the record is kept alive while it waits: its id is its own)
        self._pending.append(Row(self._count, rec, start, end, center, (self._speed, self._rotation), self._tool,
                                 self._d, offset, _modes(rec)))

    def _track(self, rec) -> None:
        """T, M6, D, S and M3/M4/M5 as the auxiliary records pass (seed 002 L4700: M06 loads the
        tool the last T selected)."""
        f, value = rec.function, rec.value
        if f == "T":
            self._next_tool = int(value)
        elif f == "D":
            self._d = int(value)
        elif f == "S" and (rec.spindle is None or rec.spindle == self._spindle):
            self._speed = value
        elif f == "M" and value == 6:
            self._tool = self._next_tool
        elif f == "M" and value in (3, 4, 5):
            self._rotation = int(value)

    def _on_segment(self, seg) -> None:
        pending = self._pending
        rec = seg.record
        if id(rec) in self._waiting:   # the rows before its record are complete: written
            while pending[0].record is not rec:
                self._flush_one()
        if pending and pending[0].record is rec:
            row = pending[0]
            if row.t0 is None:
                row.t0 = seg.t0
            row.duration = seg.t0 + seg.duration - row.t0
        self._clock = max(self._clock, seg.t0 + seg.duration)

    def _flush_one(self) -> None:
        row = self._pending.popleft()
        self._waiting.pop(id(row.record), None)
        if row.t0 is None:
            row.t0 = self._clock
        self._ready.append(row)

    # ------------------------------------------------------------------ the stream
    def run(self, emit: Callable[[Row], None]):
        """Run the program; ``emit`` receives every :class:`Row` in execution order as soon as it is
        timed.  Returns the :class:`~fagorcnc.simulate.DryRun`."""
        from ..simulate import dry_run

        def on_record(rec, interp) -> None:
            self._on_record(rec, interp)
            self._drain(emit)

        def on_segment(seg) -> None:
            self._on_segment(seg)
            self._drain(emit)

        result = dry_run(self.source, self.machine, block_skip=self.block_skip, on_record=on_record,
                         on_segment=on_segment)
        while self._pending:
            self._flush_one()
        self._drain(emit)
        return result

    def _drain(self, emit: Callable[[Row], None]) -> None:
        ready = self._ready
        while ready:
            emit(ready.popleft())


def relative_file(file: str, base: Path) -> str:
    """``file`` relative to ``base`` (the program's directory) when it lies there, else as given."""
    try:
        return Path(file).resolve().relative_to(base).as_posix()
    except (OSError, ValueError):
        return file


# ----------------------------------------------------------------------------- the formats
def _point(axes: list[str], p: dict) -> str:
    return "{" + ",".join(f'"{a}":{fixed(p[a])}' for a in axes if a in p) + "}"


def _json_text(value: str | None) -> str:
    return json.dumps(value, ensure_ascii=False)


class Writer:
    """Writes rows in one format; :meth:`lines` yields the text lines (without newline)."""

    def __init__(self, fmt: str, axes: list[str], base: Path) -> None:
        if fmt not in FORMATS:
            raise ValueError(f"format must be one of {', '.join(FORMATS)}")
        self.fmt, self.axes, self.base = fmt, axes, base
        self._files: dict[str, str] = {}

    def _src(self, rec) -> str:
        file = rec.src.file
        name = self._files.get(file)
        if name is None:
            name = self._files[file] = relative_file(file, self.base)
        return f"{name}:{rec.src.line}"

    def header(self, program: str, frame: str) -> Iterator[str]:
        if self.fmt == "jsonl":
            yield (f'{{"schema":"{SCHEMA}","program":{_json_text(program)},"frame":"{frame}",'
                   f'"axes":[{",".join(chr(34) + a + chr(34) for a in self.axes)}],"decimals":{DECIMALS}}}')
        elif self.fmt == "csv":
            yield _csv_line(self.columns())
        else:
            yield f"# {SCHEMA} {program} frame={frame} axes={','.join(self.axes)}"

    def columns(self) -> list[str]:
        axes = self.axes
        return ["n", "kind", "src", *(f"start_{a}" for a in axes), *(f"end_{a}" for a in axes), "center_1",
                "center_2", "dir", "radius", "turns", "seconds", "fn", "value", "feed", "feed_mode", "S", "M", "T",
                "D", *(f"offset_{a}" for a in axes), "modes", "t0", "duration"]

    def row(self, row: Row) -> str:
        rec = row.record
        kind = rec.kind
        if self.fmt == "jsonl":
            parts = [f'"n":{row.n}', f'"kind":"{kind}"', f'"src":{_json_text(self._src(rec))}',
                     f'"start":{_point(self.axes, row.start)}', f'"end":{_point(self.axes, row.end)}']
            if kind == "arc":
                parts += [f'"center":{_point(list(rec.plane[:2]), row.center or {})}', f'"dir":"{rec.direction}"',
                          f'"radius":{fixed(rec.radius)}', f'"turns":{rec.turns}']
            elif kind == "dwell":
                parts.append(f'"seconds":{fixed(rec.seconds)}')
            elif kind == "aux":
                parts += [f'"fn":"{rec.function}"', f'"value":{fixed(rec.value)}']
            feed = getattr(rec, "feed", None)
            parts += [f'"feed":{fixed(feed)}', f'"feed_mode":"{getattr(rec, "feed_mode", "")}"',
                      f'"S":{fixed(row.spindle[0])}', f'"M":{row.spindle[1]}', f'"T":{row.tool}', f'"D":{row.d}',
                      f'"offset":{_point(self.axes, row.offset)}', f'"modes":"{row.modes}"', f'"t0":{fixed(row.t0)}',
                      f'"duration":{fixed(row.duration)}']
            return "{" + ",".join(parts) + "}"
        if self.fmt == "csv":
            arc = kind == "arc"
            plane = list(rec.plane[:2]) if arc else []
            center = [fixed((row.center or {}).get(a)) if arc else "" for a in plane] or ["", ""]
            return _csv_line([
                str(row.n), kind, self._src(rec),
                *(fixed(row.start.get(a)) if a in row.start else "" for a in self.axes),
                *(fixed(row.end.get(a)) if a in row.end else "" for a in self.axes), *center,
                rec.direction if arc else "", fixed(rec.radius) if arc else "", str(rec.turns) if arc else "",
                fixed(rec.seconds) if kind == "dwell" else "", rec.function if kind == "aux" else "",
                fixed(rec.value) if kind == "aux" else "",
                "" if getattr(rec, "feed", None) is None else fixed(rec.feed), getattr(rec, "feed_mode", ""),
                fixed(row.spindle[0]), str(row.spindle[1]), str(row.tool), str(row.d),
                *(fixed(row.offset[a]) if a in row.offset else "" for a in self.axes), row.modes,
                fixed(row.t0), fixed(row.duration)])
        return self._text_row(row)

    def _text_row(self, row: Row) -> str:
        rec = row.record
        kind = rec.kind
        where = f"{row.n:>6} {self._src(rec):<18} {kind:<6}"
        end = " ".join(f"{a}{fixed(row.end[a])}" for a in self.axes if a in row.end) or "-"
        if kind == "aux":
            what = f"{rec.function}{fixed(rec.value)} at {end}"
        elif kind == "dwell":
            what = f"{fixed(rec.seconds)} s at {end}"
        else:
            what = end
            if kind == "arc":
                centre = " ".join(f"{a}{fixed((row.center or {}).get(a))}" for a in rec.plane[:2])
                what += f" {rec.direction} centre {centre} R{fixed(rec.radius)}"
                if rec.turns:
                    what += f" +{rec.turns} turns"
            if rec.feed is not None:
                what += f" F{fixed(rec.feed)} {rec.feed_mode}"
        offset = " ".join(f"{a}{fixed(row.offset[a])}" for a in self.axes if a in row.offset)
        state = f"S{fixed(row.spindle[0])} M{row.spindle[1]} T{row.tool} D{row.d} offset {offset or '-'} [{row.modes}]"
        return f"{where} {what} | {state} | t {fixed(row.t0)} +{fixed(row.duration)}"

    def diagnostic(self, d) -> str:
        src = f"{relative_file(d.file, self.base)}:{d.line}"
        if self.fmt == "jsonl":
            return (f'{{"kind":"diagnostic","code":"{d.code}","severity":"{d.severity}","src":{_json_text(src)},'
                    f'"col":{d.col},"message":{_json_text(d.message)}}}')
        if self.fmt == "csv":
            cells = [""] * len(self.columns())
            cells[1], cells[2], cells[-2] = "diagnostic", src, f"{d.code} {d.severity}: {d.message}"
            return _csv_line(cells)
        return f"{'':>6} {src:<18} {d.code} {d.severity}: {d.message}"

    def end(self, result) -> str:
        ended = result.ended_by or ""
        if self.fmt == "jsonl":
            return (f'{{"kind":"end","moves":{result.moves},"ended_by":{_json_text(result.ended_by)},'
                    f'"cycle_time":{fixed(result.cycle_time)},"ok":{"true" if result.ok else "false"}}}')
        if self.fmt == "csv":
            cells = [""] * len(self.columns())
            cells[1], cells[-2] = "end", f"moves={result.moves} ended_by={ended} ok={int(result.ok)}"
            cells[-1] = fixed(result.cycle_time)
            return _csv_line(cells)
        return (f"# end: {result.moves} moves, ended by {ended or 'end of file'}, cycle time "
                f"{fixed(result.cycle_time)} s, {'ok' if result.ok else 'errors'}")


def _csv_line(cells: list[str]) -> str:
    out = io.StringIO()
    csv.writer(out, lineterminator="").writerow(cells)
    return out.getvalue()


def expand(source: str | Path, sink: Callable[[str], None], machine: Machine | dict | str | Path | None = None, *,
           fmt: str = "jsonl", frame: str = "part", block_skip: bool = False):
    """Expand a program file: ``sink`` receives every text line (no newline) as it is made, in
    constant memory whatever the program's length.  Returns the
    :class:`~fagorcnc.simulate.DryRun`.  Raises :class:`ValueError` for a bad format or frame,
    :class:`~fagorcnc.config.machine.MachineError` for a bad machine."""
    mach = load_machine(machine)
    path = Path(source)
    writer = Writer(fmt, mach.axis_names, path.resolve().parent)
    expansion = Expansion(path, mach, frame=frame, block_skip=block_skip)
    for line in writer.header(path.name, frame):
        sink(line)
    result = expansion.run(lambda row: sink(writer.row(row)))
    for d in result.diagnostics:
        sink(writer.diagnostic(d))
    sink(writer.end(result))
    return result


def expand_text(source: str | Path, machine: Machine | dict | str | Path | None = None, **options) -> str:
    """The whole expansion as one string (for tests and small programs)."""
    lines: list[str] = []
    expand(source, lines.append, machine, **options)
    return "\n".join(lines) + "\n"


# ----------------------------------------------------------------------------- golden files
@dataclass
class GoldenOutcome:
    """The comparison of one program with its golden file."""

    program: str
    golden: Path
    status: str                 # "match", "differ", "written"
    line: int = 0               # first line that differs (1-based), 0 when none
    expected: str | None = None  # the golden file's line there (None: the golden file ends first)
    actual: str | None = None    # the new expansion's line there (None: it ends first)


def golden_path(directory: Path, program: Path, fmt: str) -> Path:
    """Where the golden expansion of ``program`` lives."""
    return directory / (program.name + FORMATS[fmt])


class GoldenComparison:
    """A sink that compares the lines it receives with a stored expansion (constant memory):
    remembers the first line that differs; :meth:`outcome` once the expansion ended."""

    def __init__(self, golden: Path, program: str) -> None:
        self.golden, self.program = golden, program
        self._stored = open(golden, encoding="utf-8")  # noqa: SIM115 (closed by outcome())
        self._number = 0
        self._first: tuple[int, str | None, str] | None = None

    def __call__(self, actual: str) -> None:
        if self._first is not None:
            return
        self._number += 1
        expected = self._stored.readline()
        if not expected:
            self._first = (self._number, None, actual)
        elif expected.rstrip("\n") != actual:
            self._first = (self._number, expected.rstrip("\n"), actual)

    def outcome(self) -> GoldenOutcome:
        try:
            if self._first is None:
                rest = self._stored.readline()
                if not rest:
                    return GoldenOutcome(self.program, self.golden, "match")
                return GoldenOutcome(self.program, self.golden, "differ", self._number + 1, rest.rstrip("\n"), None)
            line, expected, actual = self._first
            return GoldenOutcome(self.program, self.golden, "differ", line, expected, actual)
        finally:
            self._stored.close()


def check_golden(program: str | Path, directory: str | Path, machine: Machine | dict | str | Path | None = None, *,
                 fmt: str = "jsonl", frame: str = "part", block_skip: bool = False,
                 update: bool = False) -> GoldenOutcome:
    """Compare ``program``'s expansion with its golden file in ``directory`` (written when missing
    or with ``update``)."""
    path, directory = Path(program), Path(directory)
    golden = golden_path(directory, path, fmt)
    if update or not golden.exists():
        with open(golden, "w", encoding="utf-8", newline="\n") as out:
            expand(path, lambda line: out.write(line + "\n"), machine, fmt=fmt, frame=frame, block_skip=block_skip)
        return GoldenOutcome(str(program), golden, "written")
    comparison = GoldenComparison(golden, str(program))
    expand(path, comparison, machine, fmt=fmt, frame=frame, block_skip=block_skip)
    return comparison.outcome()


# ----------------------------------------------------------------------------- the command
def command(args: argparse.Namespace) -> int:
    """Handler of ``fagorcnc expand``: 0 clean (or every golden file matches), 1 errors or a
    difference, 2 bad usage."""
    try:
        machine = load_machine(args.machine)
    except MachineError as exc:
        print(f"fagorcnc: {exc}", file=sys.stderr)
        return 2
    for file in args.files:
        if not Path(file).is_file():
            print(f"{file}: cannot read the file: {not_a_file(file)}", file=sys.stderr)
            return 2
    if args.golden:
        return _golden_command(args, machine)
    if args.update:
        print("fagorcnc: --update goes with --golden DIR", file=sys.stderr)
        return 2
    if len(args.files) != 1:
        print("fagorcnc: expand writes one program at a time (several with --golden DIR)", file=sys.stderr)
        return 2
    options = {"fmt": args.format, "frame": args.frame, "block_skip": args.block_skip}
    if not args.output:
        result = expand(args.files[0], lambda line: sys.stdout.write(line + "\n"), machine, **options)
        return 0 if result.ok else 1
    try:
        with open(args.output, "w", encoding="utf-8", newline="\n") as out:
            result = expand(args.files[0], lambda line: out.write(line + "\n"), machine, **options)
    except OSError as exc:
        print(f"fagorcnc: cannot write {args.output}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    return 0 if result.ok else 1


def _golden_command(args: argparse.Namespace, machine: Machine) -> int:
    directory = Path(args.golden)
    if directory.exists() and not directory.is_dir():
        print(f"fagorcnc: --golden {directory}: not a directory", file=sys.stderr)
        return 2
    directory.mkdir(parents=True, exist_ok=True)
    status = 0
    for file in args.files:
        outcome = check_golden(file, directory, machine, fmt=args.format, frame=args.frame,
                               block_skip=args.block_skip, update=args.update)
        if outcome.status == "written":
            print(f"{file}: golden expansion written to {outcome.golden}")
        elif outcome.status == "match":
            print(f"{file}: matches {outcome.golden}")
        else:
            status = 1
            print(f"{file}: CLI002 differs from {outcome.golden} at line {outcome.line}:")
            print(f"  golden: {outcome.expected if outcome.expected is not None else '(the golden file ends here)'}")
            print(f"  now:    {outcome.actual if outcome.actual is not None else '(the expansion ends here)'}")
    return status


def add_parser(sub) -> None:
    """The ``expand`` sub-command's arguments."""
    p = sub.add_parser("expand", help="one line per executed record (moves, arcs, dwells, M/S/T/D) with its planned "
                                      "time: a canonical, diffable dump; --golden DIR for regression tests")
    p.add_argument("files", nargs="+", metavar="FILE", help="part program file (several with --golden)")
    p.add_argument("--format", choices=tuple(FORMATS), default="jsonl", help="jsonl (default), csv or text")
    p.add_argument("--frame", choices=FRAMES, default="part",
                   help="positions of the tool tip in part coordinates (default) or of the controlled point in "
                        "machine coordinates")
    p.add_argument("-o", "--output", metavar="OUT", help="write the expansion to OUT instead of the output")
    p.add_argument("--machine", metavar="M", help="machine configuration (TOML or LinuxCNC INI)")
    p.add_argument("--golden", metavar="DIR",
                   help="compare each program's expansion with DIR/<name>.<format> (written when missing)")
    p.add_argument("--update", action="store_true", help="with --golden: rewrite the golden files")
    p.add_argument("--block-skip", action="store_true", help="skip blocks that start with '/'")
    p.set_defaults(func=command)
