"""Front end: Fagor 8060/8065 source text -> typed AST (:mod:`fagorcnc.syntax.ast`)."""

from .ast import Block, Program, ProgramHeader, Routine, SubroutineHeader
from .parser import LineParser, grammar_path
from .reader import iter_lines, line_parser, parse_file, parse_text, read_source, source_encoding

__all__ = ["Block", "LineParser", "Program", "ProgramHeader", "Routine", "SubroutineHeader",
           "grammar_path", "iter_lines", "line_parser", "parse_file", "parse_text", "read_source", "source_encoding"]
