"""Streaming: iter_lines keeps constant memory whatever the program length."""

from __future__ import annotations

import tracemalloc

from fagorcnc.syntax import iter_lines, line_parser


def _program(n: int):
    yield "%BIG"
    for i in range(n):
        yield f"N{10 + 5 * i} G1 X{i % 200 - 100}.125 Y{i % 150 - 75}.5 F{1000 + i % 7}"
        if i % 50 == 0:
            yield f"P1 = P1 + [{i} * 2] ; computed"  # a line for the LALR path
    yield "M30"


def _peak(n: int) -> int:
    line_parser()  # grammar compiled outside the measurement
    tracemalloc.start()
    try:
        count = sum(1 for _ in iter_lines(_program(n)))
        assert count > n
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_streaming_memory_does_not_grow_with_program_size():
    small, large = _peak(2_000), _peak(8_000)
    assert large < small * 1.5 + 64_000, (small, large)
