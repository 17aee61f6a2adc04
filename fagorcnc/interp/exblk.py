"""``#EXBLK [block <, channel>]``: run one block in a channel (seed 002 ch. 13.2, L11277-L11307).

Written in a program without a channel, or with the program's own channel (1 offline), the
block runs here, as if it stood in the program (L11294-L11296); its text is read from the
statement (``#EXBLK [G01 X100 F550]``) and parsed like any block.  A block for another channel
is reported (INT119): fagorcnc runs one channel.
"""

from __future__ import annotations

from ..syntax.ast import Block, ItemList
from ..syntax.reader import line_parser
from .expressions import InterpError


def _bracket(text: str, start: int) -> tuple[int, int, int | None] | None:
    """(open, close, last top-level comma) of the bracket list opening at or after ``start``."""
    i = text.find("[", start)
    if i < 0:
        return None
    depth, comma = 0, None
    for j in range(i, len(text)):
        ch = text[j]
        if ch == "[":
            depth += 1
        elif ch == "]":
            depth -= 1
            if depth == 0:
                return i, j, comma
        elif ch == "," and depth == 1:
            comma = j
    return None


def exblk_block(interp, node, block: Block) -> Block | None:
    """The block ``#EXBLK`` runs in this channel, or ``None`` after reporting a block for another one."""
    arg = node.args[0] if len(node.args) == 1 else None
    found = _bracket(block.text, node.col - 1) if type(arg) is ItemList else None
    if found is None or not arg.items or not arg.items[0]:
        raise InterpError("INT071", "#EXBLK takes a block in brackets: #EXBLK [G01 X100 F550] or "
                          "#EXBLK [G01 X100 F550, 2] (L11291)", node.col)
    open_at, close_at, comma = found
    channel = 1
    if len(arg.items) > 1:
        last = arg.items[-1]
        if len(last) != 1 or len(arg.items) > 2:
            raise InterpError("INT071", "#EXBLK [block, channel]: the channel after the last comma is one number "
                              "(L11291)", node.col)
        channel = interp.evaluator.integer(last[0], "#EXBLK channel ", node.col, 1, 4)
    if channel != 1:
        interp.message("INT119", "warning", f"#EXBLK: the block runs in channel {channel}; fagorcnc runs one "
                       "channel, so it is not simulated", node.col)
        return None
    inner = block.text[open_at + 1:comma if comma is not None else close_at]
    file = interp.frames[-1].program.file if interp.frames else interp.program.file
    parsed, diags = line_parser().parse(" " * (open_at + 1) + inner, block.line, file)   # columns as in the line
    problem = next((d for d in diags if d.is_error), None)
    if problem is not None:
        raise InterpError(problem.code, f"#EXBLK block: {problem.message}", problem.col)
    if parsed is None:
        return None
    if type(parsed) is not Block or any(type(i).__name__ in ("Flow", "MacroUse") for i in parsed.items):
        raise InterpError("INT071", "#EXBLK runs one ISO block or # statement, not a program header or a $ "
                          "instruction", node.col)
    return block._replace(items=parsed.items)
