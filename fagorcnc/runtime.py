"""Process settings for long dry runs.

A dry run allocates a few container objects per block (records, spans,
segments) that die young and almost never form reference cycles: reference
counting frees them.  CPython's cyclic collector still runs every 700 net
allocations and, every tenth or hundredth run, walks everything that is
alive — on a long program that is about a sixth of the run time for nothing.

The planner works on arrays of a few hundred kilobytes to a few megabytes (the
corner curves of a look-ahead window at once), made and freed many times.
glibc's allocator gives memory that large back to the system as soon as it is
freed, so the next array of the size faults every page in again (on a CAM
contour with arcs, a fifth of the planning time was the system zeroing pages):
:func:`keep_freed_memory` has it keep that memory for reuse instead.

The ``fagorcnc`` process imports some sixty thousand objects the collector tracks (modules, classes,
functions), alive until it exits, which older-generation collections and the collection at exit walk
again and again: :func:`spare_collector` moves them out of its reach.
"""

from __future__ import annotations

import ctypes
import gc
import platform
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


#: glibc: blocks up to this size come from the heap (reused once freed) rather than from a mapping
#: of their own, made and returned to the system each time (default: 128 kB, rising to the largest
#: block freed).
MMAP_THRESHOLD = 4 << 20
#: glibc: free memory at the top of the heap kept for reuse, at most (default: twice the above).
TRIM_THRESHOLD = 16 << 20
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3   # mallopt() parameters (malloc.h)
_kept: bool | None = None


def keep_freed_memory() -> bool:
    """Have the C allocator keep freed memory (up to :data:`TRIM_THRESHOLD`) for the next
    allocations instead of returning it to the system at once: a process-wide setting, made once,
    for command-line runs (the ``fagorcnc`` command) and benchmarks; a program embedding the library
    decides for itself.  True where it was set (glibc); elsewhere nothing changes."""
    global _kept
    with _lock:
        if _kept is None:
            _kept = False
            if platform.libc_ver()[0] == "glibc":
                try:
                    mallopt = ctypes.CDLL(None).mallopt
                except (OSError, AttributeError):
                    return False
                mallopt.argtypes = [ctypes.c_int, ctypes.c_int]
                mallopt.restype = ctypes.c_int
                _kept = bool(mallopt(_M_MMAP_THRESHOLD, MMAP_THRESHOLD)) and bool(
                    mallopt(_M_TRIM_THRESHOLD, TRIM_THRESHOLD))
        return _kept


def spare_collector() -> None:
    """Move every object the cyclic collector tracks now to its permanent generation (:func:`gc.freeze`):
    no later collection walks them (the collection at exit included), and none of them is freed by it.
    For the ``fagorcnc`` process alone (:func:`fagorcnc.cli.command`), after its imports: their modules,
    classes and functions live until it exits anyway.  In a ``fagorcnc check`` of an empty program the
    collector's walks of them were 4 % of the instructions; a program embedding the library decides for
    itself."""
    gc.freeze()
