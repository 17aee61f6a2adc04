"""Program text cannot make fagorcnc read files outside the configured directories.

Global subroutines (``L``, ``#CALL``, ``#PCALL``, ``#MCALL``, G180...) and ``#PATH`` are
looked up only in the machine's ``subroutine_paths`` and the program's own directory;
``..``, absolute paths and symbolic links are resolved first and refused when they lead
outside (INT093).  The secret file below would parse as a valid subroutine, so a
refusal cannot be a parse error in disguise.
"""

from __future__ import annotations

import os

import pytest

import fagorcnc

SECRET = "P100 = 666\nM17\n"


@pytest.fixture
def layout(tmp_path):
    subs = tmp_path / "subs"
    subs.mkdir()
    (subs / "OK.nc").write_text("P100 = 1\nM17\n")
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "SECRET.nc").write_text(SECRET)
    prog_dir = tmp_path / "prog"
    prog_dir.mkdir()
    return {"subroutine_paths": [str(subs)]}, subs, outside, prog_dir


def run(text: str, machine, prog_dir):
    f = prog_dir / "main.nc"
    f.write_text("P100 = 0\n" + text)
    return fagorcnc.simulate(f, machine)


def refused(r) -> bool:
    return [d.code for d in r.errors] == ["INT093"] and r.state.param(100) != 666


def test_configured_directory_is_searched(layout):
    machine, _subs, _outside, prog = layout
    r = run("L OK.nc\nM30\n", machine, prog)
    assert r.ok and r.state.param(100) == 1


@pytest.mark.parametrize("target", ["../outside/SECRET.nc", "..\\outside\\SECRET.nc", "../../outside/SECRET.nc"])
def test_dot_dot_cannot_escape(layout, target):
    machine, _subs, _outside, prog = layout
    assert refused(run(f"L {target}\nM30\n", machine, prog))


def test_absolute_path_outside_is_refused(layout):
    machine, _subs, outside, prog = layout
    assert refused(run(f'#CALL "{outside / "SECRET.nc"}"\nM30\n'.replace('"', ""), machine, prog))


def test_path_sentence_cannot_point_outside(layout):
    machine, _subs, outside, prog = layout
    assert refused(run(f'#PATH ["{outside}"]\nL SECRET.nc\nM30\n', machine, prog))


@pytest.mark.skipif(not hasattr(os, "symlink"), reason="no symbolic links on this system")
def test_symlink_inside_the_directory_pointing_outside_is_refused(layout):
    machine, subs, outside, prog = layout
    (subs / "LINK.nc").symlink_to(outside / "SECRET.nc")
    assert refused(run("L LINK.nc\nM30\n", machine, prog))


def test_system_files_are_refused(layout):
    machine, _subs, _outside, prog = layout
    r = run("#CALL /etc/passwd\nM30\n", machine, prog)
    assert [d.code for d in r.errors] == ["INT093"]


def test_a_run_writes_nothing(layout):
    machine, subs, _outside, prog = layout
    (prog / "main.nc").write_text("")
    before = {p: p.stat().st_mtime_ns for p in (subs.parent).rglob("*") if p.is_file()}
    run('#MSG ["hello"]\n#ERROR ["stop"]\nM30\n', machine, prog)
    after = {p: p.stat().st_mtime_ns for p in (subs.parent).rglob("*") if p.is_file()}
    assert set(after) == set(before)
    assert all(after[p] == t for p, t in before.items() if p != prog / "main.nc")
