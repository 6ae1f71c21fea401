"""The exported LaTeX typesets in a real renderer: KaTeX (``throwOnError``, strict mode) under Node.

Needs ``node`` and KaTeX from ``tests/katex`` (``npm ci`` is run there when
``node_modules`` is missing). Without them the test is skipped locally but
FAILS when ``CI`` is set: in CI the renderer must be there.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess

import pytest
from locations import DATA, KATEX

import kinematics
import robots
from kinematics.symbolic.typeset import export as ex

KATEX_DIR = KATEX


def _unavailable(reason: str):
    if os.environ.get("CI"):
        pytest.fail(f"LaTeX renderer unavailable in CI: {reason}")
    pytest.skip(reason)


@pytest.fixture(scope="module")
def katex():
    """A function rendering a list of LaTeX formulas with KaTeX; returns the error of each (None if ok)."""
    node = shutil.which("node")
    if node is None:
        _unavailable("node is not installed (apt-get install nodejs)")
    if not (KATEX_DIR / "node_modules" / "katex").is_dir():
        npm = shutil.which("npm")
        if npm is None:
            _unavailable("npm is not installed, cannot install KaTeX (apt-get install npm)")
        done = subprocess.run(
            [npm, "ci", "--no-audit", "--no-fund"], cwd=KATEX_DIR, capture_output=True, text=True, timeout=300
        )
        if done.returncode != 0:
            _unavailable(f"npm ci failed in {KATEX_DIR}: {done.stderr[-500:]}")

    def render(formulas: list[str]) -> list[str | None]:
        done = subprocess.run(
            [node, str(KATEX_DIR / "render.cjs")],
            input=json.dumps(formulas),
            capture_output=True,
            text=True,
            timeout=120,
            check=True,
        )
        return [r["error"] for r in json.loads(done.stdout)]

    return render


def display_formulas(latex: str) -> list[str]:
    """The formulas between \\[ and \\] of an exported LaTeX fragment."""
    return [m.strip() for m in re.findall(r"\\\[(.*?)\\\]", latex, flags=re.S)]


def test_renderer_rejects_bad_latex(katex):
    good, bad = katex(["\\begin{bmatrix} a \\\\ b \\end{bmatrix}", "\\frac{1}{"])
    assert good is None and "parse error" in bad


@pytest.mark.slow
@pytest.mark.parametrize(
    "name, params",
    [
        ("puma560", False),
        ("stanford", False),
        ("panda", False),
        ("puma560", True),
        ("planar2", True),
        ("wrist", False),
    ],
)
def test_exported_latex_typesets(katex, name, params):
    text = ex.export(robots.load(name), "latex", symbolic_params=params)
    formulas = display_formulas(text)
    robot = robots.load(name)
    assert len(formulas) >= 2 + robot.dof + 1  # J, legend, one per column, det J
    errors = [(f[:80], e) for f, e in zip(formulas, katex(formulas), strict=True) if e is not None]
    assert errors == []
    # everything outside the displays is plain text or a comment
    outside = re.sub(r"\\\[.*?\\\]", "", text, flags=re.S)
    assert all(line.startswith("%") or re.fullmatch(r"[A-Za-z ,:]*", line) for line in outside.splitlines())


@pytest.mark.slow
def test_written_out_angles_typeset(katex):
    rows = [
        dict(joint="revolute", a=0.1 * (i + 1), alpha=0.3 * (i + 1), d=0.05 * i, theta=0.2 * i)
        for i in range(3)
    ]
    text = ex.export(kinematics.Robot.from_dh(rows, name="odd3"), "latex")
    assert "\\sin{\\left(\\theta_{2} + 0.2 \\right)}" in text
    formulas = display_formulas(text)
    assert [e for e in katex(formulas) if e is not None] == []


def test_compact_notation_and_legend():
    text = ex.export(robots.load("puma560"), "latex")
    assert "c_{23}" in text and "s_{1}" in text and "\\sin" not in text.split("where")[0]
    assert "c_{ij} = \\cos (\\theta_{i} + \\theta_{j})" in text
    assert "\\det J = " in text and "wrist singularity" in text


@pytest.mark.slow
@pytest.mark.parametrize("name", ["iiwa14_like", "xarm7_like"])
def test_real_arm_urdf_latex_typesets(katex, name):
    """URDF arms with 1.5708-style angles: snapped, short, and the joint-name legend typesets."""
    robot = kinematics.robot_from_urdf(str(DATA / f"{name}.urdf"))
    text = ex.export(robot, "latex", timeout=120)
    formulas = display_formulas(text)
    assert [e for e in katex(formulas) if e is not None] == []
    assert len(text) < 40_000 and "% Note: 6 value(s) of the robot file snapped" in text
    legend = next(f for f in formulas if f.startswith("\\text{where"))
    escaped = [n.replace("_", "\\_") for n in robot.joint_names]
    assert all(f"\\text{{: {n}}}" in legend for n in escaped)
