"""Parse-speed benchmark: fagorcnc against other Python G-code parsers.

Run from the repository root::

    python benchmarks/parse_speed.py [--blocks N] [--repeat R] [--memory] [--json]

The script generates a deterministic CAM-finishing-style ISO program (``%BENCH``,
then ``N10``, ``N15``, ... blocks: ~5 % ``G0 X Y Z`` rapids, ~75 % ``G1 X Y Z F``
feeds, ~20 % ``G2``/``G3 X Y I J`` arcs, coordinates with 3-4 decimals, then
``M30``), writes it to a temporary file, and times in the same process, best of
``--repeat`` runs (``time.perf_counter``):

* ``fagorcnc.syntax.parse_text``: whole-program parse into a ``Program``;
* ``fagorcnc.syntax.iter_lines``: streaming, one ``(node, diagnostics)`` per line;
* ``gcodeparser.parse_gcode_lines`` (materialised into a list);
* ``pygcode.Line`` for every line (timed on the first 20 000 lines and scaled
  when a full run would take more than ~20 s; the output says so).

It prints lines/s per parser and the ratio fagorcnc/peer (above 1 means
fagorcnc is faster).  The peers come from the ``bench`` extra
(``pip install -e '.[bench]'``); a peer that is not installed is reported as
"not installed" and skipped.

``--memory`` also measures the peak traced memory (``tracemalloc``) of
streaming ``iter_lines`` over a lazily generated program of N and 4N blocks
(``--memory-blocks``, default 20 000): with streaming the peak does not grow
with the size of the program.  It is optional because tracing is slow.
"""

from __future__ import annotations

import argparse
import gc
import importlib
import importlib.metadata
import json
import math
import os
import platform
import random
import sys
import tempfile
import time
import tracemalloc
from collections.abc import Callable, Iterator
from dataclasses import asdict, dataclass, field
from types import ModuleType
from typing import Any

import fagorcnc.syntax

SEED = 8065
PROGRAM_NAME = "BENCH"
PYGCODE_BUDGET_S = 20.0  # time on a subset and scale when a full pygcode run would take longer
PYGCODE_SUBSET = 20_000  # lines timed when pygcode is scaled
PYGCODE_PROBE = 2_000  # lines used to estimate the pygcode full-run time


# --------------------------------------------------------------------------- program


def _fmt(value: float, rng: random.Random) -> str:
    """A coordinate with 3 or 4 decimals, as CAM posts write them."""
    return f"{value:.{rng.choice((3, 4))}f}"


def program_lines(blocks: int, seed: int = SEED) -> Iterator[str]:
    """Yield the lines (no newline) of the benchmark program, lazily and deterministically.

    ``%BENCH``, ``blocks`` numbered motion blocks, then ``M30``.
    """
    rng = random.Random(seed)
    yield f"%{PROGRAM_NAME}"
    x, y, z = 0.0, 0.0, 5.0
    feeds = (800, 1000, 1200, 1500, 2000, 2500)
    for k in range(blocks):
        number = 10 + 5 * k
        kind = rng.random()
        if kind < 0.05:  # rapid: reposition above the part
            x = rng.uniform(-150.0, 150.0)
            y = rng.uniform(-100.0, 100.0)
            z = rng.uniform(1.0, 25.0)
            yield f"N{number} G0 X{_fmt(x, rng)} Y{_fmt(y, rng)} Z{_fmt(z, rng)}"
        elif kind < 0.80:  # linear feed: short finishing step
            x += rng.uniform(-2.0, 2.0)
            y += rng.uniform(-2.0, 2.0)
            z = rng.uniform(-12.0, 0.5)
            feed = rng.choice(feeds)
            yield f"N{number} G1 X{_fmt(x, rng)} Y{_fmt(y, rng)} Z{_fmt(z, rng)} F{feed}"
        else:  # arc in the XY plane: centre at (x+i, y+j), end point on the same circle
            radius = rng.uniform(0.5, 20.0)
            start = rng.uniform(0.0, 2.0 * math.pi)
            sweep = rng.uniform(0.1, 1.5)
            cw = rng.random() < 0.5
            i, j = -radius * math.cos(start), -radius * math.sin(start)
            cx, cy = x + i, y + j
            end = start - sweep if cw else start + sweep
            x, y = cx + radius * math.cos(end), cy + radius * math.sin(end)
            yield (f"N{number} G{2 if cw else 3} X{_fmt(x, rng)} Y{_fmt(y, rng)} "
                   f"I{_fmt(i, rng)} J{_fmt(j, rng)}")
    yield "M30"


def write_program(blocks: int) -> str:
    """Write the program to a new temporary file and return its path."""
    fd, path = tempfile.mkstemp(prefix="fagorcnc-bench-", suffix=".nc")
    with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as f:
        for line in program_lines(blocks):
            f.write(line)
            f.write("\n")
    return path


# --------------------------------------------------------------------------- timing


@dataclass
class Result:
    """One measured parser."""

    parser: str
    version: str | None
    installed: bool = True
    seconds: float | None = None  # best run over ``lines_timed`` lines
    lines_timed: int | None = None
    lines_per_s: float | None = None
    scaled: bool = False  # timed on a subset of the lines
    note: str = ""
    runs: list[float] = field(default_factory=list)


def best_time(fn: Callable[[], object], repeat: int) -> tuple[float, list[float]]:
    """Best wall time of ``repeat`` calls of ``fn``; the result is freed outside the timing."""
    runs: list[float] = []
    for _ in range(repeat):
        gc.collect()
        t0 = time.perf_counter()
        result = fn()
        t1 = time.perf_counter()
        del result
        runs.append(t1 - t0)
    return min(runs), runs


def timed(parser: str, version: str | None, fn: Callable[[], object], lines: int, repeat: int,
          *, scaled: bool = False, note: str = "") -> Result:
    best, runs = best_time(fn, repeat)
    return Result(parser, version, seconds=best, lines_timed=lines, lines_per_s=lines / best,
                  scaled=scaled, note=note, runs=runs)


def optional(module: str) -> ModuleType | None:
    try:
        return importlib.import_module(module)
    except ImportError:
        return None


def dist_version(dist: str) -> str | None:
    try:
        return importlib.metadata.version(dist)
    except importlib.metadata.PackageNotFoundError:
        return None


def bench_fagorcnc(text: str, path: str, blocks: int, lines: int, repeat: int) -> list[Result]:
    version = dist_version("fagorcnc")
    fagorcnc.syntax.line_parser()  # compile the grammar once, outside the timings

    program = fagorcnc.syntax.parse_text(text, path)  # correctness check (and warm-up)
    assert program.ok, [str(d) for d in program.diagnostics if d.severity == "error"]
    assert program.name == PROGRAM_NAME, program.name
    assert len(program.blocks) == blocks + 1, len(program.blocks)  # + M30
    del program

    def whole() -> object:
        program = fagorcnc.syntax.parse_text(text, path)
        assert program.ok
        return program.blocks

    def streaming() -> None:
        for _node, _diags in fagorcnc.syntax.iter_lines(text, path):
            pass

    return [timed("fagorcnc parse_text", version, whole, lines, repeat),
            timed("fagorcnc iter_lines", version, streaming, lines, repeat)]


def bench_gcodeparser(text: str, blocks: int, lines: int, repeat: int) -> Result:
    version = dist_version("gcodeparser")
    module = optional("gcodeparser")
    if module is None:
        return Result("gcodeparser", version, installed=False)
    parse_gcode_lines: Callable[[str], Iterator[Any]] = module.parse_gcode_lines

    parsed = list(parse_gcode_lines(text))  # correctness check (and warm-up)
    assert len(parsed) == blocks + 1, len(parsed)  # one GcodeLine per G/M word; %BENCH yields none
    del parsed

    return timed("gcodeparser", version, lambda: list(parse_gcode_lines(text)), lines, repeat)


def bench_pygcode(text: str, lines: int, repeat: int) -> Result:
    version = dist_version("pygcode")
    module = optional("pygcode")
    if module is None:
        return Result("pygcode", version, installed=False)
    line_cls: Callable[[str], Any] = module.Line

    all_lines = text.splitlines()
    probe = all_lines[:PYGCODE_PROBE]
    t0 = time.perf_counter()
    for line in probe:  # estimate (and warm-up)
        line_cls(line)
    estimate = (time.perf_counter() - t0) / len(probe) * lines
    if estimate <= PYGCODE_BUDGET_S:
        return timed("pygcode", version, lambda: [line_cls(line) for line in text.splitlines()], lines, repeat)

    subset = "\n".join(all_lines[:PYGCODE_SUBSET])
    n = min(PYGCODE_SUBSET, lines)
    note = f"timed on the first {n} lines and scaled (a full run was estimated at {estimate:.0f} s)"
    return timed("pygcode", version, lambda: [line_cls(line) for line in subset.splitlines()], n, repeat,
                 scaled=True, note=note)


# --------------------------------------------------------------------------- memory


def streaming_peak(blocks: int) -> int:
    """Peak traced memory (bytes) while streaming ``iter_lines`` over a lazily generated program."""
    gc.collect()
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        for _node, _diags in fagorcnc.syntax.iter_lines(program_lines(blocks), "<bench>"):
            pass
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def bench_memory(blocks: int) -> dict[str, int]:
    fagorcnc.syntax.line_parser()
    for _ in fagorcnc.syntax.iter_lines(program_lines(100), "<warm-up>"):  # fill the parser's caches
        pass
    return {str(n): streaming_peak(n) for n in (blocks, 4 * blocks)}


# --------------------------------------------------------------------------- report


def ratios(results: list[Result]) -> dict[str, dict[str, float | None]]:
    """fagorcnc lines/s divided by each peer's lines/s, for both fagorcnc modes."""
    ours = {r.parser.split()[1]: r.lines_per_s for r in results if r.parser.startswith("fagorcnc ")}
    table: dict[str, dict[str, float | None]] = {}
    for peer in results:
        if peer.parser.startswith("fagorcnc ") or not peer.installed:
            continue
        table[peer.parser] = {
            mode: (rate / peer.lines_per_s if rate and peer.lines_per_s else None) for mode, rate in ours.items()
        }
    return table


def print_table(report: dict[str, Any], results: list[Result]) -> None:
    print(f"fagorcnc parse-speed benchmark: {report['blocks']} blocks ({report['lines']} lines), "
          f"best of {report['repeat']}")
    print(f"Python {report['python']} ({report['implementation']}), lark {report['lark']}, "
          f"fagorcnc {report['fagorcnc']}")
    print()
    print(f"{'parser':<24} {'version':<9} {'lines/s':>10} {'best (s)':>9}  note")
    for r in results:
        if not r.installed:
            print(f"{r.parser:<24} {'-':<9} {'not installed':>10}")
            continue
        assert r.lines_per_s is not None and r.seconds is not None
        print(f"{r.parser:<24} {r.version or '?':<9} {r.lines_per_s:>10,.0f} {r.seconds:>9.3f}  {r.note}".rstrip())
    table = report["ratios"]
    if table:
        print()
        print(f"{'ratio fagorcnc/peer':<24} {'parse_text':>11} {'iter_lines':>11}")
        for peer, row in table.items():
            cells = [f"{v:>10.2f}x" if v is not None else f"{'-':>11}" for v in (row["parse_text"], row["iter_lines"])]
            print(f"{peer:<24} {cells[0]} {cells[1]}")
    skipped = [r.parser for r in results if not r.installed]
    if skipped:
        print(f"\nnot installed (pip install -e '.[bench]'): {', '.join(skipped)}")
    memory = report.get("memory")
    if memory:
        print()
        print("streaming memory (tracemalloc peak, iter_lines over a lazily generated program)")
        for n, peak in memory["peak_bytes"].items():
            print(f"  {int(n):>9,} blocks: {peak / 1024:>8.1f} KiB")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    ap.add_argument("--blocks", type=int, default=100_000, help="motion blocks in the program (default 100000)")
    ap.add_argument("--repeat", type=int, default=3, help="runs per parser, best is kept (default 3)")
    ap.add_argument("--memory", action="store_true", help="also measure streaming memory (slow: tracemalloc)")
    ap.add_argument("--memory-blocks", type=int, default=20_000,
                    help="N for --memory: peaks are measured for N and 4N blocks (default 20000)")
    ap.add_argument("--json", action="store_true", help="print the results as JSON")
    args = ap.parse_args(argv)
    if args.blocks < 1 or args.repeat < 1 or args.memory_blocks < 1:
        ap.error("--blocks, --repeat and --memory-blocks must be positive")

    path = write_program(args.blocks)
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
        lines = len(text.splitlines())
        results = bench_fagorcnc(text, path, args.blocks, lines, args.repeat)
        results.append(bench_gcodeparser(text, args.blocks, lines, args.repeat))
        results.append(bench_pygcode(text, lines, args.repeat))
    finally:
        os.unlink(path)
    del text

    report: dict[str, Any] = {
        "python": platform.python_version(),
        "implementation": platform.python_implementation(),
        "lark": dist_version("lark"),
        "fagorcnc": dist_version("fagorcnc"),
        "blocks": args.blocks,
        "lines": lines,
        "repeat": args.repeat,
        "seed": SEED,
        "results": [asdict(r) for r in results],
        "ratios": ratios(results),
    }
    if args.memory:
        report["memory"] = {"blocks": args.memory_blocks, "peak_bytes": bench_memory(args.memory_blocks)}

    if args.json:
        json.dump(report, sys.stdout, indent=2)
        print()
    else:
        print_table(report, results)
    return 0


if __name__ == "__main__":
    sys.exit(main())
