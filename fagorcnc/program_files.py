"""What the public entry points accept as a program: a file, or program text (issue 25.7).

:func:`resolve` decides, the same way for :func:`fagorcnc.simulate`, :func:`fagorcnc.dry_run`,
:func:`fagorcnc.interpret` and :func:`fagorcnc.run`:

* ``text="..."`` is program text, always;
* a :class:`os.PathLike` (``pathlib.Path``...) is a file; a missing one raises
  :class:`FileNotFoundError`;
* a ``str`` naming an existing file is that file; a ``str`` of several lines is program text;
* a one-line ``str`` that *looks like a path* -- it ends with a program extension
  (:data:`PROGRAM_EXTENSIONS`), or holds a path separator and nothing a block would (no blank,
  ``=``, bracket or parenthesis) -- but names no file raises :class:`FileNotFoundError` instead
  of being parsed as a program (``simulate("progs/missing.nc")`` used to report a syntax error);
* any other ``str`` is program text.  A string too long to be a file name is text, never an
  ``OSError`` (ENAMETOOLONG).

Also here: the rule that a program with no block at all is an error everywhere (``STR012``),
and the program files of a directory for ``fagorcnc check DIR``.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Sequence
from pathlib import Path

from .diagnostics import Diagnostic

#: File extensions of part programs: ``.nc`` (the manual's examples), ``.fst`` (subroutines kept in
#: memory, seed 002 L10236), ``.pim``, ``.cnc``, ``.tap``, ``.iso`` (what CAM posts for Fagor write).
#: [CONSTRUCTION] the manual allows any extension; this list only steers :func:`resolve` and
#: ``check DIR`` (``--extensions``).
PROGRAM_EXTENSIONS: tuple[str, ...] = (".nc", ".fst", ".pim", ".cnc", ".tap", ".iso")


class ProgramText(str):
    """Program text, as opposed to a file name (what :func:`resolve` returns for text)."""

    __slots__ = ()


Source = Path | ProgramText


def _names_a_file(text: str) -> bool:
    try:
        return Path(text).is_file()
    except (OSError, ValueError):   # too long for a file name (ENAMETOOLONG), a NUL byte...
        return False


def looks_like_path(text: str, extensions: Sequence[str] = PROGRAM_EXTENSIONS) -> bool:
    """A one-line string that reads as a file name rather than a block (see the module docstring)."""
    if "\n" in text or "\r" in text or not text.strip():
        return False
    if text.strip().lower().endswith(tuple(e.lower() for e in extensions)) and " " not in text.strip():
        return True
    separators = {"/", os.sep} | ({os.altsep} if os.altsep else set())
    body = text[1:] if text.startswith("/") else text   # "/G1 X10": a block skipped with '/'
    return any(s in body for s in separators) and not any(c in text for c in " \t=[]()")


def resolve(source: str | os.PathLike | None = None, text: str | None = None) -> Source:
    """The program a caller means (see the module docstring): a :class:`~pathlib.Path` or :class:`ProgramText`."""
    if text is not None:
        if source is not None:
            raise TypeError("give the program either as a file (source) or as text=..., not both")
        return ProgramText(text)
    if source is None:
        raise TypeError("no program: give a file name, a path, or text=...")
    if isinstance(source, ProgramText):
        return source
    if isinstance(source, os.PathLike):
        path = Path(source)
        if not path.is_file():
            raise FileNotFoundError(2, "no such program file" if not path.exists() else "not a file", str(path))
        return path
    if not isinstance(source, str):
        raise TypeError(f"a program is a str, an os.PathLike or text=..., not {type(source).__name__}")
    if "\n" not in source and "\r" not in source:
        if _names_a_file(source):
            return Path(source)
        if looks_like_path(source):
            raise FileNotFoundError(2, "no such program file (give program text as text=...)", source)
    return ProgramText(source)


def source_name(source: Source) -> str:
    """The file name the diagnostics of ``source`` carry: the path, or ``"<string>"`` for text."""
    return str(source) if isinstance(source, Path) else "<string>"


def no_block(file: str) -> Diagnostic:
    """STR012: the program holds no block at all -- the same verdict for ``run``, ``parse``, ``check``,
    :func:`~fagorcnc.simulate` and :func:`~fagorcnc.dry_run`: an empty file is an error (a post-processor
    that crashed leaves one)."""
    return Diagnostic(file, 1, 1, "STR012", "error", "the file has no block to execute: empty, or only comments "
                      "(a truncated or failed post-processor output?)")


def program_files(directory: str | os.PathLike, extensions: Sequence[str] = PROGRAM_EXTENSIONS) -> Iterator[Path]:
    """The program files under ``directory``, recursively, in sorted order: files whose extension is one of
    ``extensions`` (case-insensitive; ``""`` matches files without one).  Hidden directories are skipped."""
    wanted = {e.lower() for e in extensions}
    for root, dirs, files in os.walk(directory):
        dirs[:] = sorted(d for d in dirs if not d.startswith("."))
        for name in sorted(files):
            if Path(name).suffix.lower() in wanted:
                yield Path(root) / name
