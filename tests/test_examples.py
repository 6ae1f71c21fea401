"""The notebooks of examples/, executed on a real Jupyter kernel (nbclient), their printed numbers checked
against the course and against kinematics computed here."""

from __future__ import annotations

import os
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")
pytest.importorskip("matplotlib")

import robots  # noqa: E402
from kinematics import fk, jacobian, select_rows, singular_values, task_rows  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
NUMBER = re.compile(r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?")

pytestmark = pytest.mark.slow


def _run(name: str, tmp_path: Path, monkeypatch) -> dict[str, str]:
    """Execute examples/NAME in a copy of the folder; the text each tagged cell printed, by tag."""
    work = tmp_path / "examples"
    shutil.copytree(EXAMPLES, work, ignore=shutil.ignore_patterns("*.c", "*.h", ".ipynb_checkpoints"))
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))
    monkeypatch.setenv("MPLBACKEND", "Agg")
    for var in ("VSCODE_PID", "VSCODE_CWD", "COLAB_RELEASE_TAG"):  # a Jupyter kernel: the player beside
        monkeypatch.delenv(var, raising=False)
    book = nbformat.read(work / name, as_version=4)
    nbclient.NotebookClient(
        book, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(work)}}
    ).execute()
    out: dict[str, str] = {}
    for cell in book.cells:
        if cell.cell_type != "code":
            continue
        assert not [o for o in cell.outputs if o.output_type == "error"], cell.source
        text = "".join(
            o.get("text", "") if o.output_type == "stream" else o.get("data", {}).get("text/plain", "")
            for o in cell.outputs
        )
        for tag in cell.metadata.get("tags", []):
            out[tag] = text
        out.setdefault("_html", "")
        out["_html"] += "".join(o.get("data", {}).get("text/html", "") for o in cell.outputs)
    out["_dir"] = str(work)
    return out


def _numbers(text: str) -> np.ndarray:
    return np.array([float(x) for x in NUMBER.findall(text)])


def _after(text: str, label: str) -> str:
    """The text after ``label`` up to the next labelled line."""
    rest = text.split(label, 1)[1]
    return re.split(r"\n(?=[A-Za-zJ])", rest.lstrip("\n"), maxsplit=1)[0]


def test_every_example_is_checked_here():
    assert sorted(p.name for p in EXAMPLES.glob("*.ipynb")) == sorted(CHECKED)


def test_the_trr_worked_example_and_a_urdf(tmp_path, monkeypatch):
    out = _run("01_trr_and_a_urdf.ipynb", tmp_path, monkeypatch)
    trr = robots.load("trr")
    rows = task_rows(trr)
    J = select_rows(jacobian(trr, trr.configuration("home")), rows)
    worked = out["worked-example"]
    np.testing.assert_allclose(_numbers(_after(worked, "J =")), J.ravel(), atol=6e-5)
    # the course's figures: v = (17.256, -20.13, 0.500) m/s and det J = l2 l3 sin 15° = 10.35
    np.testing.assert_allclose(_numbers(_after(worked, "v =")), [17.2556, -20.1304, 0.5], atol=1e-4)
    assert float(_numbers(_after(worked, "det J ="))[0]) == pytest.approx(
        40 * np.sin(np.radians(15)), abs=1e-4
    )
    question = out["course-question"]
    Jq = select_rows(jacobian(trr, trr.configuration("course_question")), rows)
    np.testing.assert_allclose(_numbers(_after(question, "J =")), Jq.ravel(), atol=6e-5)
    # the course's answer: det J = 20, J⁻¹ = [[0, 0, 1], [0, -0.4, 0], [0.125, 0.6165, 0]]
    assert float(_numbers(_after(question, "det J ="))[0]) == pytest.approx(20.0, abs=1e-4)
    np.testing.assert_allclose(
        _numbers(_after(question, "J⁻¹ =")), [0, 0, 1, 0, -0.4, 0, 0.125, 0.6165, 0], atol=1e-4
    )
    urdf = out["urdf"]
    ur5 = robots.load(EXAMPLES / "ur5.urdf")
    q = np.array([0.3, -1.2, 1.5, -0.6, 1.1, 0.4])
    np.testing.assert_allclose(_numbers(_after(urdf, "J =")), jacobian(ur5, q).ravel(), atol=6e-5)
    assert float(_numbers(_after(urdf, "finite differences:"))[0]) < 1e-8
    assert fk(ur5, q).shape == (4, 4)


def test_the_symbolic_jacobian_as_latex_and_c(tmp_path, monkeypatch):
    out = _run("02_symbolic_latex_and_c.ipynb", tmp_path, monkeypatch)
    trr = robots.load("trr")
    rows = task_rows(trr)
    J = select_rows(jacobian(trr, trr.configuration("home")), rows)
    at_q = out["symbolic-at-q"]
    np.testing.assert_allclose(_numbers(at_q.split("largest")[0]), J.ravel(), atol=1e-7)
    assert float(_numbers(_after(at_q, "numeric J:"))[0]) < 1e-12
    work = Path(out["_dir"])
    header, source = (work / "trr_jacobian.h").read_text(), (work / "trr_jacobian.c").read_text()
    assert "void trr_jacobian(const double q[3], double J[18]);" in header
    assert '#include "trr_jacobian.h"' in source and "void trr_jacobian(" in source
    assert header.strip() in out["c-export"]


def test_the_puma_singularities_swept(tmp_path, monkeypatch):
    out = _run("03_puma_singularities.ipynb", tmp_path, monkeypatch)
    puma = robots.load("puma560")
    named = dict(line.split(None, 1) for line in out["named"].strip().splitlines())
    assert named["home"] == "regular"
    assert named["wrist_singular"] == "singular: wrist"
    assert named["elbow_singular"] == "singular: elbow"
    assert named["shoulder_singular"] == "singular: shoulder"
    # the sweeps, recomputed here one configuration at a time
    sweep = np.linspace(-np.pi / 2, np.pi / 2, 721)
    home = puma.configuration("home")
    for joint, tag in ((4, "wrist-sweep"), (2, "elbow-sweep")):
        sigma = []
        for x in sweep:
            q = home.copy()
            q[joint] = x
            sigma.append(singular_values(jacobian(puma, q))[-1])
        at, smallest = _numbers(out[tag].split("smallest at")[1])[1:3]
        assert at == pytest.approx(np.degrees(sweep[int(np.argmin(sigma))]), abs=0.01)
        assert smallest == pytest.approx(min(sigma), rel=0.01, abs=1e-15)
    assert float(_numbers(out["wrist-sweep"].split("q5 =")[1])[0]) == 0.0  # the wrist: q5 = 0


def test_the_live_app_and_a_recorded_demo_in_cells(tmp_path, monkeypatch):
    out = _run("04_live_app_and_a_recorded_demo.ipynb", tmp_path, monkeypatch)
    assert re.search(r'<iframe data-src="http://127\.0\.0\.1:\d+/"', out["_html"])
    assert "serving http://127.0.0.1:" in out["live"]
    np.testing.assert_allclose(_numbers(out["set-q"].split("\n")[0]), [0, 0.4, -0.2, 0, 0, 0])
    assert "singular: wrist" in out["set-q"] and "rank J = 5" in out["set-q"]
    assert re.search(r'var data="[A-Za-z0-9+/=]{1000,}"', out["_html"])  # the recording, inside the cell
    assert [p.suffix for p in (Path(out["_dir"]) / "jacobian-lab-player").iterdir()] == [
        ".html"
    ]  # its player
    assert "61 frames, 4.0 s" in out["recorded"]
    assert "viser" not in out["live"] + out["recorded"]  # no server banner in the cells


def test_the_pandas_null_space_self_motion_and_climb(tmp_path, monkeypatch):
    """The course's self-motion and q̇ = (I − J⁺J)∇w, checked independently of redundancy.py: the
    printed null direction against an SVD here, the tool held (fk here), w recomputed here."""
    out = _run("05_panda_null_space.ipynb", tmp_path, monkeypatch)
    panda = robots.load("panda")
    q0 = panda.configuration("home")
    J = jacobian(panda, q0)
    assert "J is (6, 7) of rank 6 ; null space dimension 1" in out["null"]
    direction = _numbers(_after(out["null"], "null direction =").split("\n")[0])
    assert np.linalg.norm(J @ direction) < 1e-3  # printed to 4 decimals
    assert abs(abs(direction @ np.linalg.svd(J)[2][-1]) - 1) < 1e-3
    assert float(_numbers(_after(out["null"], "|J q̇| for that direction ="))[0]) < 1e-12

    moved = out["self-motion"]
    assert float(_numbers(_after(moved, "largest joint change ="))[0]) > 0.5  # the arm really moves
    drift, turn = _numbers(_after(moved, "tool drift ="))[:2]
    assert drift < 1e-9 and turn < 1e-9
    dq = _numbers(_after(moved, "joints moved [rad] =").split("\n")[0])
    q_end = q0 + dq  # rounded to 3 decimals: the tool within a few mm of where it was
    assert np.linalg.norm(fk(panda, q_end)[:3, 3] - fk(panda, q0)[:3, 3]) < 5e-3

    up = out["climb"]
    before, after = _numbers(_after(up, "w before ="))[:2]
    assert after > before and "w never decreased: True" in up
    assert float(_numbers(_after(up, "tool drift ="))[0]) < 1e-9
    rows = task_rows(panda)
    w_here = np.sqrt(np.linalg.det(select_rows(J, rows) @ select_rows(J, rows).T))
    assert f"from {w_here:.4f}" in moved  # the self-motion starts at home's w, recomputed here


CHECKED = (
    "01_trr_and_a_urdf.ipynb",
    "02_symbolic_latex_and_c.ipynb",
    "03_puma_singularities.ipynb",
    "04_live_app_and_a_recorded_demo.ipynb",
    "05_panda_null_space.ipynb",
)
