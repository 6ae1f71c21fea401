"""The ``jacobian-lab`` command line: listing, serve's checks before any server starts, the export command."""

from __future__ import annotations

import io
import json
import time

import numpy as np
import pytest
from fakes import poll
from kinematics_helpers import import_source

import robots
from app.cli import export as export_command
from app.cli.main import main
from kinematics import jacobian
from kinematics.urdf import robot_from_urdf

TWO_LEAVES = """<robot name="forked">
  <link name="base"/><link name="upper"/><link name="tool0"/><link name="aux"/>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <axis xyz="0 0 1"/><limit lower="-2" upper="2"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="tool0"/>
    <origin xyz="0.5 0 0"/><axis xyz="0 0 1"/><limit lower="-2" upper="2"/></joint>
  <joint name="aux_joint" type="prismatic"><parent link="base"/><child link="aux"/>
    <axis xyz="1 0 0"/><limit lower="0" upper="0.2"/></joint>
</robot>
"""


@pytest.fixture
def forked(tmp_path):
    path = tmp_path / "forked.urdf"
    path.write_text(TWO_LEAVES)
    return path


# ------------------------------------------------------------------ robots
def test_robots_lists_the_library(capsys):
    assert main(["robots"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split()[0] for line in lines] == robots.names()
    panda = next(line for line in lines if line.startswith("panda"))
    assert "7 joints" in panda


# ------------------------------------------------------------------ serve: errors at once
def test_serve_with_an_unknown_robot_fails_before_serving(capsys):
    assert main(["serve", "--robot", "puma56", "--port", "0"]) == 2
    err = capsys.readouterr().err
    assert "unknown robot 'puma56'" in err
    assert "puma560" in err  # the message lists what exists


def test_serve_with_a_missing_urdf_fails_clearly(capsys, tmp_path):
    assert main(["serve", "--urdf", str(tmp_path / "arm.urdf"), "--port", "0"]) == 2
    assert f"cannot read URDF '{tmp_path / 'arm.urdf'}': No such file" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("port", "shown"), [("99999", "99999"), ("65536", "65536"), ("-1", "-1"), ("http", "'http'")]
)
def test_serve_refuses_a_port_outside_the_range(capsys, port, shown):
    start = time.thread_time()  # refused before any work: CPU time, which a busy machine cannot inflate
    assert main(["serve", "--port", port]) == 2
    err = capsys.readouterr().err
    assert f"argument --port: expected a port number from 0 to 65535, got {shown}" in err
    assert time.thread_time() - start < 2.0


def test_serve_refuses_a_host_that_does_not_resolve(capsys):
    start = time.perf_counter()
    assert main(["serve", "--host", "no-such-host.invalid", "--port", "0"]) == 2
    assert (
        "cannot listen on host 'no-such-host.invalid': the name does not resolve" in capsys.readouterr().err
    )
    assert time.perf_counter() - start < 10.0


def test_serve_refuses_an_address_of_another_machine(capsys):
    assert main(["serve", "--host", "192.0.2.1", "--port", "0"]) == 2  # TEST-NET-1: never local
    err = capsys.readouterr().err
    assert "cannot listen on host '192.0.2.1' (192.0.2.1)" in err and "use an address of this machine" in err


def test_serve_refuses_an_unknown_tip_before_serving(capsys, forked):
    assert main(["serve", "--urdf", str(forked), "--tip", "hand", "--port", "0"]) == 2
    assert "unknown tip_link 'hand'; links: base, upper, tool0, aux" in capsys.readouterr().err


def test_serve_refuses_links_for_a_library_robot(capsys):
    assert main(["serve", "--robot", "panda", "--tip", "tool0", "--port", "0"]) == 2
    assert "panda.toml: base_link/tip_link choose a chain in a URDF" in capsys.readouterr().err
    assert main(["serve", "--base", "world", "--port", "0"]) == 2
    assert "--base and --tip choose a chain of the URDF given with --urdf" in capsys.readouterr().err


def test_serve_presenter_flags(monkeypatch, capsys):
    import app.server

    calls = []
    monkeypatch.setattr(app.server, "serve", lambda **kwargs: calls.append(kwargs))
    assert main(["serve", "--presenter-token", "lecture-7", "--port", "8124", "--workers", "1"]) == 0
    assert calls[-1]["presenter_token"] == "lecture-7"
    assert main(["serve", "--presenter", "--port", "8124", "--workers", "1"]) == 0
    token = calls[-1]["presenter_token"]
    assert isinstance(token, str) and len(token) >= 10  # a random one
    assert main(["serve", "--presenter", "--port", "8124", "--workers", "1"]) == 0
    assert calls[-1]["presenter_token"] != token
    assert main(["serve", "--presenter-token", "   ", "--port", "8124", "--workers", "1"]) == 2
    assert "--presenter-token" in capsys.readouterr().err


def test_serve_passes_the_chain_to_the_app(monkeypatch, forked):
    import app.server

    calls = []
    monkeypatch.setattr(app.server, "serve", lambda **kwargs: calls.append(kwargs))
    assert (
        main(
            [
                "serve",
                "--urdf",
                str(forked),
                "--base",
                "base",
                "--tip",
                "aux",
                "--port",
                "8123",
                "--workers",
                "1",
                "--trusted-proxy",
                "127.0.0.1",
            ]
        )
        == 0
    )
    assert calls == [
        {
            "robot": None,
            "urdf": str(forked),
            "base_link": "base",
            "tip_link": "aux",
            "host": "127.0.0.1",
            "port": 8123,
            "block": True,
            "presenter_token": None,
            "allow_origin": [],
            "xacro_args": None,
            "language": "",
            "trusted_proxy": ["127.0.0.1"],
            "package_dirs": None,
            "package_path": [],
        }
    ]


def test_serve_lang_sets_the_rooms_language(monkeypatch):
    import app.server

    calls = []
    monkeypatch.setattr(app.server, "serve", lambda **kw: calls.append(kw))
    assert main(["serve", "--lang", "pl", "--port", "8123", "--workers", "1"]) == 0
    assert calls[0]["language"] == "pl"
    assert main(["serve", "--lang", "fr"]) == 2  # argparse: not one of en, pt, es, pl


# ------------------------------------------------------------------ export
def test_export_json_to_stdout(capsys):
    assert main(["export", "planar2", "--format", "json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["robot"] == "planar2" and doc["shape"] == [6, 2]
    assert [j["name"] for j in doc["joints"]] == ["q1", "q2"]


def test_export_python_to_a_file(tmp_path, capsys):
    out = tmp_path / "J.py"
    assert (
        main(["export", "trr", "--format", "python", "--symbolic-params", "--frame", "tool", "-o", str(out)])
        == 0
    )
    assert capsys.readouterr().out == ""
    module = import_source(tmp_path / "J_trr.py", out.read_text(), "J_trr_cli")
    assert module.FRAME == "tool" and "l2" in module.PARAMETERS


def test_export_accepts_a_robot_file_path(tmp_path, capsys):
    dst = tmp_path / "planar3.toml"
    dst.write_text((robots.DATA_DIR / "planar3.toml").read_text())
    assert main(["export", str(dst), "-f", "latex"]) == 0
    assert "\\begin{bmatrix}" in capsys.readouterr().out


def test_export_of_a_urdf_chain_chosen_by_tip(tmp_path, capsys, forked):
    assert main(["export", str(forked), "--format", "python", "-o", str(tmp_path / "default.py")]) == 0
    default = import_source(tmp_path / "J_default.py", (tmp_path / "default.py").read_text(), "J_default")
    q = np.array([0.3, -0.7])
    np.testing.assert_allclose(default.J(q), jacobian(robot_from_urdf(forked), q), atol=1e-12)
    assert main(["export", str(forked), "--format", "json", "--tip", "aux"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert [j["name"] for j in doc["joints"]] == ["aux_joint"] and doc["entries"][0] == ["1"]


def test_export_errors(tmp_path, capsys, forked):
    assert main(["export", "no_such_robot"]) == 1
    err = capsys.readouterr().err
    assert "unknown robot 'no_such_robot'" in err and "puma560" in err
    assert main(["export", "planar2", "--format", "pdf"]) == 2
    assert "invalid choice: 'pdf'" in capsys.readouterr().err
    assert main(["export", "planar2", "-o", str(tmp_path / "missing" / "J.tex")]) == 1
    assert "cannot write" in capsys.readouterr().err
    assert main(["export", "planar2", "--timeout", "-3"]) == 2  # a usage error, as argparse's own
    assert "--timeout: expected a number more than 0" in capsys.readouterr().err
    assert main(["export", str(forked), "--tip", "nowhere"]) == 1
    assert "unknown tip_link 'nowhere'" in capsys.readouterr().err
    assert main(["export", "--help"]) == 0
    assert "--tip LINK" in capsys.readouterr().out


def test_progress_only_after_a_second():
    quiet = io.StringIO()
    with export_command._StderrProgress(quiet, after=1.0) as progress:
        progress("fast step")
    assert quiet.getvalue() == ""
    slow = io.StringIO()
    with export_command._StderrProgress(slow, after=0.05) as progress:
        progress("simplifying J: entry 3/36")
        poll(lambda: "simplifying" in slow.getvalue(), what="the progress line")
    lines = slow.getvalue().splitlines()
    assert "simplifying J: entry 3/36" in lines[0]
    assert lines[-1].endswith("done")
