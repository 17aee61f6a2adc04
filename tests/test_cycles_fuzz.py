"""Bad canned-cycle input never crashes: random cycle blocks with random parameter values give
diagnostics with published codes, never an exception (bounded; a longer run is marked slow)."""

from __future__ import annotations

import random

import pytest

import fagorcnc
from fagorcnc.diagnostics import CODES
from fagorcnc.interp.cycles.runner import LETTERS

VALUES = [0, 1, -1, 2.5, -2.5, 10, -10, 0.001, 1e6, -1e6, 3, 0.5, 90, -90, 360, 1e12]
FOLLOWERS = ["X10", "Y5 NR2", "G91 X3 NR0", "X5 Z3", "G02 X5 I3", "V.C.I=-3", "V.C.J=0", "G160 X10 I5",
             "G163 X5 Y0 K3 C2 F100", "G80", "#TOOL AX [Z+]", "G41 X1", "G73 Q30", "G11", "M30"]
MACHINE = {"tools": {"1": {"1": {"radius": 3.0}}}}


def _program(rng: random.Random) -> str:
    lines = ["T1 D1 M6", rng.choice(["S1000 M3", "S1000 M4", "", "S500 M5"]), rng.choice(["G17", "G18", "G19"]),
             rng.choice(["G90", "G91", "G70 G90", "G95"]), "G00 X0 Y0 Z20"]
    for _ in range(rng.randint(1, 3)):
        code = rng.choice(list(LETTERS))
        letters = rng.sample(LETTERS[code], rng.randint(0, len(LETTERS[code])))
        words = " ".join(f"{x}{rng.choice(VALUES)}" for x in letters)
        lines.append(f"G{rng.choice([98, 99])} G{code} {words}{rng.choice(['', ' F100', ' F0', ' X5 Y5 F100'])}")
        lines += [rng.choice(FOLLOWERS) for _ in range(rng.randint(0, 2))]
    return "\n".join([*lines, "M30"]) + "\n"


def _check(seed: int) -> None:
    text = _program(random.Random(seed))
    result = fagorcnc.simulate(text, machine=MACHINE)   # must not raise
    assert all(d.code in CODES for d in result.diagnostics), (text, [str(d) for d in result.diagnostics])


@pytest.mark.parametrize("chunk", range(3))
def test_random_cycle_blocks_never_crash(chunk):
    for seed in range(chunk * 30, chunk * 30 + 30):
        _check(seed)


@pytest.mark.slow
def test_random_cycle_blocks_never_crash_long():
    for seed in range(1000, 1800):
        _check(seed)
