"""The wheel: built by ``python -m build`` into a temporary folder, installed into a fresh virtual
environment, and run from outside the source tree (its robot files shipped as package data)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import sysconfig
import venv
from pathlib import Path

import pytest

pytest.importorskip("build")

ROOT = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.slow


def _run(args: list[str], cwd: Path, env: dict[str, str]) -> subprocess.CompletedProcess[str]:
    done = subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, f"{args}: {done.stdout}\n{done.stderr}"
    return done


def test_the_wheel_installs_in_a_fresh_venv_and_runs_from_it(tmp_path):
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV")}
    # a copy of the tracked sources, so the build leaves nothing in the worktree (`python -m build` as a
    # user runs it: setuptools in an isolated environment)
    src = tmp_path / "src"
    files = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True)
    for name in files.stdout.splitlines():
        if (ROOT / name).is_file():
            (src / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / name, src / name)
    dist = tmp_path / "dist"
    _run(
        [sys.executable, "-m", "build", "--wheel", "--outdir", str(dist)],
        src,
        env,
    )
    (wheel,) = dist.glob("jacobian_lab-*.whl")
    # a fresh venv holding only the wheel (no dependency resolution: no network) ...
    home = tmp_path / "venv"
    venv.create(home, with_pip=True)
    py = home / "bin" / "python"
    _run([str(py), "-m", "pip", "install", "--no-deps", "--no-index", str(wheel)], tmp_path, env)
    # ... then the dependencies from this interpreter's site-packages as a plain path (its .pth files, the
    # editable install of the source tree among them, are not run from there)
    site = Path(
        _run(
            [str(py), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"], tmp_path, env
        ).stdout.strip()
    )
    (site / "zz_dependencies.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    where = _run(
        [
            str(py),
            "-c",
            "import app, kinematics, robots; print(app.__file__); print(robots.library.DATA_DIR)",
        ],
        elsewhere,
        env,
    ).stdout.split()
    assert all(Path(p).resolve().is_relative_to(home.resolve()) for p in where), where
    cli = home / "bin" / "jacobian-lab"
    assert "serve" in _run([str(cli), "--help"], elsewhere, env).stdout
    doc = json.loads(_run([str(cli), "export", "planar2", "-f", "json"], elsewhere, env).stdout)
    assert doc["robot"] == "planar2" and doc["shape"] == [6, 2]  # read from the wheel's robots/data
    names = _run([str(py), "-c", "import robots; print(robots.names())"], elsewhere, env).stdout
    assert "puma560" in names and "trr" in names
    # the compiled catalogs ride in the wheel: a Polish tab speaks Polish from the installed package
    polish = _run(
        [
            str(py),
            "-c",
            "from app.core.i18n import LOCALE_DIR, translations; print(LOCALE_DIR); "
            "print(translations('pl').gettext('the box is empty: type a number'))",
        ],
        elsewhere,
        env,
    ).stdout.splitlines()
    assert (
        Path(polish[0]).resolve().is_relative_to(home.resolve())
        and polish[1] == "pole jest puste: wpisz liczbę"
    )
