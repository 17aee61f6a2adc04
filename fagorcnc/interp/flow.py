"""Flow control of the interpreter: the $ instructions ($IF, $FOR, $WHILE, $DO, $SWITCH, $GOTO,
$BREAK, $CONTINUE; seed 002 ch. 21.2) and the block repetition #RPT (ch. 21.1.17).  A mixin of
:class:`~fagorcnc.interp.interpreter.Interpreter`."""

from __future__ import annotations

from ..syntax.ast import Block, Flow, Param, Repeat
from .expressions import InterpError

#: Rounding a $FOR end comparison allows, as a share of the step (see the $ENDFOR step).
FOR_SLACK = 1e-9
#: #RPT ranges one inside another, at most (seed 002 L16216).
RPT_LEVELS = 20


class _Stop(Exception):  # noqa: N818 - control flow, not an error
    """End of the run (M02/M30, #ERROR, end of the main program)."""


class _Links:
    """``links[i]``: the structure link of block ``i`` (reads ahead on a stream)."""

    __slots__ = ("source",)

    def __init__(self, source) -> None:
        self.source = source

    def __getitem__(self, i: int) -> int:
        try:
            return self.source.link(i)
        except KeyError:
            # a streamed program whose structure is unbalanced: the parser has
            # reported it (STR005/STR006) and nothing more is executed
            raise _Stop from None


class FlowMixin:
    """:meth:`_flow` (the $ instructions) and :meth:`_repeat` (#RPT), on the interpreter's frames."""

    # ------------------------------------------------------------------ flow control
    def _flow(self, node: Flow, block: Block) -> None:
        frame = self.frames[-1]
        source = frame.source
        here = frame.pc - 1
        links = _Links(source)
        kw = node.keyword
        ev = self.evaluator

        def kw_at(i: int) -> str:
            return source.get(i).items[-1].keyword

        if kw == "IF":
            cond = ev.value(node.args[0]) != 0
            if len(node.args) == 2:
                if cond:
                    self._goto(node.args[1], frame)
                return
            if cond:
                return
            i = links[here]
            while True:
                k = kw_at(i)
                if k == "ELSEIF":
                    if ev.value(source.get(i).items[-1].args[0]) != 0:
                        frame.pc = i + 1
                        return
                    i = links[i]
                elif k == "ELSE":
                    frame.pc = i + 1
                    return
                else:  # ENDIF
                    frame.pc = i + 1
                    return
        if kw in ("ELSEIF", "ELSE", "CASE", "DEFAULT"):
            # reached after a branch ran: skip to the end of the structure
            i = links[here]
            while kw_at(i) not in ("ENDIF", "ENDSWITCH"):
                i = links[i]
            frame.pc = i + 1
            return
        if kw in ("ENDIF", "ENDSWITCH"):
            return
        if kw == "SWITCH":
            value = ev.value(node.args[0])
            i = links[here]
            while True:
                k = kw_at(i)
                if k == "CASE" and ev.value(source.get(i).items[-1].args[0]) == value:
                    frame.pc = i + 1
                    return
                if k == "DEFAULT" or k == "ENDSWITCH":
                    frame.pc = i + 1
                    return
                i = links[i]
        if kw == "FOR":
            target, start, end, step = node.args
            s = ev.value(step)
            if s == 0:
                raise InterpError("INT072", "$FOR step must not be 0", node.col)
            e = ev.value(end)
            v = ev.value(start)
            self._set_target(target, v)
            frame.loops[here] = [e, s, 0]
            if (s > 0 and v > e) or (s < 0 and v < e):
                frame.loops.pop(here, None)
                frame.pc = links[here] + 1
            return
        if kw == "ENDFOR":
            opener = links[here]
            state = frame.loops.get(opener)
            if state is None:  # entered by a jump: nothing to repeat
                return
            e, s, _ = state
            target = source.get(opener).items[-1].args[0]
            v = ev.value(target) + s
            self._set_target(target, v)
            # the end value is included (seed 002 L17264, L17288); a decimal step reaches it within
            # rounding (0.1 + 0.1 + 0.1 is 0.30000000000000004)
            slack = FOR_SLACK * abs(s)
            if (s > 0 and v <= e + slack) or (s < 0 and v >= e - slack):
                self._count(state, source.get(opener))
                frame.pc = opener + 1
            else:
                frame.loops.pop(opener, None)
            return
        if kw == "WHILE":
            if ev.value(node.args[0]) == 0:
                frame.loops.pop(here, None)
                frame.pc = links[here] + 1
            else:
                self._count(frame.loops.setdefault(here, [0, 0, 0]), block)
            return
        if kw == "ENDWHILE":
            frame.pc = links[here]
            return
        if kw == "DO":
            self._count(frame.loops.setdefault(here, [0, 0, 0]), block)
            return
        if kw == "ENDDO":
            opener = links[here]
            if ev.value(node.args[0]) != 0:
                frame.pc = opener
            else:
                frame.loops.pop(opener, None)
            return
        if kw in ("BREAK", "CONTINUE"):
            opener = links[here]
            okw = kw_at(opener)
            if okw == "SWITCH":
                i = links[opener]
                while kw_at(i) != "ENDSWITCH":
                    i = links[i]
                frame.pc = i + 1
                return
            closer = links[opener]
            if kw == "BREAK":
                frame.loops.pop(opener, None)
                frame.pc = closer + 1
            elif okw == "WHILE":
                frame.pc = opener
            else:  # FOR: next value at $ENDFOR; DO: test at $ENDDO
                frame.pc = closer
            return
        if kw == "GOTO":
            self._goto(node.args[0], frame)
            return

    def _count(self, state: list, block: Block) -> None:
        state[2] += 1
        limit = self.machine.limits.max_loop_iterations
        if state[2] > limit:
            self._current_block = block
            raise InterpError("INT081", f"loop repeated more than {limit} times: runaway loop stopped "
                              "(limits.max_loop_iterations)", 1)

    def _set_target(self, target, value: float) -> None:
        if type(target) is Param:
            self.params.set(self.evaluator.index(target), value, target.col)
        else:
            self.variables.set(target.name, tuple(self.evaluator.value(i) for i in target.index), value,
                               target.col)

    def _find_label(self, source, number, label, col: int) -> int:
        if label is not None:
            index = source.find_label(label)
            shown = f"[{label}]"
        else:
            n = self.evaluator.integer(number, "N", col)
            index = source.find_number(n)
            shown = f"N{n}:"
        if index is None:
            raise InterpError("INT073", f"jump target {shown} not found in this program or subroutine "
                              "(a target block number needs ':')", col)
        return index

    def _goto(self, goto, frame) -> None:
        target = self._find_label(frame.source, goto.number, goto.label, goto.col)
        source = frame.pc - 1
        # seed 002 L17072: no jump into the body of another instruction
        for opener, closer in frame.source.spans():
            inside_target = opener < target <= closer
            inside_source = opener < source <= closer
            if inside_target and not inside_source:
                raise InterpError("INT074", "$GOTO may not jump into a $IF/$FOR/$WHILE/$DO/$SWITCH body", goto.col)
            if inside_source and not inside_target:
                frame.loops.pop(opener, None)   # leaving the structure unwinds it
        frame.pc = target

    # ------------------------------------------------------------------ #RPT
    def _repeat(self, node: Repeat) -> None:
        frame = self.frames[-1]
        start = self._find_label(frame.source, node.start.number, node.start.label, node.start.col)
        end = self._find_label(frame.source, node.end.number, node.end.label, node.end.col)
        count = 1 if node.count is None else self.evaluator.integer(node.count, "#RPT count ", node.col, 0, 1e9)
        # seed 002 L16223-L16237: #RPT [<blk1>,<blk2>,<n>] runs the range n times (no upper bound given)
        self.guard_repetitions(count, f"#RPT count {count} repeats the blocks", node.col)
        if end < start:
            raise InterpError("INT075", "#RPT: the end block comes before the start block", node.col)
        if end == start:   # seed 002 L16241
            raise InterpError("INT075", "#RPT: the start and end blocks must be different blocks (to repeat one "
                              "block, end the range at a label alone after it)", node.col)
        for opener, closer in frame.source.spans():
            if start <= closer <= end and opener < start:   # seed 002 L16280
                raise InterpError("INT075", f"#RPT: the range closes the $ structure opened at line "
                                  f"{frame.source.get(opener).line}, before the range; a repeated range must hold "
                                  "the opening of every structure it closes (L16280)", node.col)
        closing = frame.source.get(end)
        if closing is not None and closing.items:   # seed 002 L16206
            raise InterpError("INT075", f"#RPT: the end block (line {closing.line}) must hold its label alone",
                              node.col)
        if count:
            if frame.repeat is not None:   # seed 002 L16216: 20 levels of nesting
                if len(frame.outer_repeats) >= RPT_LEVELS - 1:
                    raise InterpError("INT075", f"#RPT nested more than {RPT_LEVELS} deep (L16216)", node.col)
                frame.outer_repeats.append(frame.repeat)
            frame.repeat = [start, end, count, frame.pc]
            frame.pc = start

    def _repeat_next(self, frame) -> bool:
        start, _end, remaining, back = frame.repeat
        remaining -= 1
        if remaining > 0:
            frame.repeat[2] = remaining
            frame.pc = start
        else:
            frame.repeat = frame.outer_repeats.pop() if frame.outer_repeats else None
            frame.pc = back
        return True
