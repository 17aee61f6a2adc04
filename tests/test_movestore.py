"""simulate()'s records stored as columns (fagorcnc/interp/movestore.py; issue 27 item 2: at most
0.5 KiB per block)."""

from __future__ import annotations

import pickle
import sys
import tracemalloc
from itertools import pairwise
from pathlib import Path

import pytest

import fagorcnc
from fagorcnc.interp.movestore import Moves
from fagorcnc.interp.records import Arc, Aux, Line, Source

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from plan_speed import raster

#: Every kind of record: rapids and lines (rows), a G92 preset (part end points of their own), an arc
#: (an object: the line after it has a start of its own), a dwell, auxiliary functions, a compensated
#: contour (objects), a feed change, a block making two records (G74-free: a line and its M, and M30).
MIXED = """G90 G0 X0 Y0 Z5
G1 Z0 F300
X10 Y5
G92 X0 Y0
X20
G2 X20 Y0 I5 J0
G1 X40 M8
G4 K0.5
F600 Y10
G41 D1 G1 X50
X60 Y20
G40 G1 X70
G0 Z10
M30
"""


def _records(text: str) -> list:
    """The interpreter's records of ``text``, as objects (the streaming API keeps none)."""
    return list(fagorcnc.interpret(text=text))


def test_moves_give_back_the_records_of_the_interpreter():
    records = _records(MIXED)
    moves = Moves(records)
    kinds = {type(r).__name__ for r in records}
    assert {"Line", "Arc", "Aux", "Dwell"} <= kinds
    assert len(moves) == len(records) and moves == records and records == moves and list(moves) == records
    assert [moves[i] for i in range(len(records))] == records
    assert moves[-1] == records[-1] and moves[2:7] == records[2:7] and moves[::-3] == records[::-3]
    assert moves == tuple(records) and moves != records[:-1] and moves == Moves(records)
    with pytest.raises(IndexError):
        moves[len(records)]
    # records other than plain straight moves are kept as they came: the same objects
    for i, r in enumerate(records):
        if type(r) is not Line or r.comp is not None:
            assert moves[i] is r
    # the plain lines are made again: equal, the very dyn and frame objects, dicts in the same key order
    lines = [(i, r) for i, r in enumerate(records) if type(r) is Line and r.comp is None]
    assert len(lines) >= 6
    for i, r in lines:
        m = moves[i]
        assert m == r and m is not r and m.dyn is r.dyn and m.frame is r.frame
        assert list(m.end) == list(r.end) and list(m.start) == list(r.start) and m.src == r.src
        assert (m.end_part is m.end) == (r.end_part is r.end)
    # after the G92 preset, end_part differs from end: kept in coordinates of its own
    assert any(r.end_part is not r.end for _, r in lines)


def test_iterating_shares_points_and_sources_as_the_interpreter_does():
    # the interpreter gives the end dict of a move to the next as its start: iteration does the same
    records = _records("G90 G1 X0 Y0 F1000\nX1\nX2 Y1\nX3\nM30\n")
    assert records[1].start is records[0].end
    again = list(Moves(records))
    assert again == records and again[1].start is again[0].end and again[2].start is again[1].end
    # one block making several moves (a canned cycle) shares one Source between them
    text = "G90 G0 X0 Y0 Z10\nG81 Z2 I-5 F100\nX10\nG80\nM30\n"
    records = _records(text)

    def plain(r) -> bool:
        return type(r) is Line and r.comp is None

    pairs = [(i, a.src is b.src) for i, (a, b) in enumerate(pairwise(records)) if plain(a) and plain(b)]
    assert any(same for _, same in pairs)
    again = list(Moves(records))
    assert again == records
    assert [(i, again[i].src is again[i + 1].src) for i, _ in pairs] == pairs


def test_moves_keep_exact_types_and_texts():
    # an int coordinate, a non-ASCII block text and a record of another subclass come back as they were
    src = Source("<t>", 7, "G1 X1 ; déjà vu ✓")
    dyn = object()
    a = Line("linear", {"X": 0.0}, {"X": 1.0}, {"X": 1.0}, 100.0, "G94", src, dyn=dyn)
    b = Line("linear", a.end, {"X": 2}, {"X": 2}, 100.0, "G94", Source("<t>", 8, "X2"), dyn=dyn)
    c = Line("rapid", b.end, {"X": 3.0, "Y": -0.0}, {"X": 3.0, "Y": -0.0}, None, "G94", Source("<t>", 9, ""))
    d = Aux("aux", "M", 30.0, "after", c.end, Source("<t>", 10, "M30"))
    moves = Moves([a, b, c, d])
    assert list(moves) == [a, b, c, d]
    assert moves[0].src.text == "G1 X1 ; déjà vu ✓" and moves[0].dyn is dyn
    assert moves[1] is b and type(moves[1].end["X"]) is int   # an int: kept as the object it is
    assert moves[2].feed is None and str(moves[2].end["Y"]) == "-0.0" and moves[2].src.text == ""
    assert moves[3] is d
    assert pickle.loads(pickle.dumps(Moves([c, d]))) == [c, d]
    assert Moves() == [] and not Moves() and repr(Moves([d])) == f"Moves([{d!r}])"


def test_simulate_keeps_its_records_in_columns_equal_to_the_interpreters():
    r = fagorcnc.simulate(MIXED)
    assert r.ok and type(r.moves) is Moves
    assert r.moves == _records(MIXED)
    assert r.summary.moves == sum(1 for m in _records(MIXED) if m.kind not in ("aux", "dwell"))
    assert any(type(m) is Arc for m in r.moves)


def test_a_planning_error_still_keeps_every_record_of_the_program():
    # the records are planned as the interpreter makes them; after a PLN001 the rest of the program
    # still runs, as when it was interpreted whole before planning (rapid override 0: seed 002 L20355)
    text = "G0 X100\nG1 X10 F100\nM30\n"
    r = fagorcnc.simulate(text, {"planner": {"rapid_override": 0}})
    assert [d.code for d in r.diagnostics] == ["PLN001"] and not r.ok
    assert [m.kind for m in r.moves] == ["rapid", "linear", "aux"]
    assert r.moves == _records(text)


def test_simulate_keeps_a_raster_in_columns_of_about_90_bytes_a_move(tmp_path):
    # issue 27: simulate() at most 0.5 KiB per block.  Per plain move of the raster (X Y Z on three axes, one
    # block each), in the columns:
    #   values: feed + 3 end coordinates = 4 doubles = 32 B      rows: 5 ints (context, at, start,
    #   part, source) = 20 B                                      where: 1 int = 4 B
    #   source: line int 4 B + text end 8 B + the text "X12.5000 Y37.0000 Z1.2345" = 24 B: 36 B
    # = 92 B, plus the arrays' over-allocation (at most 1/8 and a little): at most 120 B, against
    # 136 (Line) + 184 (end dict) + 2 x 24 (floats) + 56 (Source) + 72 (text) + 28 (line) = 524 B as objects.
    # tracemalloc counts bytes, whatever the load.  (What does not grow with the program, the stream's
    # window of at most some 4 100 parsed blocks and the planner's look-ahead, comes on top: 0.13 KiB per
    # block of peak RSS in all at 200 000 blocks, benchmarks/throughput.py --only-simulate.)
    path = tmp_path / "raster.nc"
    path.write_text("\n".join(raster(5_000, "G50")) + "\n")
    result = fagorcnc.simulate(path)
    assert result.ok and type(result.moves) is Moves and len(result.moves) > 5_000
    assert len(result.moves._objects) == 1   # the M30; every move is a row
    records = list(result.moves)
    tracemalloc.start()
    try:
        before = tracemalloc.get_traced_memory()[0]
        moves = Moves(records)
        kept = tracemalloc.get_traced_memory()[0] - before
    finally:
        tracemalloc.stop()
    assert moves == records
    assert kept / len(records) <= 120
