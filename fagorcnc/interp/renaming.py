"""``#RENAME AX`` and ``#RENAME SP``: one statement shape for the channel's axes (seed 002 L14943-L15047)
and its spindles (L15144-L15233).

``#RENAME AX [X, X1] [..]`` / ``#RENAME SP [S, S1] [..]``: each pair's first element takes the second name,
and an element of the channel that already has that name takes the first (the swap, L14947, L15148-L15149).
``#RENAME AX OFF`` / ``#RENAME SP OFF <[X, ..]>``: the own names back, of all or of those listed (L15030,
L15214-L15233).  The configuration object (``ChannelAxes`` or ``ChannelSpindles``) holds ``names`` (element
-> new name) and ``by_name`` (name in use -> element); the caller's ``renamed`` re-indexes it and refuses two
elements under one name.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass

from ..syntax.ast import ItemList, Keyed, Name, Num
from .expressions import InterpError, whole


def item_name(item) -> str | None:
    """The text of an axis or spindle name item: ``X`` or ``S`` (a Name), ``X1`` or ``S1`` (read as X with the
    value 1), ``?2`` (a Name)."""
    t = type(item)
    if t is Name:
        return item.name
    if t is Keyed and type(item.value) is Num and whole(item.value.value) is not None and len(item.name) == 1:
        return f"{item.name}{int(item.value.value)}"
    return None


@dataclass(frozen=True)
class Renaming:
    """What differs between ``#RENAME AX`` and ``#RENAME SP``."""

    keyword: str        # "AX" or "SP"
    noun: str           # "axis" or "spindle"
    nouns: str          # "axes" or "spindles"
    code: str           # the statement's error code
    pattern: re.Pattern  # a valid new name
    name_rule: str      # the naming rule, for the message
    examples: str       # pairs, for the message: "[X, X1] [Z, V2]"
    off_example: str    # "[X]"


def rename(node, cfg, how: Renaming, renamed: Callable[[object, int], None]) -> None:
    """Run ``#RENAME <AX|SP> ...`` on ``cfg`` (see the module's text)."""
    kw, code = how.keyword, how.code
    args = list(node.args)
    first = args[0] if args else None
    if type(first) is Name and first.name == kw and len(args) == 2 and type(args[1]) in (Name, Keyed) \
            and args[1].name == "OFF":
        off = args[1]
        if type(off) is Name:
            cfg.names.clear()
        elif type(off.value) is not ItemList:
            raise InterpError(code, f"#RENAME {kw} OFF takes the {how.nouns} in brackets: #RENAME {kw} OFF "
                              f"{how.off_example}", off.col)
        else:
            for seq in off.value.items:
                item = seq[0] if len(seq) == 1 else None
                col = getattr(item, "col", off.col)
                name = item_name(item) if item is not None else None
                element = cfg.by_name.get(name) if name else None
                if element is None:
                    raise InterpError(code, f"#RENAME {kw} OFF: there is no {how.noun} {name or '?'} in the "
                                      "channel", col)
                cfg.names.pop(element, None)
        renamed(cfg, node.col)
        return
    if type(first) is not Keyed or first.name != kw or type(first.value) is not ItemList:
        raise InterpError(code, f"#RENAME {kw} takes pairs in brackets: #RENAME {kw} {how.examples}", node.col)
    for pair in [first.value, *args[1:]]:
        if type(pair) is not ItemList or len(pair.items) != 2 or any(len(s) != 1 for s in pair.items):
            raise InterpError(code, f"#RENAME {kw}: each pair is [{how.noun}, new name]: #RENAME {kw} "
                              f"{how.examples.split('] ')[0]}]", getattr(pair, "col", node.col))
        (a,), (b,) = pair.items
        old, new = item_name(a), item_name(b)
        if old is None or not how.pattern.fullmatch(old):
            raise InterpError(code, f"#RENAME {kw}: expected {_article(how.noun)} of the channel; {how.name_rule}",
                              a.col)
        if new is None or not how.pattern.fullmatch(new):
            raise InterpError(code, f"#RENAME {kw}: the new name: {how.name_rule}", b.col)
        element = cfg.by_name.get(old)
        if element is None:
            raise InterpError(code, f"#RENAME {kw}: there is no {how.noun} {old} in the channel", a.col)
        other = cfg.by_name.get(new)
        if other is not None and other != element:
            cfg.names[other] = old   # the swap (L14947, L15148-L15149)
        cfg.names[element] = new
        renamed(cfg, node.col)


def _article(noun: str) -> str:
    return f"an {noun}" if noun[0] in "aeiou" else f"a {noun}"
