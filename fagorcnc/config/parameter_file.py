"""Parameter persistence: global and common parameters kept between runs.

On a Fagor the global parameters (P100..P299 by default) belong to the
channel and the common ones (P10000..P10999) to the whole CNC; both keep their
values from one program to the next (seed 002 L1861-L1911).  fagorcnc runs
each program in a fresh interpreter, so a machine that wants them kept names
a parameter file, like LinuxCNC's ``[RS274NGC] PARAMETER_FILE`` (seed 003 L802)::

    parameter_file = "params.var"     # in the machine TOML, relative to it

The file is LinuxCNC's ``.var`` format: one ``number value`` pair per line
(tab-separated, numbers in increasing order); blank lines and lines starting
with ``#`` or ``;`` are ignored when reading.  A missing file is an empty one.

* Every run (:func:`fagorcnc.simulate`, :func:`fagorcnc.interpret` and so
  ``fagorcnc run`` and ``fagorcnc check``) starts with the values of the file.
* Only a real run saves them: the streaming run behind ``fagorcnc run`` writes
  the file when its iteration ends (at M30, at an error or when stopped).  A
  dry run (``simulate``, ``fagorcnc check``, the check before a real machine
  run) never writes it, so checking a program twice does not change the next
  run's starting values.
* Entries outside the machine's global and common ranges are kept as they are.
* The file is replaced atomically (written beside it, then renamed).

A malformed file is reported as a ``CFG002`` error diagnostic of the run and
is then never overwritten.
"""

from __future__ import annotations

import os
import stat
import tempfile
from pathlib import Path

from ..diagnostics import Diagnostic
from .machine import Machine


class ParameterFileError(ValueError):
    """A parameter file that cannot be read; the message names the file and line."""

    def __init__(self, reason: str, path: Path, line: int = 1) -> None:
        super().__init__(f"{path}:{line}: {reason}")
        self.reason, self.path, self.line = reason, path, line


#: Largest parameter file read, in bytes: the 20 000 global and common parameters take about
#: 600 kB.  A larger file, or one that is not a regular file (``/dev/zero``, a pipe), is refused
#: with CFG002 before it is read (issue 30).  [CONSTRUCTION]
MAX_PARAMETER_FILE_BYTES = 4 * 1024 * 1024


def read_parameter_file(path: str | Path) -> dict[int, float]:
    """The ``{number: value}`` pairs of a parameter file; ``{}`` when it does not exist."""
    path = Path(path)
    try:
        info = os.stat(path)
        if not stat.S_ISREG(info.st_mode):
            raise ParameterFileError("the parameter file is not a regular file (a device, a pipe or a directory)",
                                     path)
        if info.st_size > MAX_PARAMETER_FILE_BYTES:
            raise ParameterFileError(f"the parameter file is {info.st_size} bytes, more than the "
                                     f"{MAX_PARAMETER_FILE_BYTES} a parameter file may hold", path)
        with open(path, "rb") as f:
            data = f.read(MAX_PARAMETER_FILE_BYTES + 1)   # it may have grown since
        if len(data) > MAX_PARAMETER_FILE_BYTES:
            raise ParameterFileError(f"the parameter file holds more than {MAX_PARAMETER_FILE_BYTES} bytes", path)
        text = data.decode("utf-8", errors="replace")
    except FileNotFoundError:
        return {}
    except OSError as exc:
        raise ParameterFileError(f"cannot read the parameter file ({exc.strerror or exc})", path) from None
    if "\r" in text:
        text = text.replace("\r\n", "\n").replace("\r", "\n")   # as read_text did (universal newlines)
    values: dict[int, float] = {}
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.strip()
        if not line or line[0] in "#;":
            continue
        fields = line.split()
        try:
            if len(fields) != 2:
                raise ValueError
            values[int(fields[0])] = float(fields[1])
        except ValueError:
            raise ParameterFileError(f"parameter file: expected 'number value', got {line!r}", path,
                                     number) from None
    return values


def write_parameter_file(path: str | Path, values: dict[int, float]) -> None:
    """Write ``{number: value}`` pairs (sorted by number, exact float text) atomically."""
    path = Path(path)
    text = "".join(f"{n}\t{float(values[n])!r}\n" for n in sorted(values))
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as out:
            out.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


class ParameterFile:
    """The link between one interpreter's parameters and the machine's parameter file."""

    def __init__(self, path: Path, params, machine: Machine, kept: dict[int, float]) -> None:
        self.path = path
        self.params = params
        self.machine = machine
        self.kept = kept   # entries outside the machine's ranges, written back unchanged

    def save(self) -> None:
        """Write the current global and common parameters (and the kept entries) to the file."""
        values = dict(self.kept)
        values.update(self.params.globals)
        values.update(self.params.common)
        write_parameter_file(self.path, values)


def attach_parameter_file(interpreter) -> ParameterFile | None:
    """Load the machine's parameter file into a fresh interpreter's global and common parameters.

    Returns the :class:`ParameterFile` to :meth:`~ParameterFile.save` at the end
    of a real run, or None when the machine has no parameter file or the file is
    malformed (then a ``CFG002`` error is added to the interpreter's diagnostics
    and the file is left alone).  Touches only ``interpreter.params``.
    """
    machine: Machine = interpreter.machine
    path = getattr(machine, "parameter_file", None)
    if path is None:
        return None
    path = Path(path)
    try:
        values = read_parameter_file(path)
    except ParameterFileError as exc:
        interpreter.diagnostics.append(Diagnostic(str(exc.path), exc.line, 1, "CFG002", "error", exc.reason))
        return None
    params = interpreter.params
    kept = {}
    for n, v in values.items():
        if machine.global_params[0] <= n <= machine.global_params[1]:
            params.globals[n] = v
        elif machine.common_params[0] <= n <= machine.common_params[1]:
            params.common[n] = v
        else:
            kept[n] = v
    return ParameterFile(path, params, machine, kept)
