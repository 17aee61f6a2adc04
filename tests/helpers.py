"""Small helpers shared by the front-end tests."""

from __future__ import annotations

from fagorcnc.syntax import line_parser, parse_text
from fagorcnc.syntax.ast import Word


def block(text: str):
    """The block of one line (line-level syntax only); fails on any diagnostic."""
    node, diags = line_parser().parse(text, 1)
    assert not diags, [str(d) for d in diags]
    assert node is not None
    return node


def items(text: str) -> tuple:
    """The items of the single block of ``text``."""
    return block(text).items


def words(text: str) -> list:
    """``(address, value)`` of each word of the single block of ``text``."""
    return [(w.address, w.value) for w in items(text) if type(w) is Word]


def codes(text: str) -> list:
    """``(line, col, code)`` of every diagnostic of ``text``."""
    return [(d.line, d.col, d.code) for d in parse_text(text).diagnostics]


def error_codes(text: str) -> list:
    """Codes of the error diagnostics of ``text``."""
    return [d.code for d in parse_text(text).diagnostics if d.is_error]


def edit_text(draw, text: str, chars) -> str:
    """One random edit of ``text`` (hypothesis ``draw``): insert, delete, replace or duplicate."""
    from hypothesis import strategies as st

    op = draw(st.sampled_from(["insert", "delete", "replace", "duplicate"]))
    pos = draw(st.integers(0, len(text)))
    if op == "insert":
        return text[:pos] + draw(chars) + text[pos:]
    if op == "delete":
        return text[:pos] + text[pos + draw(st.integers(1, 4)):]
    if op == "replace":
        return text[:pos] + draw(chars) + text[pos + 1:]
    end = min(len(text), pos + draw(st.integers(1, 12)))  # duplicate a slice
    return text[:end] + text[pos:end] + text[end:]
