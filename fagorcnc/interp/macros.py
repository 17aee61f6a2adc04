"""Running macros (seed 002 ch. 21.1.16): ``#DEF``, ``#INIT MACROTAB`` and the blocks that use them.

The table is the channel's, kept for the whole run (the CNC keeps it from power-on until
``#INIT MACROTAB``, L16121-L16125, so a subroutine sees the macros its caller defined).  The
text rules and the expansion itself are :mod:`fagorcnc.syntax.macros`.
"""

from __future__ import annotations

from ..syntax.ast import Assignment, Block, Definition, ItemList, Name
from ..syntax.macros import MAX_MACROS, MacroError, MacroUse, check_definition, expand
from ..syntax.reader import line_parser
from .expressions import InterpError


def _definitions(node) -> list[Definition]:
    found = []
    for arg in node.args:
        items = [x for seq in arg.items for x in seq] if type(arg) is ItemList else [arg]
        for item in items:
            if type(item) is not Definition:
                raise InterpError("MAC008", '#DEF takes "NAME"="block text" pairs: #DEF "START"="SP1 M3 M41" '
                                  "(L16140)", getattr(item, "col", node.col))
            found.append(item)
    if not found:
        raise InterpError("MAC008", '#DEF needs at least one "NAME"="block text" (L16140)', node.col)
    return found


def define_statement(interp, node) -> None:
    """``#DEF "NAME"="text" ["NAME2"="text2" ...]``: store the macros (L16132-L16145).

    A name already in the table takes the new text and no new place (the manual does not say;
    spec 06 §4.16 recommends it); a 51st name is an error (L16127-L16131)."""
    table = interp.macros
    for d in _definitions(node):
        try:
            check_definition(d.name, d.text, d.col)
        except MacroError as exc:
            raise InterpError(exc.code, exc.message, exc.col) from None
        if d.name not in table and len(table) >= MAX_MACROS:
            raise InterpError("MAC002", f"macro '{d.name}': the table already holds {MAX_MACROS} macros, the most "
                              "the CNC keeps (L16127); #INIT MACROTAB empties it", d.col)
        table[d.name] = d.text


def init_statement(interp, node) -> None:
    """``#INIT MACROTAB``: empty the table (L16186-L16188)."""
    if len(node.args) != 1 or type(node.args[0]) is not Name:
        raise InterpError("MAC008", "#INIT MACROTAB takes nothing more", node.col)
    interp.macros.clear()


def _split_assignments(text: str, line: int, file: str) -> tuple[Block, Block] | None:
    """``P1=800 SP1 M3 M41 F450`` as the manual's macro example writes it (L16160-L16162: it "is
    ``S800 M3 M41``"): the assignments first, then the ISO block, when the line reads so."""
    parse = line_parser().parse
    for i, ch in enumerate(text):
        if ch not in " \t" or i == 0:
            continue
        head, head_diags = parse(text[:i], line, file)
        if head is None or head_diags or type(head) is not Block:
            continue
        if not head.items or any(type(x) is not Assignment for x in head.items):
            continue
        tail, tail_diags = parse(" " * i + text[i:], line, file)   # the same columns as in the line
        if tail is not None and not tail_diags and type(tail) is Block and tail.items and all(
                type(x) is not Assignment for x in tail.items):
            return head, tail
    return None


def expanded_blocks(interp, block: Block, use: MacroUse) -> list[Block]:
    """The block as it reads with its macros replaced by their text (L16115-L16118), parsed: one
    block, or the assignments and the ISO block of the manual's ``P1=800 "START" F450``."""
    try:
        text = expand(use.text, interp.macros, 1)
    except MacroError as exc:
        raise InterpError(exc.code, exc.message, exc.col) from None
    file = interp.frames[-1].program.file if interp.frames else interp.program.file
    node, diags = line_parser().parse(text, block.line, file)
    problem = next((d for d in diags if d.is_error), None)
    if problem is not None and (split := _split_assignments(text, block.line, file)) is not None:
        return [block._replace(text=text, items=b.items) for b in split]
    if problem is None and node is not None and type(node) is not Block:
        raise InterpError("MAC006", f"with its macros the block reads '{text.strip()}', which is not a block",
                          use.col)
    if problem is not None:
        raise InterpError("MAC006", f"with its macros the block reads '{text.strip()}': {problem.message}",
                          use.col)
    if node is None:
        return []
    if any(type(i) is MacroUse for i in node.items):
        raise InterpError("MAC006", f"with its macros the block reads '{text.strip()}', which still names a "
                          "macro", use.col)
    return [block._replace(text=text, items=node.items)]
