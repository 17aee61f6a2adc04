"""LinuxCNC INI import (seed 003 §3.5: [TRAJ], [AXIS_n], [JOINT_n], [EMCMOT]; units per second)."""

from __future__ import annotations

import pytest

import fagorcnc
from fagorcnc.cli import main
from fagorcnc.config.linuxcnc import DEFAULT_JERK_RATE, NO_LIMIT, load_ini
from fagorcnc.config.machine import MachineError, load_machine

INCH_MILL = """\
# LinuxCNC 2.8+ layout, inch machine
[EMC]
MACHINE = test mill

[EMCMOT]
SERVO_PERIOD = 500000

[TRAJ]
COORDINATES = X Y Y Z A
LINEAR_UNITS = inch
ANGULAR_UNITS = degree
MAX_LINEAR_VELOCITY = 2.0

[KINS]
KINEMATICS = trivkins coordinates=XYYZA
JOINTS = 5

[AXIS_X]
MAX_VELOCITY = 1.5   # inch per second
MAX_ACCELERATION = 20.0
MIN_LIMIT = -10.0
MAX_LIMIT = 10.0

[AXIS_Y]
MAX_VELOCITY = 1.0
MAX_ACCELERATION = 10.0
MAX_JERK = 500
MIN_LIMIT = -5.0
MAX_LIMIT = 5.0

[JOINT_1]
MAX_VELOCITY = 0.9
MIN_LIMIT = -4.0
HOME = 1.0

[JOINT_2]
MAX_LIMIT = 4.5

[AXIS_Z]
MAX_VELOCITY = 0.5
MAX_ACCELERATION = 5.0
MIN_LIMIT = -4.0
MAX_LIMIT = 0.1

[AXIS_A]
MAX_VELOCITY = 90
MAX_ACCELERATION = 360
WRAPPED_ROTARY = 1

[HAL]
HALFILE = core_sim.hal
HALFILE = simulated_home.hal

[RS274NGC]
SUBROUTINE_PATH = subs:/opt/shared
"""


@pytest.fixture
def inch_ini(tmp_path):
    f = tmp_path / "mill.ini"
    f.write_text(INCH_MILL)
    return f


def test_inch_units_per_second_become_mm_per_minute(inch_ini):
    m = load_machine(inch_ini)
    assert m.axis_names == ["X", "Y", "Z", "A"]   # a gantry's Y written twice is one axis
    x, y, z, a = (m.axes[n] for n in m.axis_names)
    assert x.type == "linear" and x.max_velocity == pytest.approx(1.5 * 25.4 * 60)   # 2286 mm/min
    assert x.max_acceleration == pytest.approx(20 * 25.4)
    assert (x.min_limit, x.max_limit) == pytest.approx((-254.0, 254.0))
    assert x.max_jerk == pytest.approx(DEFAULT_JERK_RATE * 20 * 25.4)   # no MAX_JERK: documented default
    assert y.max_jerk == pytest.approx(500 * 25.4)
    # axis and joint both give a value: the more restrictive wins (JOINT_1 speed, JOINT_1 min, JOINT_2 max)
    assert y.max_velocity == pytest.approx(0.9 * 25.4 * 60)
    assert (y.min_limit, y.max_limit) == pytest.approx((-4.0 * 25.4, 4.5 * 25.4))
    assert y.home == pytest.approx(25.4)
    assert z.max_limit == pytest.approx(2.54)
    # rotary axes stay in degrees; WRAPPED_ROTARY: 0..360 with the sign giving the direction
    assert a.type == "rotary" and a.max_velocity == pytest.approx(5400.0) and a.rotary_mode == "normal"
    assert (a.min_limit, a.max_limit) == (-NO_LIMIT, NO_LIMIT)
    assert m.planner.servo_period == pytest.approx(0.0005)
    assert m.rapid_feed == m.max_feed == pytest.approx(2.0 * 25.4 * 60)
    assert [str(p) for p in m.subroutine_paths] == [str(inch_ini.parent.resolve() / "subs"), "/opt/shared"]


def test_soft_limits_of_the_ini_apply_to_programs(inch_ini):
    r = fagorcnc.simulate("G1 X200 F1000\nG1 X300\nM30\n", inch_ini)
    (d,) = r.errors
    assert d.code == "INT100" and d.line == 2 and "upper limit 254" in d.message


def test_a_bad_value_names_file_line_section_and_key(tmp_path, capsys):
    f = tmp_path / "bad.ini"
    f.write_text("[TRAJ]\nCOORDINATES = X Y Z\nLINEAR_UNITS = mm\n\n[AXIS_X]\nMAX_VELOCITY = fast\n")
    with pytest.raises(MachineError) as exc:
        load_machine(f)
    assert str(exc.value) == f"{f}:6: [AXIS_X] MAX_VELOCITY: expected a number, got 'fast'"
    assert main(["check", "--machine", str(f), "nothing.nc"]) == 2
    assert "[AXIS_X] MAX_VELOCITY" in capsys.readouterr().err


@pytest.mark.parametrize(("text", "message"), [
    ("[TRAJ]\nCOORDINATES = X Y Z\nLINEAR_UNITS = furlong\n", "[TRAJ] LINEAR_UNITS: unknown unit 'furlong'"),
    ("[TRAJ]\nCOORDINATES = X Q\n", "[TRAJ] COORDINATES: 'Q' is not an axis letter"),
    ("[TRAJ]\nCOORDINATES = X\n[AXIS_X]\nMAX_ACCELERATION = 0\n", ":4: [AXIS_X] MAX_ACCELERATION: must be positive"),
    ("[TRAJ]\nCOORDINATES = X\n[AXIS_X]\nMIN_LIMIT = 5\nMAX_LIMIT = 1\n", "[AXIS_X] MIN_LIMIT 5 is above MAX_LIMIT 1"),
    ("[EMCMOT]\nSERVO_PERIOD = 10\n[TRAJ]\nCOORDINATES = X\n", "[EMCMOT] SERVO_PERIOD: 10 ns is not a servo period"),
    ("[EMC]\nMACHINE = nothing\n", "no axes"),
])
def test_configuration_errors(tmp_path, text, message):
    f = tmp_path / "m.ini"
    f.write_text(text)
    with pytest.raises(MachineError) as exc:
        load_ini(f)
    assert message in str(exc.value) and str(f) in str(exc.value)


def test_older_numbered_axis_sections_and_traj_fallbacks(tmp_path):
    # LinuxCNC 2.7 and before: [AXIS_0] = X, [AXIS_2] = Z (seed 003 L950-L966); [TRAJ] MAX_VELOCITY fallback
    f = tmp_path / "lathe.ini"
    f.write_text("[TRAJ]\nLINEAR_UNITS = mm\nMAX_VELOCITY = 50\nMAX_ACCELERATION = 400\n"
                 "[AXIS_0]\nTYPE = LINEAR\nMIN_LIMIT = -100\nMAX_LIMIT = 5\n"
                 "[AXIS_2]\nTYPE = LINEAR\nMAX_VELOCITY = 30\n")
    m = load_machine(f)
    assert m.axis_names == ["X", "Z"]
    assert m.axes["X"].max_velocity == pytest.approx(3000.0) and m.axes["X"].max_acceleration == 400.0
    assert m.axes["Z"].max_velocity == pytest.approx(1800.0)
    assert (m.axes["X"].min_limit, m.axes["X"].max_limit) == (-100.0, 5.0)


def test_toml_includes_an_ini_and_overrides_single_keys(inch_ini, tmp_path):
    toml = tmp_path / "machine.toml"
    toml.write_text('linuxcnc_ini = "mill.ini"\nparameter_file = "params.var"\n'
                    '[axes.Z]\nmax_limit = 0.0\n[origins]\nG54 = { X = 10.0 }\n')
    m = load_machine(toml)
    assert m.axes["Z"].max_limit == 0.0 and m.axes["Z"].min_limit == pytest.approx(-101.6)
    assert m.axes["X"].max_velocity == pytest.approx(2286.0)
    assert m.origins[1] == {"X": 10.0}
    assert m.parameter_file == tmp_path.resolve() / "params.var"


def test_trivial_kinematics_number_the_joints_by_axis_letter_not_by_coordinates_order(tmp_path):
    # seed 003 L896-L900: with trivial kinematics X is always joint 0, A joint 3, U joint 6; COORDINATES
    # names the axes and has no effect on the joint numbers.  A lathe: COORDINATES = X Z, joints 0 and 2.
    f = tmp_path / "lathe.ini"
    f.write_text("[TRAJ]\nCOORDINATES = X Z\nLINEAR_UNITS = mm\n[KINS]\nKINEMATICS = trivkins\n"
                 "[JOINT_0]\nMAX_VELOCITY = 20\nMAX_ACCELERATION = 200\n"
                 "[JOINT_2]\nMAX_VELOCITY = 8\nMAX_ACCELERATION = 50\nMIN_LIMIT = -300\nMAX_LIMIT = 2\nHOME = 1\n")
    m = load_machine(f)
    x, z = m.axes["X"], m.axes["Z"]
    assert m.axis_names == ["X", "Z"]
    assert x.max_velocity == pytest.approx(20 * 60) and x.max_acceleration == pytest.approx(200)
    # 8 mm/s = 480 mm/min and 50 mm/s² from JOINT_2, not the default axis
    assert z.max_velocity == pytest.approx(480) and z.max_acceleration == pytest.approx(50)
    assert (z.min_limit, z.max_limit, z.home) == pytest.approx((-300, 2, 1))
    # with coordinates= the joints follow its letters: joint 1 is then Z
    f.write_text("[TRAJ]\nCOORDINATES = X Z\n[KINS]\nKINEMATICS = trivkins coordinates=XZ\n"
                 "[JOINT_1]\nMAX_VELOCITY = 8\n")
    assert load_machine(f).axes["Z"].max_velocity == pytest.approx(480)


def test_the_trajectory_acceleration_limits_the_path(tmp_path):
    # seed 003 L932: [TRAJ] MAX_LINEAR_ACCELERATION, the trajectory's maximum acceleration (units/s²)
    f = tmp_path / "m.ini"
    body = "".join(f"[AXIS_{a}]\nMAX_VELOCITY = 100\nMAX_ACCELERATION = 500\n" for a in "XY")
    f.write_text("[TRAJ]\nCOORDINATES = X Y\nMAX_LINEAR_ACCELERATION = 200\n" + body)
    limited = load_machine(f)
    assert limited.planner.max_path_acceleration == pytest.approx(200.0)
    assert limited.axes["X"].max_acceleration == pytest.approx(500.0)   # the axis' own value stays
    program = "G1 X100 F6000\nM30\n"   # 100 mm/s: 0.5 s of acceleration at 200 mm/s², 0.2 s at 500
    slow = fagorcnc.simulate(program, limited).cycle_time
    f.write_text("[TRAJ]\nCOORDINATES = X Y\n" + body)
    fast = fagorcnc.simulate(program, load_machine(f)).cycle_time
    assert slow > fast + 0.25
