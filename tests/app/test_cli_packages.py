"""``--package NAME=DIR`` and ``--package-path DIR`` on the command line (issue 30): defined once for
``serve`` and ``export`` (and ``handout``, ``record``), checked as argparse reads them, given to
:func:`robots.load`, to the one-process server and to every worker process of the default ``serve``; a
misspelt ``--xacro-arg`` is refused before anything starts."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading

import pytest
from fakes import POLL_TIMEOUT
from server_process import ROOT
from xacro_helpers import make_kuka

from app.cli.main import main
from app.cli.workers import default_workers


@pytest.fixture
def kuka(tmp_path, monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    return make_kuka(tmp_path)


def test_export_takes_package_and_package_path(kuka, tmp_path, capsys):
    out = tmp_path / "J.json"
    folder = kuka.parents[1]
    assert main(["export", str(kuka), "-f", "json", "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert "no package 'kuka_kr6_support' found" in err and "--package kuka_kr6_support=DIR" in err
    argv = ["export", str(kuka), "-f", "json", "-o", str(out), "--package", f"kuka_kr6_support={folder}"]
    assert main([*argv, "--xacro-arg", "prefix:=r_"]) == 0
    assert [j["name"] for j in json.loads(out.read_text())["joints"]] == ["r_joint_a1", "r_joint_a6"]
    (folder / "package.xml").write_text("<package><name>kuka_kr6_support</name></package>")
    out.unlink()
    assert (
        main(["export", str(kuka), "-f", "json", "-o", str(out), "--package-path", str(folder.parent)]) == 0
    )
    assert json.loads(out.read_text())["robot"] == "kuka_kr6"


@pytest.mark.parametrize(
    ("option", "words"),
    [
        (["--package", "kuka_kr6_support"], "expected NAME=DIR"),
        (["--package", "a/b=."], "is not a package name"),
        (["--package", "kuka_kr6_support=/no/such/folder"], "'/no/such/folder' is not a folder"),
        (["--package-path", "/no/such/folder"], "'/no/such/folder' is not a folder"),
    ],
)
@pytest.mark.parametrize("command", ["serve", "export"])
def test_a_wrong_package_option_is_a_usage_error(kuka, capsys, option, words, command):
    robot = ["--urdf", str(kuka)] if command == "serve" else [str(kuka)]
    assert main([command, *robot, *option]) == 2
    assert words in capsys.readouterr().err


def test_a_misspelt_xacro_argument_stops_serve_before_it_starts(kuka, capsys, monkeypatch):
    import app.server

    monkeypatch.setattr(app.server, "serve", lambda **kw: pytest.fail("started"))
    folder = kuka.parents[1]
    argv = ["serve", "--urdf", str(kuka), "--package", f"kuka_kr6_support={folder}", "--workers", "1"]
    assert main([*argv, "--xacro-arg", "prefx:=r_"]) == 2
    assert (
        "xacro argument prefx is not an argument of the file; it declares: prefix" in capsys.readouterr().err
    )


def test_serve_gives_the_packages_to_the_server_and_to_the_worker_processes(kuka, monkeypatch):
    import app.cli.workers
    import app.server

    single: list[dict] = []
    pooled: list[dict] = []
    monkeypatch.setattr(app.server, "serve", lambda **kw: single.append(kw))
    monkeypatch.setattr(
        app.cli.workers, "serve_workers", lambda n, options, **kw: pooled.append(options) or 0
    )
    folder = str(kuka.parents[1])
    argv = ["serve", "--urdf", str(kuka), "--package", f"kuka_kr6_support={folder}", "--port", "0"]
    argv += ["--package-path", str(kuka.parents[2])]
    assert main([*argv, "--workers", "1"]) == 0
    assert main([*argv, "--workers", "2"]) == 0
    for options in (single[0], pooled[0]):
        assert options["package_dirs"] == {"kuka_kr6_support": folder}
        assert options["package_path"] == [str(kuka.parents[2])]


@pytest.mark.slow
def test_the_default_serve_s_worker_processes_open_a_xacro_robot_through_package(kuka, tmp_path):
    """The default ``serve`` (one worker process per core here): each worker builds its Lab, which loads
    the robot anew in a spawned process; without the mapping there, no worker would start."""
    log = open(tmp_path / "serve.log", "wb")
    proc = subprocess.Popen(
        [sys.executable, "-u", "-m", "app.cli.main", "serve", "--urdf", str(kuka), "--port", "0"]
        + ["--package", f"kuka_kr6_support={kuka.parents[1]}"],
        stdout=subprocess.PIPE,
        stderr=log,
        text=True,
        cwd=ROOT,
        env={k: v for k, v in dict(os.environ, PYTHONPATH=str(ROOT)).items() if "ROS" not in k},
        start_new_session=True,
    )
    lines: list[str] = []
    printed = threading.Event()

    def read() -> None:
        assert proc.stdout is not None
        for line in proc.stdout:
            lines.append(line)
            if "open http://" in line:
                printed.set()
        printed.set()  # the process ended

    threading.Thread(target=read, daemon=True).start()
    try:
        assert printed.wait(POLL_TIMEOUT * 4), (lines, (tmp_path / "serve.log").read_text()[-2000:])
        text = "".join(lines)
        assert "open http://" in text, (text, (tmp_path / "serve.log").read_text()[-2000:])
        assert "(robot: " in text and "kr6.xacro" in text
        workers = default_workers()
        if workers > 1:
            assert f"{workers} worker processes" in text
    finally:
        os.killpg(proc.pid, signal.SIGTERM)
        try:
            proc.wait(timeout=POLL_TIMEOUT * 2)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
        log.close()
