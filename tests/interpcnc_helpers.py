"""Helpers shared by the InterpCNC back-end tests: plan a program, stream it with the operator's recovery, and
compare what the emulated card executed with the plan."""

from __future__ import annotations

import fagorcnc
from fagorcnc.backends.interpcnc import InterpCncError
from fagorcnc.backends.interpcnc.verify import executed_events, expected_events, first_difference


def plan(text: str):
    """``(machine, segments)`` of a program that must simulate without error."""
    result = fagorcnc.simulate(text)
    assert result.ok, result.diagnostics[:3]
    return result.machine, list(result.segments(keep_profiles=False))


def stream(backend, segments, recover, limit: int = 4) -> list[InterpCncError]:
    """Send everything then finish; on an error check the segment was kept and call ``recover(error)``
    (at most ``limit`` errors while sending, ``limit`` attempts to finish)."""
    errors: list[InterpCncError] = []
    for seg in segments:
        try:
            backend.send(seg)
        except InterpCncError as err:
            assert err.accepted, err
            errors.append(err)
            assert len(errors) <= limit, errors
            recover(err)
    for _ in range(limit):
        try:
            backend.finish()
            break
        except InterpCncError as err:
            errors.append(err)
            recover(err)
    return errors


def assert_exactly_once(segments, backend, log) -> None:
    """Every move, dwell and output action of the plan ran once, in order (the card's executed ``log``)."""
    difference = first_difference(expected_events(segments, backend), executed_events(log))
    assert difference is None, difference
