"""The configuration's one exception, shared by the machine file and the LinuxCNC INI import."""

from __future__ import annotations


class MachineError(ValueError):
    """A configuration problem; the message names the key."""
