"""Interpreter: runs a parsed program and yields canonical motion records."""

from .interpreter import Interpreter
from .records import Arc, Aux, Dwell, Line, Source

__all__ = ["Arc", "Aux", "Dwell", "Interpreter", "Line", "Source"]
