"""The ``jacobian-lab`` command line: robot listing, export delegation, clear errors."""

from __future__ import annotations

import robots
from app.cli import main


def test_robots_lists_the_library(capsys):
    assert main(["robots"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split()[0] for line in lines] == robots.names()
    assert any("7 joints" in line and line.startswith("panda") for line in lines)


def test_serve_with_an_unknown_robot_fails_before_serving(capsys):
    assert main(["serve", "--robot", "puma56", "--port", "0"]) == 2
    err = capsys.readouterr().err
    assert "unknown robot 'puma56'" in err and "puma560" in err  # the message lists what exists


def test_serve_with_a_missing_urdf_fails_clearly(capsys, tmp_path):
    assert main(["serve", "--urdf", str(tmp_path / "arm.urdf"), "--port", "0"]) == 2
    assert "arm.urdf" in capsys.readouterr().err


def test_export_is_delegated(capsys):
    assert main(["export", "planar2", "--format", "json"]) == 0
    out = capsys.readouterr().out
    assert '"robot": "planar2"' in out or '"planar2"' in out
