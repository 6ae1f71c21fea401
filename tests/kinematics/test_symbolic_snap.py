"""Rounded values of real robot files (1.5708, 1.57079632679, 3.14159) snapped to exact ones, and said so."""

from __future__ import annotations

import html
import math
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from locations import DATA

import kinematics
import robots
from kinematics import symbolic
from kinematics.symbolic.simplify import drop_negligible
from kinematics.symbolic.snap import SNAP_TOL, Snapper
from kinematics.transforms import rot_x, rot_y, rot_z

ROUNDED = {"1.57079632679": math.pi / 2, "3.14159265359": math.pi, "3.14159": math.pi, "1.5708": math.pi / 2}


def exact_copy(path: Path, tmp_path: Path) -> Path:
    """The same URDF with every rounded right angle written to full double precision."""
    text = path.read_text()
    for rounded, value in ROUNDED.items():  # longest first, so 3.14159265359 goes before 3.14159
        text = text.replace(rounded, repr(value))
    out = tmp_path / path.name
    out.write_text(text)
    return out


def random_q(robot, count=4, seed=5):
    return np.random.default_rng(seed).uniform(-2.5, 2.5, size=(count, robot.dof))


def exact_rx(t):
    return sp.Matrix([[1, 0, 0], [0, sp.cos(t), -sp.sin(t)], [0, sp.sin(t), sp.cos(t)]])


def exact_ry(t):
    return sp.Matrix([[sp.cos(t), 0, sp.sin(t)], [0, 1, 0], [-sp.sin(t), 0, sp.cos(t)]])


def exact_rz(t):
    return sp.Matrix([[sp.cos(t), -sp.sin(t), 0], [sp.sin(t), sp.cos(t), 0], [0, 0, 1]])


# ------------------------------------------------------------------ the snapper
@pytest.mark.parametrize(
    "given, exact, reported",
    [
        (1.5708, sp.pi / 2, True),
        (1.57079632679, sp.pi / 2, True),
        (-3.14159, -sp.pi, True),
        (0.2620, sp.pi / 12, True),
        (math.pi / 2, sp.pi / 2, False),  # already exact: nothing to say
        (0.3, sp.Rational(3, 10), False),  # not near a multiple of pi/12: kept
        (0.2630, sp.Rational(263, 1000), False),  # 1.2e-3 from pi/12: beyond the tolerance
    ],
)
def test_angles(given, exact, reported):
    S = Snapper()
    assert S.angle(given, "alpha") == exact
    assert bool(S.snaps) == reported
    if reported:
        assert S.snaps[0].change == pytest.approx(abs(given - float(exact)), rel=1e-9, abs=1e-15)
        assert S.snaps[0].change <= SNAP_TOL


def test_lengths():
    S = Snapper()
    assert S.length(1e-17, "a") == 0 and S.snaps == []  # float noise: not worth a note
    assert S.length(3e-10, "d") == 0 and S.snaps[0].change == 3e-10
    assert S.length(0.36, "d") == sp.Rational(9, 25)


@pytest.mark.parametrize(
    "R, exact",
    [
        (rot_z(3.14159) @ rot_x(1.57079632679), sp.Matrix([[-1, 0, 0], [0, 0, 1], [0, 1, 0]])),
        (rot_x(0.7854) @ rot_y(0.7854), exact_rx(sp.pi / 4) * exact_ry(sp.pi / 4)),  # 1/2, sqrt(2)/2
        (rot_z(0.5236) @ rot_x(-1.0472), exact_rz(sp.pi / 6) * exact_rx(-sp.pi / 3)),
    ],
)
def test_rotations_snap_to_exact_orthogonal_matrices(R, exact):
    S = Snapper()
    E, change = S.rotation(R[:3, :3], "joint 'j'")
    assert sp.simplify(E - exact) == sp.zeros(3, 3)
    assert 0 < change < SNAP_TOL and len(S.snaps) == 1


@pytest.mark.slow
def test_rotation_that_does_not_snap_stays_exactly_orthogonal():
    S = Snapper()
    E, change = S.rotation((rot_x(0.3) @ rot_y(0.2))[:3, :3], "joint 'j'")
    assert S.snaps == [] and change < 1e-11
    assert sp.simplify(E.T * E - sp.eye(3)) == sp.zeros(3, 3)


def test_negligible_terms_are_dropped():
    q1, a = sp.Symbol("q1", real=True), sp.Symbol("a", real=True)
    expr = 2 * sp.cos(q1) + sp.Rational(1, 10**15) * sp.sin(q1) + a * sp.sin(q1)
    kept, dropped = drop_negligible(expr, (q1,), {a: 1e-14})
    assert kept == 2 * sp.cos(q1) and dropped == 2
    kept, dropped = drop_negligible(expr, (q1,), {a: 0.5})
    assert kept == 2 * sp.cos(q1) + a * sp.sin(q1) and dropped == 1


# ------------------------------------------------------------- whole robots
@pytest.mark.slow
def test_dh_arm_with_rounded_twists_gives_the_exact_formulas():
    """A Puma 560 whose twists are written 1.5708: the same symbolic J as the exact Puma, a note,
    and numbers that agree with its own numeric J to the size of the snap."""
    exact = robots.load("puma560")
    rows = [
        dict(joint=r.joint, a=r.a, alpha=round(r.alpha, 4), d=r.d, theta=round(r.theta, 4)) for r in exact.dh
    ]
    rounded = kinematics.Robot.from_dh(rows, name="puma_rounded")
    d, d_exact = symbolic.derive(rounded), symbolic.derive(exact)
    assert d.J == d_exact.J and d.complete
    assert d.notes[0] == d.snap_note and "largest change 3.7e-06 rad" in d.snap_note
    assert "DH row 1: alpha: 1.5708 -> pi/2" in d.snap_note and d_exact.snaps == ()
    f = symbolic.numeric_function(d.J, symbolic.build_model(rounded))
    for q in random_q(rounded):
        J = kinematics.jacobian(rounded, q)
        assert np.linalg.norm(f(q) - J) <= 1e-3 * np.linalg.norm(J)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["iiwa14_like", "xarm7_like"])
def test_real_arm_urdf_snaps_and_stays_readable(name, tmp_path):
    path = DATA / f"{name}.urdf"
    rounded = kinematics.robot_from_urdf(str(path))
    exact = kinematics.robot_from_urdf(str(exact_copy(path, tmp_path)))
    d, d_exact = symbolic.derive(rounded, timeout=120), symbolic.derive(exact, timeout=120)
    assert d.complete and d_exact.complete
    assert d_exact.snaps == () and d.snaps and d.largest_snap < 4e-6
    assert d.J == d_exact.J  # the rounded file gives the formulas of the exact one
    f, f_exact = (
        symbolic.numeric_function(x.J, symbolic.build_model(r)) for x, r in ((d, rounded), (d_exact, exact))
    )
    for q in random_q(rounded):
        np.testing.assert_allclose(f_exact(q), kinematics.jacobian(exact, q), atol=1e-12)  # exact: exact
        J = kinematics.jacobian(rounded, q)
        assert np.linalg.norm(f(q) - J) <= 1e-3 * np.linalg.norm(J)  # rounded: to the snap
    # readable: decimals of the file, no long rationals, a short LaTeX
    assert max(int(r.q) for r in d.J.atoms(sp.Rational)) <= 10**4
    latex = symbolic.jacobian_latex(rounded)
    assert len(latex) < 20_000


@pytest.mark.slow
def test_snapped_values_are_named_in_every_export():
    robot = kinematics.robot_from_urdf(str(DATA / "xarm7_like.urdf"))
    from kinematics.symbolic.typeset import export as ex

    for fmt in ("latex", "mathml", "python", "json"):
        text = ex.export(robot, fmt, timeout=120)
        text = html.unescape(text) if fmt == "mathml" else text
        assert "snapped to exact multiples of pi/12" in text, fmt
        assert "joint 'joint2': fixed rotation: rpy (-1.5708, 0, 0) -> rpy (-pi/2, 0, 0)" in text, fmt


def test_snapping_is_in_the_cache_key():
    robot = robots.load("planar2")
    key = symbolic.build_model(robot).cache_key()
    assert f"snap={SNAP_TOL}" in key
