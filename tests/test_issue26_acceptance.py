"""Issue 26's "done when": ``fagorcnc check`` on a program using each function the issue names gives no
INT011 (unknown function), INT078 (not computed), INT079 (no effect offline), INT044 (unknown variable) or
INT240 (a variable of the manual not implemented), and passes.  One program per item of the issue, each
made of the manual's own forms (the seed lines are in the feature tests named in each comment)."""

from __future__ import annotations

import json

import pytest

from fagorcnc.cli import main

#: axes of the manual's examples (X Y Z A W, L14818) and the U V B C of the others; two spindles
MACHINE = """\
spindles = ["S", "S1"]
[axes.X]
[axes.Y]
[axes.Z]
[axes.A]
type = "rotary"
[axes.W]
[axes.U]
[axes.V]
[axes.B]
type = "rotary"
[axes.C]
type = "rotary"
[tools.1.1]
radius = 2.0
length = 50.0
[machine_parameters]
"MPA.POSFEED.U" = 400
"MPG.MINDYNOVR" = 10
"MPG.MAXDYNOVR" = 200
"MPG.STEPDYNOVR" = 10
"MPA.THREADOVR.S" = 20
"""

PROGRAMS = {
    # 1. threading and rigid tapping, G95 (tests/test_threading.py)
    "threading": "S100 M03\nG01 G90 X30 Y30 Z0 F500\nG33 Z-30 K1.5\nM19 S0\nG91 G00 X3\nG90 Z10\n"
                 "S500 M03\nG63 Z-20 F500\nG63 Z10 S-500\nM05\nS800 M3\nG95 G1 Z-5 F0.1\nG94\nM30\n",
    # 2. spindle positioning (tests/test_spindle_positioning.py)
    "spindle positioning": "N10 G97 S2500 M03\nN20 M19 S50\nN30 M19 S150\nN40 S1000\nN50 M19 S-100\nN60 M03\n"
                           "P1=V.A.PRGSPOS.S P2=V.A.SPOS.S P3=V.A.PRGSSO.S P4=V.A.SSO.S\nM30\n",
    # 3. manual intervention (tests/test_manual_intervention.py)
    "manual intervention": "N100 G71 G90 X0 Y0 F400\nN110 G201 #AXIS [X, Z]\nN120 G01 X100 Y50\n"
                           "N130 G202 #AXIS [X]\nN140 G01 X50 Y150\nN150 G202 #AXIS [Z]\nM30\n",
    # 4. axis and spindle configuration (tests/test_axes.py, tests/test_spindle_config.py)
    "configuration": "#SET AX [X, Y, Z, A, U]\n#CALL AX [W, 6]\n#FREE AX [W]\n#RENAME AX [X, X1]\n"
                     "#RENAME AX OFF\n#PARK B\n#UNPARK B\n#FREE SP [S1]\n#CALL SP [S1]\n#SET SP [S, S1]\n"
                     "#RENAME SP [S, S1]\n#RENAME SP OFF\n#MASTER S1\nP1=V.G.NSPDL P2=V.A.ACTCH.S\nM30\n",
    # 5. coupled axes (tests/test_axes.py)
    "coupled axes": "G0 U5\n#LINK [X, U]\nG1 X10 F1000\n#UNLINK\nG1 U20\nG1 X0\nM30\n",
    # 6. macros (tests/test_macros.py)
    "macros": '#DEF "READY"="G0 X0 Y0 Z10"\n#DEF "START"="SP1 M3 M41" "STOP"="M05"\n"READY"\n'
              'P1=800 "START" F450\nG01 Z0\nX40 Y40\n"STOP"\n#INIT MACROTAB\nM30\n',
    # 7. curves and independent axes (tests/test_curves.py, tests/test_independent_timeline.py)
    "curves": "G0 X0 Y1 Z0\nG1 F1000\n#POLY [X[0,60] Y[1,0,3] SP0 EP1]\nG1 X20 Y20\n"
              "#ASPLINE MODE [1,2]\n#SPLINE ON\nX40 Y60\nX60\nX50 Y40\n#SPLINE OFF\n"
              "#MOVE ABS [U100, F1000]\nG1 X50 F600\n#SYNC POS\nM30\n",
    # 8. block rules (tests/test_block_rules.py, tests/test_entry_compensation.py)
    "block rules": "#MCS ON\nG0 X0\n#MCS OFF\n#DGWZ [-100, 100, -100, 100, -50, 50]\nM30\n",
    # 9. laser state (tests/test_laser.py)
    "laser": "#SWTOUT ON [TON=50 TOF=40]\nP1=V.G.TON P2=V.G.TOF P3=V.G.PON P4=V.G.POF\n#SWTOUT OFF\n"
             "#PWMOUT ON [FREQ=1000, DUTY=50]\nP5=V.G.PWMON P6=V.G.PWMFREQ P7=V.G.PWMDUTY\n#PWMOUT OFF\nM30\n",
    # 10. the variable catalogue (tests/test_variables_catalogue.py, tests/test_variables_tools.py)
    "variables": "T1 D1 M6\nS1000 M3\nG134 X80\nG264\nG1 G90 X0 Y0 F100\nG2 X20 Y0 I10 J0\n"
                 "P1=V.G.CIRERR[1] P2=V.G.EXTORG P3=V.G.MIRROR1\n"
                 "P4=V.G.AXISNAME1 P5=V.G.MAXACCEL P6=V.G.TOR P7=V.A.FFGAIN.X P8=V.MPA.POSFEED.U\n"
                 "V.G.DYNOVR=50\nP9=V.G.DYNOVR P10=V.G.ENDREP P11=V.G.SPDLREP P12=V.SP.THREADOVR "
                 "P13=V.MPG.RENAMECANCEL\nM30\n",
}

UNSUPPORTED = ("INT011", "INT078", "INT079", "INT044", "INT240")


@pytest.mark.parametrize("item", PROGRAMS)
def test_check_passes_without_an_unsupported_function(item, tmp_path, capsys):
    (tmp_path / "machine.toml").write_text(MACHINE)
    program = tmp_path / "part.nc"
    program.write_text(PROGRAMS[item])
    status = main(["check", "--machine", str(tmp_path / "machine.toml"), "--format", "json", str(program)])
    report = json.loads(capsys.readouterr().out)
    codes = [d["code"] for f in report["files"] for d in f["diagnostics"]]
    assert not [c for c in codes if c in UNSUPPORTED], codes
    assert status == 0, codes
