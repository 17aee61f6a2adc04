"""The records :func:`fagorcnc.simulate` keeps, stored as columns (issue 27: at most 0.5 KiB per block).

A CAM program is mostly plain straight moves: as objects, each one cost its :class:`Line` (136 B),
its end point dict (184 B) and floats, its :class:`Source` and the block's text, about 0.55 KiB.
:class:`Moves` keeps such a move as a row of machine arrays instead: the end point's coordinates
(8 B each), the feed, indexes into a table of the few distinct contexts (kind, feed mode, file,
``dyn``, ``frame``, ``joins``, axis names) and into the block sources (line number, the text as
UTF-8 bytes), and where its start and part end points are (the end of the row before and the
end itself in the common case, else coordinates of their own): about 90 B per block.

On access (``moves[i]``, iteration, slices) the same record is made again: a :class:`Line` with
dicts in the same key order, equal floats, an equal :class:`Source`, the very ``dyn``/``frame``
objects; iterating also shares, as the interpreter does, the end dict of a move with the start of
the next one and one :class:`Source` between consecutive moves of one block.  A record that is
not such a plain line (an arc, a compensated or threaded move, a chord of a curve, a dwell, an
auxiliary function, a point that is not a dict of floats...) is kept as it came.  Records are
immutable, and nothing may change their dicts (the interpreter already shares them between
records): a record got twice is equal, not the same object.
"""

from __future__ import annotations

from array import array
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import fields
from operator import attrgetter
from typing import overload

from .records import Line, Source

#: The start of a row is the end point of the row before (the same dict when iterating).
_AT_END_BEFORE = -1
#: The part-coordinate end point of a row is its end point (one dict: no origin shift).
_IS_END = -1
#: Line numbers and offsets of a row are kept in C ints ("i": 32 bits signed).
_INT_MAX = 2**31 - 1
#: Ints per row in Moves._rows: context, offset of the values, of the start, of the part end point, source.
_ROW = 5
#: Records added are stored in batches of this many (see Moves.flush).
BATCH = 256
#: Distinct contexts kept, at most: a move of yet another one is kept as an object.
MAX_CONTEXTS = 1 << 16

#: The fields of Line a row stores; every other one (comp, thread, css) must have its default.
_STORED = ("kind", "start", "end", "end_part", "feed", "feed_mode", "src", "dyn", "frame", "joins")
_OTHERS = tuple(f.name for f in fields(Line) if f.name not in _STORED)
_OTHER_DEFAULTS = tuple(f.default for f in fields(Line) if f.name not in _STORED)


def _others_of(record) -> tuple:
    return tuple(getattr(record, name) for name in _OTHERS)


#: The values of the fields a row does not store (attrgetter of one name gives no tuple).
_others: Callable[[Line], tuple] = attrgetter(*_OTHERS) if len(_OTHERS) > 1 else _others_of

#: Line's and Source's fields when this module was written, in order: records are then made by
#: setting their slots, about twice as fast as the frozen dataclasses' __init__ (one
#: object.__setattr__ call per field); with other fields, by their __init__.
LINE_FIELDS = ("kind", "start", "end", "end_part", "feed", "feed_mode", "src", "comp", "dyn", "frame", "joins",
               "thread", "css")
SOURCE_FIELDS = ("file", "line", "text")


#: Whether Line has the fields of LINE_FIELDS, comp, thread and css defaulting to None.
_KNOWN = tuple(f.name for f in fields(Line)) == LINE_FIELDS and _OTHER_DEFAULTS == (None, None, None)


def _line_maker() -> Callable[..., Line]:
    """``make(kind, start, end, end_part, feed, feed_mode, src, dyn, frame, joins)``: a :class:`Line`,
    the fields a row does not store at their default."""
    if not _KNOWN:
        def make(kind, start, end, end_part, feed, feed_mode, src, dyn, frame, joins) -> Line:
            return Line(kind=kind, start=start, end=end, end_part=end_part, feed=feed, feed_mode=feed_mode,
                        src=src, dyn=dyn, frame=frame, joins=joins)
        return make
    blank = Line.__new__
    (s_kind, s_start, s_end, s_end_part, s_feed, s_feed_mode, s_src, s_comp, s_dyn, s_frame, s_joins, s_thread,
     s_css) = (getattr(Line, name).__set__ for name in LINE_FIELDS)

    def make_fast(kind, start, end, end_part, feed, feed_mode, src, dyn, frame, joins) -> Line:
        line = blank(Line)
        s_kind(line, kind)
        s_start(line, start)
        s_end(line, end)
        s_end_part(line, end_part)
        s_feed(line, feed)
        s_feed_mode(line, feed_mode)
        s_src(line, src)
        s_comp(line, None)
        s_dyn(line, dyn)
        s_frame(line, frame)
        s_joins(line, joins)
        s_thread(line, None)
        s_css(line, None)
        return line
    return make_fast


def _source_maker() -> Callable[[str, int, str], Source]:
    """``make(file, line, text)``: a :class:`Source`."""
    if tuple(f.name for f in fields(Source)) != SOURCE_FIELDS:
        return Source
    blank = Source.__new__
    s_file, s_line, s_text = (getattr(Source, name).__set__ for name in SOURCE_FIELDS)

    def make_fast(file: str, line: int, text: str) -> Source:
        src = blank(Source)
        s_file(src, file)
        s_line(src, line)
        s_text(src, text)
        return src
    return make_fast


_new_line = _line_maker()
_new_source = _source_maker()


class Moves(Sequence):
    """A sequence of motion records (:mod:`fagorcnc.interp.records`) in little memory: plain
    straight moves as columns, the rest as objects.  Compares equal to a list or tuple of the same
    records; ``moves[i]``, slices and iteration make the records on access (see the module)."""

    __slots__ = ("_context_of", "_contexts", "_last_context", "_last_end", "_last_src", "_lines", "_objects",
                 "_pending", "_rows", "_text", "_text_end", "_values", "_where")

    def __init__(self, records: Iterable = ()) -> None:
        self._where = array("i")      # per record: a row (>= 0), or ~k for self._objects[k]
        self._objects: list = []      # the records not stored as rows
        self._contexts: list[tuple] = []   # (kind, feed_mode, has_feed, file, dyn, frame, joins, axes)
        self._context_of: dict[tuple, int] = {}
        # the rows: _ROW ints each (context, at, start, part, source), and at _values[at] the feed
        # (0.0 without one), the end point's coordinates, then the start's and the part end point's
        # when they have their own (start: offset, or _AT_END_BEFORE; part: offset, or _IS_END)
        self._rows = array("i")
        self._values = array("d")
        # the sources: one entry per Source object (consecutive rows of one block share one)
        self._lines = array("i")
        self._text_end = array("q")   # end offset of each text in self._text
        self._text = bytearray()      # the texts, UTF-8
        self._last_src: Source | None = None
        self._last_end: dict | None = None   # the end dict of the last row stored
        self._last_context = -1
        self._pending: list = []      # records added, not stored yet (at most BATCH)
        self.extend(records)
        self.flush()

    # ------------------------------------------------------------------------------------ storing
    def append(self, record) -> None:
        """Add ``record`` at the end (stored with the next batch: see :meth:`flush`)."""
        pending = self._pending
        pending.append(record)
        if len(pending) >= BATCH:
            self.flush()

    def extend(self, records: Iterable) -> None:
        """Add every record of ``records`` (as :meth:`append`)."""
        append = self.append
        for record in records:
            append(record)

    def flush(self) -> None:
        """Store the records waiting in ``_pending`` (every access does it first): a plain straight move
        as a row, any other record as the object it is."""
        where, objects = self._where, self._objects
        row_of = self._row_of
        for record in self._pending:
            if type(record) is Line and (record.comp is None and record.thread is None and record.css is None
                                         if _KNOWN else _others(record) == _OTHER_DEFAULTS):
                row = row_of(record)
                if row >= 0:
                    where.append(row)
                    continue
            where.append(~len(objects))
            objects.append(record)
        self._pending = []

    def _row_of(self, rec: Line) -> int:
        """Store ``rec`` as a new row and return its index; -1 (nothing stored) when it does not fit."""
        end = rec.end
        src = rec.src
        if type(end) is not dict or type(src) is not Source:
            return -1
        axes = tuple(end)
        values = tuple(end.values())
        for v in values:
            if type(v) is not float:   # an int or anything else: the record is kept as it came
                return -1
        start = rec.start
        if start is self._last_end and start is not None:
            start_values = None
        else:
            start_values = _same_axes(start, axes)
            if start_values is None:
                return -1
        part = rec.end_part
        if part is end:
            part_values = None
        else:
            part_values = _same_axes(part, axes)
            if part_values is None:
                return -1
        feed = rec.feed
        if feed is not None and type(feed) is not float:
            return -1
        new_source = src is not self._last_src
        if new_source:
            line, text = src.line, src.text
            if type(line) is not int or not 0 <= line <= _INT_MAX or type(text) is not str \
                    or type(src.file) is not str:
                return -1
        context = self._context(rec, src.file, axes)
        values_ = self._values
        at = len(values_)
        if context < 0 or at + 1 + 3 * len(axes) > _INT_MAX or len(self._lines) >= _INT_MAX:
            return -1
        if new_source:
            self._lines.append(line)
            self._text += text.encode("utf-8", "surrogatepass")
            self._text_end.append(len(self._text))
            self._last_src = src
        values_.append(0.0 if feed is None else feed)
        values_.extend(values)
        if start_values is None:
            start_at = _AT_END_BEFORE
        else:
            start_at = len(values_)
            values_.extend(start_values)
        if part_values is None:
            part_at = _IS_END
        else:
            part_at = len(values_)
            values_.extend(part_values)
        rows = self._rows
        rows.extend((context, at, start_at, part_at, len(self._lines) - 1))
        self._last_end = end
        return len(rows) // _ROW - 1

    def _context(self, rec: Line, file: str, axes: tuple) -> int:
        """The index of the context of ``rec`` (added when new), -1 when it cannot be one."""
        kind, mode, joins, dyn, frame = rec.kind, rec.feed_mode, rec.joins, rec.dyn, rec.frame
        has_feed = rec.feed is not None
        last = self._last_context
        if last >= 0:   # mostly the context of the move before: the same objects
            c = self._contexts[last]
            if c[4] is dyn and c[5] is frame and c[6] is joins and c[0] is kind and c[1] is mode \
                    and c[3] is file and c[2] is has_feed and c[7] == axes:
                return last
        if type(kind) is not str or type(mode) is not str or not (joins is None or type(joins) is tuple):
            return -1
        # dyn and frame by identity (the context holds them, so their ids stay theirs), joins by value
        key = (kind, mode, has_feed, file, id(dyn), id(frame), joins, axes)
        try:
            index = self._context_of.get(key)
        except TypeError:   # a joins tuple that cannot be a key
            return -1
        if index is None:
            if len(self._contexts) >= MAX_CONTEXTS:
                return -1
            index = self._context_of[key] = len(self._contexts)
            self._contexts.append((kind, mode, has_feed, file, dyn, frame, joins, axes))
        self._last_context = index
        return index

    # ---------------------------------------------------------------------------------- accessing
    def __len__(self) -> int:
        return len(self._where) + len(self._pending)

    @overload
    def __getitem__(self, index: int): ...

    @overload
    def __getitem__(self, index: slice) -> list: ...

    def __getitem__(self, index):
        if self._pending:
            self.flush()
        if isinstance(index, slice):
            return [self[i] for i in range(*index.indices(len(self._where)))]
        where = self._where[index]   # IndexError and TypeError as a list raises them
        if where < 0:
            return self._objects[~where]
        i = where * _ROW
        start_at = self._rows[i + 2]
        start = self._point(where - 1, self._rows[i - _ROW + 1] + 1) if start_at == _AT_END_BEFORE \
            else self._point(where, start_at)
        return self._make(where, start, None)

    def __iter__(self) -> Iterator:
        if self._pending:
            self.flush()
        objects = self._objects
        rows = self._rows
        point, make = self._point, self._make
        end_before = None   # the end dict of the row before: the start of the next one
        src = None          # the Source of the row before
        last = -1           # its index in the sources
        for where in self._where:
            if where < 0:
                yield objects[~where]
                continue
            i = where * _ROW
            start_at = rows[i + 2]
            s = rows[i + 4]
            record = make(where, end_before if start_at == _AT_END_BEFORE else point(where, start_at),
                          src if s == last else None)
            end_before = record.end
            src = record.src
            last = s
            yield record

    def _point(self, row: int, at: int) -> dict:
        """The point of ``row``'s axes whose coordinates begin at ``at`` in the values."""
        axes = self._contexts[self._rows[row * _ROW]][7]
        return dict(zip(axes, self._values[at:at + len(axes)]))  # noqa: B905 (as many as the axes)

    def _make(self, row: int, start: dict, src: Source | None) -> Line:
        """The record of ``row`` from ``start``, with ``src`` when given (the row's Source, else made)."""
        i = row * _ROW
        context, at, _start, part_at, s = self._rows[i:i + _ROW]
        kind, mode, has_feed, file, dyn, frame, joins, axes = self._contexts[context]
        values = self._values
        n = len(axes)
        end = dict(zip(axes, values[at + 1:at + 1 + n]))  # noqa: B905 (as many as the axes)
        part = end if part_at == _IS_END else dict(zip(axes, values[part_at:part_at + n]))  # noqa: B905
        if src is None:
            begin = self._text_end[s - 1] if s else 0
            src = _new_source(file, self._lines[s], self._text[begin:self._text_end[s]].decode("utf-8",
                                                                                              "surrogatepass"))
        return _new_line(kind, start, end, part, values[at] if has_feed else None, mode, src, dyn, frame, joins)

    # ------------------------------------------------------------------------------- as a list
    def __eq__(self, other: object) -> bool:
        if isinstance(other, (Moves, list, tuple)):
            return len(self) == len(other) and all(a == b for a, b in zip(self, other))  # noqa: B905 (same len)
        return NotImplemented

    __hash__ = None   # type: ignore[assignment]   # it grows, as a list does

    def __repr__(self) -> str:
        return f"Moves({list(self)!r})"

    def __reduce__(self):
        return Moves, (list(self),)


def _same_axes(point, axes: tuple) -> tuple | None:
    """The coordinates of ``point`` when it is a dict of floats over ``axes`` in that order, else None."""
    if type(point) is not dict or tuple(point) != axes:
        return None
    values = tuple(point.values())
    for v in values:
        if type(v) is not float:
            return None
    return values
