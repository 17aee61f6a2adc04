"""Evaluation of expressions (seed 002 L1927-L2157).

Angles are degrees.  Domain errors are :class:`InterpError` with the
column of the offending node; the interpreter turns them into diagnostics on
the block.  Choices where the manual is silent follow spec 01 §11:
``a MOD b`` takes the sign of the dividend (C ``fmod``); bitwise operators
work on 32-bit unsigned integers after dropping the fractional part; INT
truncates toward zero, ROUND rounds halves away from zero, FUP is the
ceiling; ARG[x, y] = atan2(y, x) in [0, 360).
"""

from __future__ import annotations

import math
from collections.abc import Callable

from ..syntax.ast import Binary, Call, Num, Param, Unary, Var


class InterpError(Exception):
    """An error of the program found while interpreting a block."""

    def __init__(self, code: str, message: str, col: int = 1) -> None:
        super().__init__(message)
        self.code, self.message, self.col = code, message, max(int(col or 1), 1)


def whole(v: float) -> int | None:
    """``v`` as an int when it is a finite whole number of sane size, else None."""
    if not math.isfinite(v) or abs(v) > 1e15 or v != math.floor(v):
        return None
    return int(v)


def _int32(x: float, col: int) -> int:
    if not math.isfinite(x) or x < 0 or x >= 4294967296:
        raise InterpError("INT031", f"bitwise operators take integers 0..4294967295, not {x:g}", col)
    return int(x)


def _check(value: float, col: int) -> float:
    if math.isfinite(value):
        return value
    raise InterpError("INT030", "the result is not a finite number (overflow)", col)


def _tan(a: float, col: int) -> float:
    # seed 002 L2015: TAN of +-90, 270... is an error
    if math.isclose(math.fmod(abs(a), 180.0), 90.0, abs_tol=1e-12):
        raise InterpError("INT032", f"TAN[{a:g}] is not defined (odd multiple of 90 degrees)", col)
    return math.tan(math.radians(a))


def _asin_acos(f: Callable[[float], float], name: str) -> Callable[[float, int], float]:
    def g(x: float, col: int) -> float:
        if not -1.0 <= x <= 1.0:  # seed 002 L2017
            raise InterpError("INT032", f"{name}[{x:g}]: the argument must be between -1 and 1", col)
        return math.degrees(f(x))
    return g


def _log(f: Callable[[float], float], name: str) -> Callable[[float, int], float]:
    def g(x: float, col: int) -> float:
        if x <= 0:  # seed 002 L2025
            raise InterpError("INT032", f"{name}[{x:g}]: the argument must be greater than 0", col)
        return f(x)
    return g


def _sqrt(x: float, col: int) -> float:
    if x < 0:  # seed 002 L2027
        raise InterpError("INT032", f"SQRT[{x:g}]: the argument must not be negative", col)
    return math.sqrt(x)


def _round(x: float, col: int) -> float:
    return float(math.floor(abs(x) + 0.5)) * (1.0 if x >= 0 else -1.0)


def _exp(x: float, col: int) -> float:
    try:
        return math.exp(x)
    except OverflowError:
        raise InterpError("INT030", f"EXP[{x:g}] is too large", col) from None


def _dexp(x: float, col: int) -> float:
    try:
        return math.pow(10.0, x)
    except OverflowError:
        raise InterpError("INT030", f"DEXP[{x:g}] is too large", col) from None


FUNCTIONS: dict[str, Callable[[float, int], float]] = {
    "SIN": lambda a, c: math.sin(math.radians(a)),
    "COS": lambda a, c: math.cos(math.radians(a)),
    "TAN": _tan,
    "ASIN": _asin_acos(math.asin, "ASIN"),
    "ACOS": _asin_acos(math.acos, "ACOS"),
    "ATAN": lambda x, c: math.degrees(math.atan(x)),
    "ABS": lambda x, c: abs(x),
    "SQR": lambda x, c: x * x,
    "SQRT": _sqrt,
    "LOG": _log(math.log10, "LOG"),
    "LN": _log(math.log, "LN"),
    "EXP": _exp,
    "DEXP": _dexp,
    "INT": lambda x, c: float(math.trunc(x)),
    "FRACT": lambda x, c: x - math.trunc(x),
    "ROUND": _round,
    "FUP": lambda x, c: float(math.ceil(x)),
    "INV": lambda x, c: float(0xFFFFFFFF - _int32(x, c)),
}


def _arg(x: float, y: float, col: int) -> float:
    if x == 0 and y == 0:
        raise InterpError("INT032", "ARG[0,0] has no angle", col)
    return math.degrees(math.atan2(y, x)) % 360.0


def _binary(op: str, a: float, b: float, col: int) -> float:
    if op == "+":
        return a + b
    if op == "-":
        return a - b
    if op == "*":
        return a * b
    if op == "/":
        if b == 0:
            raise InterpError("INT033", "division by zero", col)
        return a / b
    if op == "**":
        try:
            r = math.pow(a, b)
        except (ValueError, ZeroDivisionError):
            raise InterpError("INT032", f"{a:g} ** {b:g} is not a real number", col) from None
        except OverflowError:
            raise InterpError("INT030", f"{a:g} ** {b:g} is too large", col) from None
        return r
    if op == "MOD":
        if b == 0:
            raise InterpError("INT033", "MOD 0 (division by zero)", col)
        return math.fmod(a, b)
    if op == "==":
        return 1.0 if a == b else 0.0
    if op == "!=":
        return 1.0 if a != b else 0.0
    if op == ">":
        return 1.0 if a > b else 0.0
    if op == "<":
        return 1.0 if a < b else 0.0
    if op == ">=":
        return 1.0 if a >= b else 0.0
    if op == "<=":
        return 1.0 if a <= b else 0.0
    x, y = _int32(a, col), _int32(b, col)
    if op == "&":
        return float(x & y)
    if op == "|":
        return float(x | y)
    return float(x ^ y)  # "^"


class Evaluator:
    """Evaluates expression nodes against parameter and variable stores.

    ``params`` needs ``get(index, col)`` and ``exists(index)``; ``variables``
    needs ``get(name, index_values, col)`` and ``exists(name, index_values)``.
    """

    def __init__(self, params, variables) -> None:
        self.params = params
        self.variables = variables

    def value(self, node) -> float:
        """The number a word value or expression stands for."""
        t = type(node)
        if t is float:
            if node - node != 0.0:   # inf or nan from a literal too large for a double
                raise InterpError("INT030", "this number is too large", 1)
            return node
        if t is Num:
            v = node.value
            if v - v != 0.0:   # inf or nan: a literal beyond the range of a double
                raise InterpError("INT030", "this number is too large", node.col)
            return v
        if t is Param:
            return self.params.get(self.index(node), node.col)
        if t is Binary:
            a = self.value(node.left)
            b = self.value(node.right)
            try:
                return _check(_binary(node.op, a, b, node.col), node.col)
            except (ValueError, OverflowError):
                raise InterpError("INT030", f"{a:g} {node.op} {b:g} cannot be computed", node.col) from None
        if t is Unary:
            return -self.value(node.operand)
        if t is Var:
            return self.variables.get(node.name, tuple(self.value(i) for i in node.index), node.col)
        if t is Call:
            if node.func == "EXIST":  # seed 002 L2031: the argument is not evaluated
                return 1.0 if self.exists(node.args[0]) else 0.0
            if node.func == "ARG":
                return _arg(self.value(node.args[0]), self.value(node.args[1]), node.col)
            x = self.value(node.args[0])
            try:
                return _check(FUNCTIONS[node.func](x, node.col), node.col)
            except (ValueError, OverflowError):
                raise InterpError("INT032", f"{node.func}[{x:g}] cannot be computed", node.col) from None
        if t is int:
            return float(node)
        raise InterpError("INT034", "this is not a number", getattr(node, "col", 1))

    def index(self, node: Param) -> int:
        """The parameter number of ``P12`` or ``P[expr]`` (integer, E20)."""
        if type(node.index) is int:
            return node.index
        v = self.value(node.index)
        if not math.isfinite(v) or abs(v) > 1e9:
            raise InterpError("INT041", f"P[{v:g}] does not exist", node.col)
        n = round(v)
        if abs(v - n) > 1e-9:
            raise InterpError("INT035", f"parameter index P[{v:g}] is not an integer", node.col)
        return int(n)

    def exists(self, node) -> bool:
        if type(node) is Param:
            return self.params.exists(self.index(node))
        return self.variables.exists(node.name, tuple(self.value(i) for i in node.index))

    def integer(self, node, what: str, col: int, low: float = 0, high: float = 4294967295,
                floor: bool = False) -> int:
        """An integral value in ``[low, high]`` (N, G, M, H, T, D, NR; spec 01 E9/E20).

        With ``floor`` a fractional value is rounded down, as the manual says for
        T, M and H (seed 002 L4678-L4681, spec 02 §19-20); otherwise it is an error.
        """
        v = self.value(node)
        if not math.isfinite(v) or abs(v) > 1e15:
            raise InterpError("INT037", f"{what}{v:g} is out of range {low:g}..{high:g}", col)
        n = math.floor(v + 1e-9) if floor else round(v)
        if not floor and abs(v - n) > 1e-9:
            raise InterpError("INT036", f"{what} must be a whole number, not {v:g}", col)
        if not low <= n <= high:
            raise InterpError("INT037", f"{what}{n} is out of range {low:g}..{high:g}", col)
        return int(n)
