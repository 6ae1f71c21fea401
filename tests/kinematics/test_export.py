"""Exports of the symbolic Jacobian (Python module, JSON, MathML) and the ``export`` command line."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from fakes import random_configurations
from kinematics_helpers import import_source

import kinematics
import robots
from kinematics.symbolic import jacobian_mathml
from kinematics.symbolic.typeset import export as ex

MATHML = "{http://www.w3.org/1998/Math/MathML}"


@pytest.mark.slow
@pytest.mark.parametrize(
    "name, frame, params",
    [
        ("puma560", "base", False),
        ("stanford", "tool", False),
        ("panda", "base", False),
        ("elbow3r", "base", True),
        ("trr", "tool", True),
    ],
)
def test_python_module_matches_numeric_jacobian(tmp_path, name, frame, params):
    robot = robots.load(name)
    module = import_source(tmp_path / f"J_{name}.py", ex.export(robot, "python", frame, params), f"J_{name}")
    assert module.ROBOT == name and module.FRAME == frame and module.FINGERPRINT == robot.fingerprint()
    qs = random_configurations(robot, 4, seed=3)
    for q in qs:
        np.testing.assert_allclose(module.J(q), kinematics.jacobian(robot, q, frame), atol=1e-9, rtol=0)
    np.testing.assert_allclose(
        module.J(qs), kinematics.jacobian(robot, qs, frame), atol=1e-9, rtol=0
    )  # batch
    with pytest.raises(ValueError, match="shape"):
        module.J(np.zeros(robot.dof + 1))
    if params:  # parameters are keyword arguments with their values as defaults: doubling every
        assert module.PARAMETERS  # length doubles the linear velocities of the revolute joints
        scaled = module.J(qs[0], **{k: 2 * v for k, v in module.PARAMETERS.items()})
        rev = [k == "revolute" for k in robot.joint_types]
        np.testing.assert_allclose(scaled[:3, rev], 2 * module.J(qs[0])[:3, rev], atol=1e-12)


def test_python_module_shares_subexpressions():
    text = ex.export(robots.load("panda"), "python")
    functions = text.split("\ndef ")[1:]  # J, T and Jdot: each computes sin q1 once
    assert [f.split("(")[0] for f in functions] == ["J", "T", "Jdot"]
    assert all(f.count("numpy.sin(q1)") == 1 for f in functions) and "x0 = " in text


def test_json_export():
    robot = robots.load("elbow3r")
    doc = json.loads(ex.export(robot, "json", symbolic_params=True))
    assert doc["robot"] == "elbow3r" and doc["shape"] == [6, 3] and doc["frame"] == "base"
    assert doc["parameters"] == {"L1": 0.2, "L2": 0.5, "L3": 0.4}
    assert doc["entries"][2][1] == "L2*cos(q2) + L3*cos(q2 + q3)"
    assert [j["symbol"] for j in doc["joints"]] == ["q1", "q2", "q3"]
    assert doc["determinant"]["rows"] == ["vx", "vy", "vz"]
    assert {s["kind"] for s in doc["determinant"]["singular_sets"]} == {"elbow", "shoulder"}
    assert "c_{23}" in doc["latex"]["matrix"] and doc["simplified"] is True


def parse_math(fragment):
    return ET.fromstring(f'<div xmlns="http://www.w3.org/1998/Math/MathML">{fragment}</div>')


def test_jacobian_mathml_for_the_app():
    text = jacobian_mathml(robots.load("puma560"), "base", timeout=30)
    assert text.startswith('<math display="block"')
    root = parse_math(text.replace("<math", "<math xmlns='http://www.w3.org/1998/Math/MathML'"))
    assert root.find(f".//{MATHML}mtable") is not None
    subs = {"".join(e.itertext()) for e in root.iter(f"{MATHML}msub")}
    assert {"s23", "c1", "c23"} <= subs  # compact notation
    assert 'class="jl-legend"' in text and "cos" in text


@pytest.mark.slow
def test_wide_jacobians_are_shown_column_by_column():
    """A 7-joint arm's J is too wide to read as one matrix: the app gets J1 … J7, one block each."""
    panda = robots.load("panda")
    text = jacobian_mathml(panda, "base", timeout=60)
    blocks = [b for b in text.split("\n") if b.startswith('<math display="block"')]
    assert len(blocks) == panda.dof
    for j, block in enumerate(blocks, start=1):
        root = parse_math(block.replace("<math", "<math xmlns='http://www.w3.org/1998/Math/MathML'", 1))
        first = root.find(f".//{MATHML}msub")
        assert "".join(first.itertext()) == f"J{j}"  # J_j = [...]
    puma = jacobian_mathml(robots.load("puma560"), "base", timeout=30, layout="columns")
    assert puma.count('<math display="block"') == 6
    with pytest.raises(ValueError, match="layout must be"):
        jacobian_mathml(panda, layout="rows")


def test_mathml_page_is_well_formed():
    page = ex.export(robots.load("stanford"), "mathml", "tool")
    assert page.startswith("<!DOCTYPE html>")
    body = page[page.index("<body>") + 6 : page.index("</body>")]
    root = ET.fromstring(f"<body>{body}</body>")
    assert len(root.findall("math")) >= 1 + 6 + 1  # J, six columns, det
    assert "wrist singularity" in page


def test_export_rejects_bad_input():
    robot = robots.load("planar2")
    with pytest.raises(ex.ExportError, match="format must be one of"):
        ex.export(robot, "pdf")
    with pytest.raises(kinematics.JacobianLabError, match="frame"):
        ex.export(robot, "latex", frame="world")
    with pytest.raises(ex.ExportError, match="kinematics.Robot"):
        ex.export("planar2", "latex")


# ------------------------------------------------------------------------- CLI


def test_the_apps_download_buttons_name_formats_the_export_writes():
    """app.core.downloads keeps the button label → format table out of kinematics.symbolic (SymPy
    stays out of the server process); every format it names is one the export writes."""
    from app.core.downloads import EXPORT_FORMATS

    assert EXPORT_FORMATS and {fmt for fmt, _ in EXPORT_FORMATS.values()} <= set(ex.FORMATS)
    assert len({ext for _, ext in EXPORT_FORMATS.values()}) == len(EXPORT_FORMATS)
