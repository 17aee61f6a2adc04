"""Program structure: headers, local subroutines, jump labels, ``$`` nesting.

Turns the stream of parsed lines of one file into a :class:`Program`
(seed 002 L708-L953, L10269-L10312, L17046-L17419):

* local subroutines ``%L NAME`` come first, each ending with ``M17``, ``M29``
  or ``#RET``; then the program header ``%NAME`` (mandatory when local
  subroutines exist) and the body;
* jump targets ``N40:`` and ``[LABEL]`` are indexed per routine (duplicates
  are errors);
* ``$`` structures are matched with a stack (unmatched, crossing or
  misplaced instructions are diagnostics) and recorded in
  :attr:`Routine.structure` so the interpreter can jump without searching.
"""

from __future__ import annotations

from collections.abc import Iterable

from ..diagnostics import Diagnostic, error
from .ast import Block, Flow, Program, Routine, Sentence, SubroutineHeader, Word

_LOOP_END = {"ENDFOR": "FOR", "ENDWHILE": "WHILE", "ENDDO": "DO", "ENDIF": "IF", "ENDSWITCH": "SWITCH"}
_LOOPS = ("FOR", "WHILE", "DO")


def _ends_subroutine(block: Block) -> bool:
    """M17, M29 or #RET/#RETDSBLK in the block (seed 002 L10299-L10300)."""
    for item in block.items:
        t = type(item)
        if t is Word and item.address == "M" and item.value in (17.0, 29.0):
            return True
        if t is Sentence and item.keyword in ("RET", "RETDSBLK"):
            return True
    return False


class _Frame:
    __slots__ = ("block", "case_broken", "case_index", "case_line", "case_open", "has_else", "index", "kind",
                 "last")

    def __init__(self, kind: str, index: int, block: Block) -> None:
        self.kind = kind
        self.index = index      # block index of the opening instruction
        self.block = block      # the opening block (for messages)
        self.case_line = 0
        self.last = index       # latest instruction of the structure (for chaining)
        self.has_else = False
        self.case_open = False  # inside a $CASE section
        self.case_broken = False
        self.case_index = -1


class RoutineBuilder:
    """Collects the blocks of one routine and checks its structure on the fly."""

    def __init__(self, name: str, kind: str, line: int, file: str) -> None:
        self.name, self.kind, self.line, self.file = name, kind, line, file
        self.blocks: list = []
        self.numbers: dict = {}
        self.labels: dict = {}
        self.structure: dict = {}
        self.stack: list = []
        self.diagnostics: list = []
        self.offset = 0  # index of blocks[0] (a streamed routine drops blocks it no longer needs)
        self._target_lines: dict[int, int] = {}  # line of each jump target, by block index (for STR004)

    def _err(self, block: Block, col: int, code: str, message: str) -> None:
        self.diagnostics.append(error(self.file, block.line, col, code, message, block.text))

    def add(self, block: Block) -> None:
        index = self.offset + len(self.blocks)
        self.blocks.append(block)
        if block.number is not None:
            if block.number in self.numbers:
                first = self._line(self.numbers[block.number])
                self._err(block, 1, "STR004", f"jump target N{block.number}: is already defined on line {first}")
            else:
                self.numbers[block.number] = index
                self._target_lines[index] = block.line
        if block.label is not None:
            key = block.label.upper()
            if key in self.labels:
                first = self._line(self.labels[key])
                self._err(block, 1, "STR004", f"label [{block.label}] is already defined on line {first}")
            else:
                self.labels[key] = index
                self._target_lines[index] = block.line
        items = block.items
        if items and type(items[-1]) is Flow:  # a $ instruction is the block's last item
            self._flow(block, index, items[-1])

    def add_run(self, blocks: list) -> None:
        """:meth:`add` of each of ``blocks``, plain blocks of literal words (no jump target, no ``$``
        instruction: nothing to note but the block), all at once."""
        self.blocks.extend(blocks)

    def _line(self, index: int) -> int:
        # kept apart from the blocks: a whole-file syntax check drops every block once read
        return self._target_lines.get(index, 0)

    # ------------------------------------------------------------------ $ nesting
    def _flow(self, block: Block, index: int, node: Flow) -> None:
        kw = node.keyword
        stack = self.stack
        if kw == "IF":
            if len(node.args) == 1:  # block form; "$IF c $GOTO" has no $ENDIF (L17122)
                stack.append(_Frame("IF", index, block))
        elif kw in ("ELSEIF", "ELSE"):
            top = stack[-1] if stack else None
            if top is None or top.kind != "IF":
                self._err(block, node.col, "STR005", f"${kw} without an open $IF")
                return
            if top.has_else:
                self._err(block, node.col, "STR007", f"${kw} after $ELSE: $ELSE must be the last branch")
            if kw == "ELSE":
                top.has_else = True
            self.structure[top.last] = index
            top.last = index
        elif kw == "SWITCH":
            stack.append(_Frame("SWITCH", index, block))
        elif kw in ("CASE", "DEFAULT"):
            top = stack[-1] if stack else None
            if top is None or top.kind != "SWITCH":
                self._err(block, node.col, "STR005", f"${kw} without an open $SWITCH")
                return
            self._close_case(top, block, node.col)
            if top.has_else:
                self._err(block, node.col, "STR007", f"${kw} after $DEFAULT: $DEFAULT must be the last section")
            if kw == "DEFAULT":
                top.has_else = True
            else:
                top.case_open, top.case_broken, top.case_index = True, False, index
                top.case_line = block.line
            self.structure[top.last] = index
            top.last = index
        elif kw in _LOOPS:
            stack.append(_Frame(kw, index, block))
        elif kw in _LOOP_END:
            opener = _LOOP_END[kw]
            depth = next((i for i in range(len(stack) - 1, -1, -1) if stack[i].kind == opener), None)
            if depth is None:
                self._err(block, node.col, "STR005", f"${kw} without an open ${opener}")
                return
            while len(stack) > depth + 1:  # structures crossing this one
                inner = stack.pop()
                self._unclosed(inner, f"is not closed before ${kw} on line {block.line}")
            frame = stack.pop()
            if frame.kind == "SWITCH":
                self._close_case(frame, block, node.col)
            self.structure[frame.last] = index
            self.structure[index] = frame.index
        elif kw in ("BREAK", "CONTINUE"):
            kinds = (*_LOOPS, "SWITCH") if kw == "BREAK" else _LOOPS
            target = next((f for f in reversed(stack) if f.kind in kinds), None)
            if target is None:
                where = "a loop or a $CASE" if kw == "BREAK" else "a loop"
                self._err(block, node.col, "STR009", f"${kw} outside {where}")
                return
            self.structure[index] = target.index
            if target.kind == "SWITCH":
                target.case_broken = True

    def _close_case(self, frame: _Frame, block: Block, col: int) -> None:
        # seed 002 L17225-L17228: each $CASE ends with $BREAK
        if frame.case_open and not frame.case_broken:
            case_line = frame.case_line
            self._err(block, col, "STR007", f"the $CASE on line {case_line} must end with $BREAK")
        frame.case_open = False

    def _unclosed(self, frame: _Frame, why: str) -> None:
        block = frame.block
        closer = {"IF": "ENDIF", "SWITCH": "ENDSWITCH", "FOR": "ENDFOR", "WHILE": "ENDWHILE", "DO": "ENDDO"}
        col = next((i.col for i in block.items if type(i) is Flow), 1)
        self._err(block, col, "STR006", f"${frame.kind} {why} (missing ${closer[frame.kind]})")

    def finish(self) -> Routine:
        """Close the routine: unclosed structures and a missing subroutine end are errors."""
        while self.stack:
            self._unclosed(self.stack.pop(), "is not closed")
        if self.kind == "local" and (not self.blocks or not _ends_subroutine(self.blocks[-1])):
            last = self.blocks[-1] if self.blocks else None
            line, text = (last.line, last.text) if last else (self.line, "")
            self.diagnostics.append(error(
                self.file, line, 1, "STR003",
                f"local subroutine {self.name} must end with M17, M29 or #RET", text))
        return Routine(self.name, self.kind, self.line, tuple(self.blocks),
                       self.numbers, self.labels, self.structure)


def assemble(lines: Iterable, file: str, keep_body: bool = True) -> Program:
    """Build a :class:`Program` from ``(node, diagnostics)`` pairs of one file.

    ``keep_body=False`` checks the file without keeping the blocks of its main program (each is
    dropped once its structure is noted): the diagnostics of the whole file in constant memory,
    and a program whose main routine is empty."""
    diagnostics: list[Diagnostic] = []
    subroutines: dict = {}
    name = None
    header_seen = False
    first_sub_line = None
    current = RoutineBuilder("", "program", 1, file)  # body before any header
    main = current

    def close(builder: RoutineBuilder) -> None:
        routine = builder.finish()
        diagnostics.extend(builder.diagnostics)
        builder.diagnostics = []
        if builder.kind == "local":
            key = routine.name.upper()
            if key in subroutines:
                diagnostics.append(error(file, routine.line, 1, "STR008",
                                         f"local subroutine {routine.name} is defined twice"))
            else:
                subroutines[key] = routine

    for node, diags in lines:
        diagnostics.extend(diags)
        if node is None:
            continue
        t = type(node)
        if t is Block:
            current.add(node)
            if not keep_body and current is main:
                main.offset += 1
                main.blocks.clear()
        elif t is SubroutineHeader:
            if header_seen or main.offset + len(main.blocks):
                diagnostics.append(error(
                    file, node.line, 1, "STR002",
                    f"local subroutine {node.name} must be defined before the program header and body "
                    "(seed 002 L917)", node.text))
            if first_sub_line is None:
                first_sub_line = node.line
            if current is not main:
                close(current)
            current = RoutineBuilder(node.name, "local", node.line, file)
        else:  # ProgramHeader
            if header_seen:
                diagnostics.append(error(file, node.line, 1, "STR010",
                                         f"second program header %{node.name} in one file", node.text))
            if current is not main:
                close(current)
            header_seen = True
            name = node.name
            current = main
            main.name, main.line = node.name, node.line
    if current is not main:
        close(current)
    if subroutines and not header_seen:
        diagnostics.append(error(file, first_sub_line or 1, 1, "STR001",
                                 "a file with local subroutines needs a program header %NAME "
                                 "before its body (seed 002 L846)"))
    routine = main.finish()
    diagnostics.extend(main.diagnostics)
    diagnostics.sort(key=lambda d: (d.line, d.col))
    return Program(file, name, routine, subroutines, tuple(diagnostics))
