"""``copy.deepcopy`` of a tool offset (:class:`fagorcnc.config.machine.ToolOffset`): every channel
state copies the machine's tool table, so the offset copies itself without the generic
``__reduce_ex__`` reconstruction.  The copy must be the one the generic path makes."""

from __future__ import annotations

import copy
import dataclasses

from fagorcnc.config.machine import ToolOffset, load_machine


def _generic(offset: ToolOffset) -> ToolOffset:
    """What ``copy.deepcopy`` makes of an object without ``__deepcopy__``."""
    return copy._reconstruct(offset, {}, *offset.__reduce_ex__(4))


def _same(a: ToolOffset, b: ToolOffset) -> None:
    assert type(a) is type(b)
    assert vars(a) == vars(b)
    assert [type(v) for v in vars(a).values()] == [type(v) for v in vars(b).values()]


def test_the_copy_is_the_generic_one():
    offsets = [
        ToolOffset(),
        ToolOffset(length=12.5, radius=3, radius_wear=-0.01, type=8, location_code=3, nominal_life=60.0,
                   axis_offsets={"X": 1.5}, axis_offsets_wear={"Z": -0.2}, declared=False),
    ]
    for offset in offsets:
        fast = copy.deepcopy(offset)
        _same(fast, _generic(offset))
        assert fast == offset and fast is not offset and fast.declared == offset.declared
        assert fast.axis_offsets is not offset.axis_offsets
        assert fast.axis_offsets_wear is not offset.axis_offsets_wear


def test_a_value_that_is_not_a_number_is_copied_deeply():
    """The shortcut only shares numbers, strings and None: anything else (a nested table, a list,
    an object) goes through ``copy.deepcopy``, memo included."""
    shared = [1.0, 2.0]
    offset = ToolOffset(axis_offsets={"X": shared, "Y": shared})
    offset.note = {"nested": [shared]}   # an attribute the dataclass does not declare
    fast = copy.deepcopy(offset)
    _same(fast, _generic(offset))
    assert fast.axis_offsets["X"] is not shared and fast.axis_offsets["X"] is fast.axis_offsets["Y"]
    assert fast.note["nested"][0] is fast.axis_offsets["X"]
    fast.axis_offsets["X"].append(3.0)
    assert shared == [1.0, 2.0]


def test_the_machine_tool_table_copies_as_before():
    tools = load_machine({"tools": {"1": {"1": {"length": 10.0, "radius": 2.0}}}}).tools
    fast = copy.deepcopy(tools)
    assert fast == tools
    for tool, offsets in tools.items():
        for d, offset in offsets.items():
            _same(fast[tool][d], _generic(offset))
            assert fast[tool][d] is not offset
    fast[1][1].radius = 5.0
    assert tools[1][1].radius == 2.0 and dataclasses.replace(tools[1][1]) == tools[1][1]
