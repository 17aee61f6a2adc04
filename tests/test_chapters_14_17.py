"""Every function of seed 002 chapters 14-17 is computed or refused with its own code, never passed over
with INT078 ("not computed yet"): the index of the manual (L1353-L1715) lists them."""

from __future__ import annotations

import pytest

import fagorcnc

MACHINE = {
    "axes": {"X": {}, "Y": {}, "Z": {}, "A": {"type": "rotary", "min_limit": -120, "max_limit": 120},
             "C": {"type": "rotary", "min_limit": -9999, "max_limit": 9999},
             "B": {"type": "rotary", "rotary_mode": "normal"}, "C1": {"type": "rotary"}},
    "kinematics": [{"type": 10}, {"type": 43, "axes": ["A"], "directions": [[1, 0, 0]]}],
    "angular_axes": [{"angular_axis": "X", "orthogonal_axis": "Z", "angle": 30}],
    "c_axis": {"S": "C1"},
}
PROGRAMS = [
    "#CAX\nG1 C1=10 F100\n#CAX OFF\n",                                        # 14.1
    "#FACE [X,C]\nG1 X10 C5 F100\n#FACE OFF\n",                # 14.2
    "#CYL [Y,A,Z20]\nG1 A10 F100\n#CYL OFF\n",                 # 14.3
    "#ANGAX ON [1]\nG1 X10 F100\n#ANGAX SUSP [1]\n#ANGAX OFF [1]\n",   # 15.1, 15.2
    "G45 B90\nG1 X10 Y10 F100\nG145\nG45\n",                     # 16.1, 16.2
    "#TANGCTRL ON [B90, F300]\nG1 X10 Y10 F100\n#TANGCTRL SUSP\n#TANGCTRL OFF\n",
    "#KIN ID [1]\n",                                           # 17.2
    "#CS ON [1] [MODE 1, 0,0,0, 30,0,0]\n#TOOL ORI\nG0 X10\n#CS OFF\n",   # 17.3, 17.5
    "#ACS ON [1] [MODE 2, 0,0,0, 0,30,0]\n#ACS OFF\n",
    "#RTCP ON\nG1 X10 A10 F100\n#RTCP OFF\n",                  # 17.6
    "#TLC ON [1]\nG1 X10 F100\n#TLC OFF\n",                    # 17.7
]


@pytest.mark.parametrize("text", PROGRAMS)
def test_no_int078(text):
    r = fagorcnc.simulate(text + "M30\n", MACHINE)
    assert r.ok and "INT078" not in [d.code for d in r.diagnostics], r.diagnostics
