"""``fagorcnc emulate``: serve an emulated InterpCNC card over Modbus TCP (its own options:
``fagorcnc emulate --help``)."""

from __future__ import annotations

from collections.abc import Sequence


def command(argv: Sequence[str]) -> int:
    """Handler of ``fagorcnc emulate``: the emulator's own command line."""
    from ..backends.interpcnc.emulator import main as emulate

    return emulate(list(argv))
