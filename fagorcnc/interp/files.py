"""Global subroutine files: where a call finds them, what a program may make fagorcnc read, and how
a file is read.

Lookup (seed 002 L10322-L10333): a call with a full path looks only there; otherwise the CNC looks
in the directory of ``#PATH``, then in the directory of the program being executed, then in the
machine's SUBPATH (``subroutine_paths``).  A relative path (``L deep/NEST.nc``, a relative
``#PATH``) is taken in each of those directories in turn, never in the working directory of the
process.  Whatever the program writes, the file must lie inside the program's directory or a
``subroutine_paths`` directory once ``..`` and symbolic links are resolved (tests/test_file_safety.py).

Guards (issue 30): a name too long for the system, a symbolic-link loop, a file that is not a
regular file (a device, a FIFO), or one that cannot be opened (permissions) is INT151, never an
exception; a file the lookup cannot find at all is INT093.

Reading: a file of at most :data:`PARSE_WHOLE_BYTES` is parsed once and kept (a subroutine called in
a loop is parsed once); a larger one is checked once for its syntax in constant memory, then
streamed line by line at each call, like the main program (:class:`~fagorcnc.interp.source.StreamSource`),
so a subroutine file of a million lines does not sit in memory.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from ..diagnostics import Diagnostic
from ..syntax.ast import Program
from ..syntax.reader import iter_lines, parse_file, source_encoding
from ..syntax.structure import assemble
from .expressions import InterpError
from .source import StreamSource, stream_program

#: Files up to this size are parsed whole and kept; larger ones are streamed at each call.
PARSE_WHOLE_BYTES = 256 * 1024
#: Longest file name (one path component) and whole path the lookup tries (Linux's NAME_MAX, PATH_MAX).
MAX_NAME = 255
MAX_PATH = 4096


class SubroutineFiles:
    """The lookup and the files already read, for one run."""

    def __init__(self, search_paths: list[Path], program_dir: Path | None, compat=None) -> None:
        self.search_paths = search_paths
        self.program_dir = program_dir
        self.compat = compat   # the machine's [compat] policy: subroutine files are read as the program is
        self._parsed: dict[Path, Program] = {}     # small files, parsed once
        self._checked: dict[Path, str] = {}        # large files whose syntax is clean -> encoding
        self._open: list = []                       # files being streamed

    @property
    def roots(self) -> list[Path]:
        """The directories a file may come from: the program's, then the machine's subroutine_paths."""
        return ([self.program_dir] if self.program_dir is not None else []) + list(self.search_paths)

    # ------------------------------------------------------------------ lookup
    def find(self, target: str, path_sentence: str | None, col: int) -> Path:
        """The file a call of ``target`` runs (INT093 not found, INT151 found but unusable)."""
        name = target.replace("\\", "/")
        if ":" in name and len(name.split(":")[0]) == 1:   # a drive letter (C:\...), as the CNC writes it
            name = name.split(":", 1)[1]
        roots = self.roots
        _check_name(target, name, col)
        if name.startswith("/"):
            candidates = [Path(name)]   # a full path: only there (L10324)
        else:
            dirs: list[Path] = []
            if path_sentence:
                directory = path_sentence.replace("\\", "/")
                if ":" in directory and len(directory.split(":")[0]) == 1:
                    directory = directory.split(":", 1)[1]
                _check_name(path_sentence, directory, col)
                dirs += [Path(directory)] if directory.startswith("/") else [r / directory for r in roots]
            dirs += roots
            candidates = [d / name for d in dirs]
        problem = None
        for c in candidates:
            try:
                resolved = c.resolve()
                info = os.stat(resolved)
            except FileNotFoundError:
                continue
            except (OSError, RuntimeError) as exc:   # RuntimeError: a symbolic-link loop (Python 3.11)
                problem = problem or (c, _reason(exc))
                continue
            if not any(_within(resolved, r) for r in roots):
                continue
            if stat.S_ISDIR(info.st_mode):
                continue
            if not stat.S_ISREG(info.st_mode):
                problem = problem or (c, "it is not a regular file (a device or a pipe)")
                continue
            return resolved
        if problem is not None:
            raise InterpError("INT151", f"global subroutine {target}: {problem[0]} cannot be read: {problem[1]}", col)
        where = ", ".join(str(r) for r in roots) or "no directory configured (machine subroutine_paths)"
        raise InterpError("INT093", f"global subroutine {target} not found in {where}", col)

    # ------------------------------------------------------------------ reading
    def load(self, path: Path, col: int, diagnostics: list[Diagnostic]) -> tuple:
        """``(source, program, close)`` for one call of the file at ``path``: its main routine as a
        source of blocks (a :class:`RoutineSource` or a fresh :class:`StreamSource`) and what closes
        the file afterwards (None for a parsed one).  The file's diagnostics go to ``diagnostics`` once."""
        from .source import RoutineSource

        if path in self._parsed:
            sub = self._parsed[path]
            return RoutineSource(sub.main), sub, None
        if path not in self._checked:
            try:
                size = os.stat(path).st_size
                if size <= PARSE_WHOLE_BYTES:
                    sub = parse_file(path, self.compat)
                else:
                    encoding = source_encoding(path)
                    with open(path, encoding=encoding, errors="replace") as f:
                        sub = assemble(iter_lines(f, str(path), self.compat), str(path), keep_body=False)
            except OSError as exc:
                raise InterpError("INT151", f"subroutine file {path} cannot be read: {_reason(exc)}", col) from None
            diagnostics.extend(sub.diagnostics)
            if not sub.ok:
                raise InterpError("INT092", f"subroutine file {path.name} has errors", col)
            if size <= PARSE_WHOLE_BYTES:
                self._parsed[path] = sub
                return RoutineSource(sub.main), sub, None
            self._checked[path] = encoding
        try:
            f = open(path, encoding=self._checked[path], errors="replace")  # noqa: SIM115 - closed by the frame
        except OSError as exc:
            raise InterpError("INT151", f"subroutine file {path} cannot be read: {_reason(exc)}", col) from None
        self._open.append(f)
        program, source = stream_program(f, str(path), self.compat)
        source.diagnostics = []   # reported by the check above; a second read would repeat them

        def close() -> None:
            f.close()
            if f in self._open:
                self._open.remove(f)

        return source, program, close

    def close(self) -> None:
        """Close the files still being streamed (a run stopped inside a subroutine)."""
        for f in self._open:
            f.close()
        self._open.clear()


def is_stream(source) -> bool:
    return type(source) is StreamSource


def _check_name(target: str, name: str, col: int) -> None:
    parts = [p for p in name.split("/") if p]
    if len(name) > MAX_PATH or any(len(p.encode("utf-8", "surrogatepass")) > MAX_NAME for p in parts):
        raise InterpError("INT151", f"global subroutine {target[:60]}{'...' if len(target) > 60 else ''}: the name "
                          f"is too long (at most {MAX_NAME} characters a name, {MAX_PATH} a path)", col)
    if "\0" in name:
        raise InterpError("INT151", "a subroutine name cannot hold a NUL character", col)


def _reason(exc: BaseException) -> str:
    if isinstance(exc, RuntimeError) or getattr(exc, "errno", None) == 40:   # ELOOP
        return "a loop of symbolic links"
    if isinstance(exc, PermissionError):
        return "permission denied"
    return getattr(exc, "strerror", None) or str(exc)


def _within(path: Path, root: Path) -> bool:
    try:
        path.relative_to(root)
        return True
    except ValueError:
        return False
