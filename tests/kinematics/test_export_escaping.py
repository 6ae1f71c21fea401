"""Hostile names in robot files come out of every export as text: never code, markup or broken JSON."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from test_export_latex import display_formulas, katex  # noqa: F401  (katex is a fixture)

import kinematics
from kinematics.model import Axis, Joint, Robot
from kinematics.symbolic import jacobian_mathml
from kinematics.symbolic.typeset import export as ex
from kinematics.symbolic.typeset.escape import latex_text, plain, py_docstring, py_identifier, xml_text
from kinematics.transforms import rot_x, trans

INJECT = '"""; import os; os.system("touch MARKER")#'
SCRIPT = "</math><script>alert(1)</script>"
TEX = "\\input{/etc/passwd}"
HOSTILE = [INJECT, SCRIPT, TEX, "$\\", "two\nlines\x00nul & 100% #1 ^ ~ _ {x}"]


def hostile_robot() -> Robot:
    """A 3R arm whose every name is hostile, with twists written as 1.5708 (so that the notes on
    snapped values carry the joint names too)."""
    names = [f"{HOSTILE[k]} {k}" for k in (0, 1, 4)]
    T = [trans(z=0.3), trans(x=0.25) @ rot_x(1.5708), trans(x=0.2) @ rot_x(-1.5708)]
    axes = tuple(Axis(n, "revolute", i, 1.0, 0.0, T[i], np.eye(4)) for i, n in enumerate(names))
    return Robot(
        name=INJECT,
        joints=tuple(Joint(n, "revolute", (-3.0, 3.0)) for n in names),
        axes=axes,
        tool=trans(x=0.1),
        title=SCRIPT,
        description=TEX,
        source=HOSTILE[3] + HOSTILE[4],
    )


@pytest.fixture(scope="module")
def robot():
    return hostile_robot()


def test_escape_functions():
    assert plain("a\nb\x00c\u2028d") == "a b c d"
    assert latex_text("\\{}$%#&_^~") == (
        "\\textbackslash{}\\{\\}\\$\\%\\#\\&\\_\\textasciicircum{}\\textasciitilde{}"
    )
    assert xml_text(SCRIPT) == "&lt;/math&gt;&lt;script&gt;alert(1)&lt;/script&gt;"
    assert '"' not in py_docstring(INJECT) and "\\" not in py_docstring(TEX)
    assert [py_identifier(x) for x in ("class", "2a", "a-b", "")] == ["class_", "_2a", "a_b", "name"]


def test_python_module_never_runs_injected_code(robot, tmp_path):
    text = ex.export(robot, "python")
    (tmp_path / "hostile_J.py").write_text(text, encoding="utf-8")
    q = [0.3, -0.8, 1.2]
    probe = (
        "import json, hostile_J as m; "
        f"print(json.dumps([m.J({q}).tolist(), m.ROBOT, m.TITLE, m.SOURCE, list(m.JOINT_NAMES), list(m.NOTES)]))"
    )
    done = subprocess.run(
        [sys.executable, "-c", probe], cwd=tmp_path, capture_output=True, text=True, timeout=60, check=True
    )
    assert not (tmp_path / "MARKER").exists()
    J, name, title, source, joint_names, notes = json.loads(done.stdout)
    assert (name, title, source, joint_names) == (INJECT, SCRIPT, robot.source, list(robot.joint_names))
    # the module's J is the robot's J (to the size of the snap: 1.5708 is 3.7e-6 from pi/2)
    np.testing.assert_allclose(J, kinematics.jacobian(robot, np.array(q)), atol=5e-6, rtol=0)
    assert len(notes) == 1 and "snapped" in notes[0] and "largest change 3.7e-06 rad" in notes[0]


@pytest.mark.slow
def test_latex_typesets_and_keeps_names_in_text(robot, katex):  # noqa: F811
    text = ex.export(robot, "latex")
    formulas = display_formulas(text)
    assert [e for e in katex(formulas) if e is not None] == []
    outside = re.sub(r"\\\[.*?\\\]", "", text, flags=re.S)
    assert all(line.startswith("%") or re.fullmatch(r"[A-Za-z ,:]*", line) for line in outside.splitlines())
    assert "\\input{" not in text and "\x00" not in text
    legend = next(f for f in formulas if f.startswith("\\text{where"))
    assert latex_text(robot.joint_names[1]) in legend and latex_text(robot.joint_names[2]) in legend


def test_mathml_page_has_no_markup_from_names(robot):
    page = ex.export(robot, "mathml")
    body = page[page.index("<body>") + 6 : page.index("</body>")]
    root = ET.fromstring(f"<body>{body}</body>")  # well-formed XML despite NUL and </math>
    assert [e for e in root.iter() if e.tag.split("}")[-1] == "script"] == []
    assert "".join(root.find("h1").itertext()) == f"Symbolic Jacobian of {plain(INJECT)} ({SCRIPT})"
    texts = {"".join(e.itertext()) for e in root.iter() if e.tag.endswith("mtext")}
    assert f":\xa0{plain(robot.joint_names[1])}" in texts  # the name shown as text, in the legend
    head = page[: page.index("<body>")]
    assert "<script" not in head and "&lt;script&gt;" in head


def test_app_mathml_has_no_markup_from_names(robot):
    text = jacobian_mathml(robot, timeout=30)
    root = ET.fromstring(
        f"<div>{text}</div>".replace("<math", "<math xmlns='http://www.w3.org/1998/Math/MathML'")
    )
    assert [e for e in root.iter() if e.tag.split("}")[-1] == "script"] == []
    notes = ["".join(p.itertext()) for p in root.iter("p") if p.get("class") == "jl-note"]
    assert any(plain(robot.joint_names[1], 60) in n and "snapped" in n for n in notes)


def test_json_round_trips_every_name(robot):
    doc = json.loads(ex.export(robot, "json"))
    assert (doc["robot"], doc["title"], doc["source"]) == (INJECT, SCRIPT, robot.source)
    assert [j["name"] for j in doc["joints"]] == list(robot.joint_names)
    assert [s["where"] for s in doc["snapped"]] == [
        f"joint {plain(robot.joint_names[k], 60)!r}: fixed rotation" for k in (1, 2)
    ]
    assert all(abs(s["change"] - 3.67e-6) < 1e-8 and s["unit"] == "rad" for s in doc["snapped"])


def test_dh_robot_with_hostile_joint_names_and_parameters(tmp_path):
    rows = [
        dict(joint="revolute", a=0.4, alpha=1.5707963267948966, d=0.2, theta=0.0, name=HOSTILE[3]),
        dict(joint="prismatic", a=0.0, alpha=0.0, d=0.1, theta=0.0, name=HOSTILE[4]),
    ]
    robot = Robot.from_dh(rows, name=TEX)
    text = ex.export(robot, "python", symbolic_params=True)
    (tmp_path / "dh_J.py").write_text(text, encoding="utf-8")
    probe = (
        "import json, dh_J as m; print(json.dumps([m.J([0.4, 0.3]).tolist(), m.ROBOT, sorted(m.PARAMETERS)]))"
    )
    done = subprocess.run(
        [sys.executable, "-c", probe], cwd=tmp_path, capture_output=True, text=True, timeout=60, check=True
    )
    J, name, params = json.loads(done.stdout)
    assert name == TEX and params == ["a1", "d1", "d20"]
    np.testing.assert_allclose(J, kinematics.jacobian(robot, np.array([0.4, 0.3])), atol=1e-12)
