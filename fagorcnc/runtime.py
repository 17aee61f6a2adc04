"""Process settings for long dry runs.

A dry run allocates a few container objects per block (records, spans,
segments) that die young and almost never form reference cycles: reference
counting frees them.  CPython's cyclic collector still runs every 700 net
allocations and, every tenth or hundredth run, walks everything that is
alive — on a long program that is about a sixth of the run time for nothing.
"""

from __future__ import annotations

import gc
import threading
from collections.abc import Iterator
from contextlib import contextmanager

#: Net allocations between young-generation collections during a dry run (CPython: 700).
YOUNG_THRESHOLD = 50_000
#: Young collections per middle one, middle ones per full one (CPython: 10, 10).
OLDER_THRESHOLDS = (20, 100)

_lock = threading.Lock()
_depth = 0
_saved: tuple[int, int, int] | None = None


@contextmanager
def fewer_collections() -> Iterator[None]:
    """Run the body with the cyclic collector triggered less often (never more often than the
    process had it); the previous thresholds come back when the outermost body ends.  Cyclic
    garbage is still collected, only in larger batches, so memory stays bounded."""
    global _depth, _saved
    with _lock:
        if _depth == 0:
            _saved = gc.get_threshold()
            young, middle, old = _saved
            if young > 0:   # 0: the process turned automatic collection off; leave it so
                gc.set_threshold(max(young, YOUNG_THRESHOLD), max(middle, OLDER_THRESHOLDS[0]),
                                 max(old, OLDER_THRESHOLDS[1]))
        _depth += 1
    try:
        yield
    finally:
        with _lock:
            _depth -= 1
            if _depth == 0 and _saved is not None:
                gc.set_threshold(*_saved)
                _saved = None
