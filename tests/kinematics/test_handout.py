"""Handouts (``jacobian-lab handout``): both formats written, every LaTeX display typesets (KaTeX),
the HTML fits a 1280 px window in Chromium with MathML, hostile names come out as text, and the
worked example and the symbolic J agree with what the course prints.

The course's formulas are typed in here from the notes in ``../shared/course/`` (an independent
derivation, not the library's output):

* 002 (UNCuyo, Robótica I), planar RR: J and J⁻¹ in a₁, a₂;
* 002, TRR: the 3×3 position J in l₂, l₃, and its worked example at q = (5 m, 60°, −15°);
* 001 (J. Rosen, UCLA), spatial 3R: the 6×3 J in frame 0 in L₁, L₂, L₃ (slides 41-42).
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest
import sympy as sp
from browser_helpers import ARGS, CHROMIUM, new_page, require_browser
from test_export_latex import display_formulas, katex  # noqa: F401  (katex is a fixture)

import robots
from app.cli.main import main as cli_main
from kinematics.symbolic import is_zero
from kinematics.symbolic.handout import handout
from kinematics.symbolic.steps import derivation_steps

q1, q2, q3 = sp.symbols("q1 q2 q3", real=True)
c, s = sp.cos, sp.sin


def _J(name: str) -> sp.Matrix:
    steps = derivation_steps(robots.load(name), "whitney", symbolic_params=True, timeout=None)
    return next(st for st in steps if st.key == "J").expr


def _same(A: sp.Matrix, B: sp.Matrix) -> bool:
    return A.shape == B.shape and all(is_zero(e, (q1, q2, q3)) for e in A - B)


# ------------------------------------------------------------------ the course's printed formulas
def test_planar_rr_agrees_with_course_002():
    a1, a2 = sp.symbols("a1 a2", real=True)
    J_course = sp.Matrix(
        [
            [-a1 * s(q1) - a2 * s(q1 + q2), -a2 * s(q1 + q2)],
            [a1 * c(q1) + a2 * c(q1 + q2), a2 * c(q1 + q2)],
        ]
    )
    J_inv_course = (1 / (a1 * a2 * s(q2))) * sp.Matrix(
        [
            [a2 * c(q1 + q2), a2 * s(q1 + q2)],
            [-a1 * c(q1) - a2 * c(q1 + q2), -a1 * s(q1) - a2 * s(q1 + q2)],
        ]
    )
    J = _J("planar2")[:2, :]
    assert _same(J, J_course)
    # the printed inverse, times our J, is the identity (after clearing the denominator a1 a2 s2)
    assert _same((a1 * a2 * s(q2)) * (J_inv_course * J), a1 * a2 * s(q2) * sp.eye(2))


def test_trr_agrees_with_course_002():
    l2, l3 = sp.symbols("l2 l3", real=True)
    J_course = sp.Matrix(
        [
            [0, l2 * c(q2) + l3 * c(q2 + q3), l3 * c(q2 + q3)],
            [0, -l2 * s(q2) - l3 * s(q2 + q3), -l3 * s(q2 + q3)],
            [1, 0, 0],
        ]
    )
    for method in ("whitney", "differentiation", "propagation", "force"):
        steps = derivation_steps(robots.load("trr"), method, symbolic_params=True, timeout=None)
        J = next(st for st in steps if st.key == "J").expr
        assert _same(J[:3, :], J_course), method


def test_spatial_3r_agrees_with_course_001():
    L1, L2, L3 = sp.symbols("L1 L2 L3", real=True)
    reach = L1 + L3 * c(q2 + q3) + L2 * c(q2)
    J_course = sp.Matrix(
        [
            [-s(q1) * reach, -c(q1) * (L3 * s(q2 + q3) + L2 * s(q2)), -L3 * c(q1) * s(q2 + q3)],
            [c(q1) * reach, -s(q1) * (L3 * s(q2 + q3) + L2 * s(q2)), -L3 * s(q1) * s(q2 + q3)],
            [0, L3 * c(q2 + q3) + L2 * c(q2), L3 * c(q2 + q3)],
            [0, s(q1), s(q1)],
            [0, -c(q1), -c(q1)],
            [1, 0, 0],
        ]
    )
    assert _same(_J("elbow3r"), J_course)


# ------------------------------------------------------------------------------- the worked example
_UNITS = r"(?:\\;\\begin\{matrix\}(.*)\\end\{matrix\})?"


def _matrices(tex: str) -> dict[str, np.ndarray]:
    """Numeric bmatrix displays of the worked example by left-hand side (a column of units beside a
    vector is left out: see :func:`_units`)."""
    out = {}
    for f in display_formulas(tex):
        m = re.fullmatch(r"(.*?) = \\begin\{bmatrix\}([-0-9.&\\ ]*)\\end\{bmatrix\}" + _UNITS, f)
        if m:
            rows = [[float(x) for x in row.split("&")] for row in m.group(2).split("\\\\")]
            out[m.group(1)] = np.array(rows)
    return out


def _units(tex: str) -> dict[str, list[str]]:
    """The units set beside each vector of the worked example, row by row, by left-hand side."""
    out = {}
    for f in display_formulas(tex):
        m = re.fullmatch(r"(.*?) = \\begin\{bmatrix\}[-0-9.&\\ ]*\\end\{bmatrix\}" + _UNITS, f)
        if m and m.group(2):
            out[m.group(1)] = re.findall(r"\\text\{([^}]*)\}", m.group(2))
    return out


def test_trr_worked_example_gives_units_per_row(tmp_path):
    """The TRR's q̇ mixes a prismatic joint's m/s with two revolute joints' rad/s: each row says its unit."""
    out = tmp_path / "trr.tex"
    assert cli_main(["handout", "trr", "--method", "whitney", "-o", str(out)]) == 0
    units = _units(out.read_text(encoding="utf-8"))
    assert units["\\dot{q} = J^{-1} v"] == ["m/s", "rad/s", "rad/s"]
    assert units["v"] == ["m/s", "m/s", "m/s"]  # the task rows: vx, vy, vz
    html_out = tmp_path / "trr.html"
    assert (
        cli_main(["handout", "trr", "--method", "whitney", "--rates", "0.5", "90", "45", "-o", str(html_out)])
        == 0
    )
    page = html_out.read_text(encoding="utf-8")
    assert "in rad/s and m/s" not in page
    cells = re.findall(r"<mtext>(m/s|rad/s)</mtext>", page)
    assert cells[:3] == ["m/s", "rad/s", "rad/s"]  # q̇ beside its column, then J q̇ (m/s)


def test_the_result_comes_first_and_the_derivation_after(tmp_path):
    """J(q) and det J (with the singular sets) open the handout; the DH table, transforms and methods
    follow, and the contents line says where."""
    out = tmp_path / "trr.html"
    assert cli_main(["handout", "trr", "-o", str(out)]) == 0
    page = out.read_text(encoding="utf-8")
    heads = re.findall(r"<h2>(.*?)</h2>", page)
    assert heads[0] == "1. The result: J(q) and det J" and heads[1].startswith("2. The Denavit")
    assert heads[-2].endswith("Worked example") and heads[-1] == "Notation"
    result = page[page.index(heads[0]) : page.index(heads[1])]
    assert "det" in result and "Singular configurations" in result and "<mtable" in result
    assert "The derivation follows: §2 The Denavit–Hartenberg table" in result
    assert page.count("The Jacobian and its singularities") == 0
    tex = tmp_path / "trr.tex"
    assert cli_main(["handout", "trr", "-o", str(tex)]) == 0
    sections = re.findall(r"\\section\*\{(.*?)\}\n", tex.read_text(encoding="utf-8"))
    assert sections[0].startswith("1. The result") and sections[1].startswith("2. The Denavit")


def test_trr_worked_example_is_the_courses(tmp_path):
    out = tmp_path / "trr.tex"
    assert (
        cli_main(["handout", "trr", "--method", "whitney", "--rates", "0.5", "90", "45", "-o", str(out)]) == 0
    )
    M = _matrices(out.read_text(encoding="utf-8"))
    J_course = np.array([[0, 8.157, 5.657], [0, -9.987, -5.657], [1, 0, 0]])
    assert np.array_equal(M["J(q)"], J_course)
    assert np.array_equal(M["J \\dot{q}"][:, 0], [17.256, -20.130, 0.500])
    # without rates: the course's velocity (the robot file's motion) back to the joint rates
    out2 = tmp_path / "trr2.tex"
    assert cli_main(["handout", "trr", "--method", "whitney", "-o", str(out2)]) == 0
    M2 = _matrices(out2.read_text(encoding="utf-8"))
    J_inv_course = np.array([[0, 0, 1], [-0.5464, -0.5464, 0], [0.9647, 0.7879, 0]])
    assert np.array_equal(M2["J^{-1}(q)"], J_inv_course)
    qd = M2["\\dot{q} = J^{-1} v"][:, 0]
    assert np.allclose(qd, [0.5, np.pi / 2, np.pi / 4], atol=1e-3)  # the course's v is rounded


# ----------------------------------------------------------------------------------- both formats
@pytest.mark.slow
@pytest.mark.parametrize(
    "args",
    [
        ["trr", "--symbolic-params"],
        ["elbow3r", "--symbolic-params", "--frame", "tool"],
        ["planar2", "--symbolic-params", "--method", "propagation"],
        ["puma560", "--method", "whitney"],
        ["puma560_mdh", "--method", "force", "--timeout", "10"],
    ],
)
def test_tex_document_typesets_in_katex(katex, tmp_path, args):  # noqa: F811
    out = tmp_path / "h.tex"
    assert cli_main(["handout", *args, "-o", str(out)]) == 0
    tex = out.read_text(encoding="utf-8")
    assert tex.startswith("\\documentclass") and tex.rstrip().endswith("\\end{document}")
    assert tex.count("\\begin{document}") == 1
    formulas = display_formulas(tex)
    assert len(formulas) > 10
    errors = [(f[:100], e) for f, e in zip(formulas, katex(formulas), strict=True) if e is not None]
    assert errors == []
    for section in ("The result", "Denavit", "Link transforms", "Worked example"):
        assert section in tex


def test_html_is_self_contained_mathml(tmp_path):
    out = tmp_path / "h.html"
    assert cli_main(["handout", "trr", "--symbolic-params", "-o", str(out)]) == 0
    html = out.read_text(encoding="utf-8")
    assert html.startswith("<!DOCTYPE html>") and "<script" not in html and "http" not in html
    assert html.count("<math") > 50 and "<table" in html
    for math in re.findall(r"<math.*?</math>", html, flags=re.S):
        ET.fromstring(math)  # every formula is well-formed XML


@pytest.mark.slow
@pytest.mark.browser
def test_html_fits_1280_px_in_chromium(tmp_path):
    sync_playwright = require_browser()
    pages = []
    # puma560: long simplified entries; panda at a short time limit: unsimplified ones as well
    for args in (
        ["puma560", "--method", "whitney"],
        ["panda", "--method", "differentiation", "--timeout", "3"],
    ):
        out = tmp_path / f"{args[0]}.html"
        assert cli_main(["handout", *args, "-o", str(out)]) == 0
        pages.append(out)
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=ARGS)
        try:
            page = new_page(browser, {"width": 1280, "height": 900})
            for path in pages:
                page.goto(path.as_uri())
                assert page.evaluate("document.documentElement.scrollWidth") <= 1280, path.name
                too_wide = page.evaluate(
                    "[...document.querySelectorAll('main *')].filter(e => e.getBoundingClientRect().right > 1280)"
                    ".length"
                )
                assert too_wide == 0, path.name
                # MathML is laid out as math (Chromium's MathML Core), not as unknown inline elements
                assert page.evaluate("document.querySelectorAll('math').length") > 50
                shown = page.evaluate(
                    "getComputedStyle(document.querySelector('math[display=block]')).display"
                )
                assert shown == "block math"
        finally:
            browser.close()


# ------------------------------------------------------------------------------------ hostile names
HOSTILE_TOML = """
name = "hostile"
title = "<script>alert(1)</script> \\\\input{/etc/passwd}"
description = "</math><script>x</script> & \\\\input{/etc/passwd} % # $"
source = "<img src=x onerror=alert(3)> \\\\include{x}"
convention = "standard"
planar = true

[[joints]]
name = "<script>alert(2)</script>"
joint = "revolute"
a = 1.0
alpha = 0.0
d = 0.0
theta = 0.0

[[joints]]
name = "\\\\input{/etc/passwd}"
joint = "revolute"
a = 1.0
alpha = 0.0
d = 0.0
theta = 0.0
"""


@pytest.mark.slow
def test_hostile_names_are_escaped(katex, tmp_path):  # noqa: F811
    robot_file = tmp_path / "hostile.toml"
    robot_file.write_text(HOSTILE_TOML, encoding="utf-8")
    assert robots.load(robot_file).joints[1].name == "\\input{/etc/passwd}"
    html_out, tex_out = tmp_path / "h.html", tmp_path / "h.tex"
    assert cli_main(["handout", str(robot_file), "-o", str(html_out)]) == 0
    assert cli_main(["handout", str(robot_file), "-o", str(tex_out)]) == 0
    html = html_out.read_text(encoding="utf-8")
    assert "<script" not in html and "<img" not in html and "&lt;script&gt;alert(2)&lt;/script&gt;" in html
    assert "\\input{/etc/passwd}" in html  # as text: harmless in HTML
    tex = tex_out.read_text(encoding="utf-8")
    assert "\\input{" not in tex and "\\textbackslash{}input\\{/etc/passwd\\}" in tex
    formulas = display_formulas(tex)
    assert [e for e in katex(formulas) if e is not None] == []


def test_handout_function_refuses_bad_requests():
    from kinematics.errors import JacobianLabError

    robot = robots.load("planar2")
    for kwargs in (
        dict(fmt="pdf"),
        dict(fmt="html", method="newton"),
        dict(fmt="html", configuration="nowhere"),
    ):
        with pytest.raises(JacobianLabError):
            handout(robot, **kwargs)  # type: ignore[arg-type]
    assert cli_main(["handout", "planar2", "-o", "x.pdf"]) == 2
