"""Machine-file errors name the key and the file (the user's side issue)."""

from __future__ import annotations

import pytest

from fagorcnc.cli import main
from fagorcnc.config.machine import MachineError, load_machine


@pytest.mark.parametrize(("body", "key"), [
    ("[axes.X]\nmax_jerk = -5\n", "axes.X.max_jerk"),            # negative jerk
    ("[planner]\nlookahed = 100\n", "lookahed"),                  # unknown key (typo)
    ("[axes.X]\nmax_velocity = 'fast'\n", "axes.X.max_velocity"),  # wrong type
    ("[planner]\ncorner = 200\n", "planner.corner"),              # out of range
    ("[axes.X]\nspeed = 3\n", "speed"),                           # unknown axis key
])
def test_config_errors_name_the_key_and_the_file(tmp_path, capsys, body, key):
    f = tmp_path / "mill.toml"
    f.write_text(body)
    with pytest.raises(MachineError) as err:
        load_machine(f)
    assert str(err.value).startswith(f"{f}: ") and key in str(err.value)
    assert main(["run", "--machine", str(f), "programs/demo.nc"]) == 2
    message = capsys.readouterr().err
    assert str(f) in message and key in message
