"""Arithmetic parameters: local, global and common (seed 002 L1861-L1911).

* local P0..P99 (configured range, usually P0..P25): one group per
  subroutine nesting level that opens a parameter level (#PCALL, #MCALL,
  G180..., #CALL), at most 7 levels (seed 002 L10503-L10507);
* global P100..P9999 (usually P100..P299): one group for the channel, kept
  across subroutines and programs;
* common P10000..P19999 (usually P10000..P10999): shared by all channels.

A number outside the configured ranges is an error; P20000 and above always
(L1882-L1903).  Reading a parameter never assigned is an error (spec 01
E19); ``EXIST[Pn]`` tells whether it has a value.
"""

from __future__ import annotations

from ..config.machine import Machine
from .expressions import InterpError


class Parameters:
    """The parameter store of one channel."""

    def __init__(self, machine: Machine, global_values: dict[int, float] | None = None,
                 common_values: dict[int, float] | None = None) -> None:
        self.local_range = machine.local_params
        self.global_range = machine.global_params
        self.common_range = machine.common_params
        self.max_levels = machine.limits.max_parameter_levels
        self.levels: list[dict[int, float]] = [{}]
        self.globals: dict[int, float] = dict(global_values or {})
        self.common: dict[int, float] = dict(common_values or {})

    def _store(self, n: int, col: int) -> dict[int, float]:
        lo, hi = self.local_range
        if lo <= n <= hi:
            return self.levels[-1]
        lo, hi = self.global_range
        if lo <= n <= hi:
            return self.globals
        lo, hi = self.common_range
        if lo <= n <= hi:
            return self.common
        ranges = (f"P{self.local_range[0]}..P{self.local_range[1]}, P{self.global_range[0]}..P{self.global_range[1]}"
                  f", P{self.common_range[0]}..P{self.common_range[1]}")
        raise InterpError("INT041", f"P{n} is outside the parameter ranges of this machine ({ranges})", col)

    def get(self, n: int, col: int = 1) -> float:
        store = self._store(n, col)
        try:
            return store[n]
        except KeyError:
            raise InterpError("INT040", f"P{n} has no value yet (use EXIST[P{n}] to test)", col) from None

    def set(self, n: int, value: float, col: int = 1) -> None:
        self._store(n, col)[n] = value

    def exists(self, n: int) -> bool:
        try:
            return n in self._store(n, 1)
        except InterpError:
            return False

    def push(self, values: dict[int, float], col: int = 1) -> None:
        """Open a new local level initialised with ``values`` (a #PCALL's arguments)."""
        # spec 05 §1.2 (A4): the main program's set is one of the 7 levels (L10220)
        if len(self.levels) >= self.max_levels:
            raise InterpError("INT042", f"more than {self.max_levels} local parameter levels", col)
        self.levels.append(dict(values))

    def pop(self) -> None:
        if len(self.levels) > 1:
            self.levels.pop()

    @property
    def level(self) -> int:
        """Current local parameter level (0 = main program)."""
        return len(self.levels) - 1
