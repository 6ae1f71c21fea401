"""The facts written once (kinematics.conventions, kinematics.dh.dh_factors, the ZYX angles in
kinematics.transforms) checked against independent derivations."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
import sympy as sp

from kinematics import conventions
from kinematics.dh import NUMPY_OPS, dh_factors
from kinematics.symbolic.exact import SYMPY_OPS
from kinematics.transforms import euler_angles, matrix_to_rpy, rot_z, rpy_to_matrix, trans


def _textbook_dh(convention: str, a: float, alpha: float, d: float, theta: float) -> np.ndarray:
    """The DH link transform written out entry by entry (Spong's standard A, Craig's modified T)."""
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    if convention == "standard":
        return np.array(
            [[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st], [0, sa, ca, d], [0, 0, 0, 1]]
        )
    return np.array(
        [[ct, -st, 0, a], [st * ca, ct * ca, -sa, -sa * d], [st * sa, ct * sa, ca, ca * d], [0, 0, 0, 1]]
    )


@pytest.mark.parametrize("convention", ["standard", "modified"])
@pytest.mark.parametrize("revolute", [True, False])
def test_dh_factors_rebuild_the_textbook_link_transform_in_numpy_and_sympy(convention, revolute):
    rng = np.random.default_rng(7)
    a_, al_, d_, th_, q_ = sp.symbols("a alpha d theta q", real=True)
    sym_pj, sym_jc = dh_factors(SYMPY_OPS, revolute, convention, a_, al_, d_, th_)
    for _ in range(20):
        a, alpha, d, theta, q = rng.uniform(-2, 2, 5)
        T_pj, T_jc = dh_factors(NUMPY_OPS, revolute, convention, a, alpha, d, theta)
        # The joint moves about z (revolute: θ = q + θ₀) or along it (prismatic: d = q + d₀).
        motion = rot_z(q + theta) if revolute else trans(z=q + d)
        expected = _textbook_dh(convention, a, alpha, d + q * (not revolute), theta + q * revolute)
        np.testing.assert_allclose(T_pj @ motion @ T_jc, expected, atol=1e-12)
        values = {a_: a, al_: alpha, d_: d, th_: theta}
        np.testing.assert_allclose(np.array(sym_pj.subs(values), dtype=float), T_pj, atol=1e-12)
        np.testing.assert_allclose(np.array(sym_jc.subs(values), dtype=float), T_jc, atol=1e-12)


def test_rpy_and_zyx_euler_angles_are_one_convention():
    rng = np.random.default_rng(3)
    for _ in range(200):
        roll, yaw = rng.uniform(-math.pi, math.pi, 2)
        pitch = rng.uniform(-math.pi / 2 + 1e-3, math.pi / 2 - 1e-3)
        R = rpy_to_matrix(roll, pitch, yaw)
        # R = Rz(yaw) Ry(pitch) Rx(roll): its first column and last row, from the product by hand.
        cy, sy, cp, sp_, cr, sr = (f(x) for x in (yaw, pitch, roll) for f in (math.cos, math.sin))
        np.testing.assert_allclose(R[:, 0], [cy * cp, sy * cp, -sp_], atol=1e-12)
        np.testing.assert_allclose(R[2], [-sp_, cp * sr, cp * cr], atol=1e-12)
        np.testing.assert_allclose(matrix_to_rpy(R), [roll, pitch, yaw], atol=1e-9)
        np.testing.assert_allclose(euler_angles(R, "zyx"), [yaw, pitch, roll], atol=1e-9)


def test_at_gimbal_lock_the_turn_goes_to_yaw_and_the_matrix_is_kept():
    for pitch in (math.pi / 2, -math.pi / 2):
        R = rpy_to_matrix(0.4, pitch, -0.3)
        roll, p, yaw = matrix_to_rpy(R)
        assert roll == 0.0 and p == pytest.approx(pitch)
        np.testing.assert_allclose(rpy_to_matrix(roll, p, yaw), R, atol=1e-12)


def _plain(markup: str) -> str:
    text = re.sub(r"<[^>]+>", "", markup)  # HTML and MathML tags
    return text.replace("\\omega", "ω").replace("_", "").replace("{", "").replace("}", "")


def test_every_spelling_of_the_rows_names_the_same_six_rows():
    assert len(conventions.ROW_TEXT) == 6
    for spelling in (conventions.ROW_HTML, conventions.ROW_LATEX, conventions.ROW_MATHML):
        assert tuple(_plain(s) for s in spelling) == conventions.ROW_TEXT
    assert tuple(s.replace("w", "ω") for s in conventions.ROW_ASCII) == conventions.ROW_TEXT
    assert all(s.isascii() for s in conventions.ROW_ASCII)
    # The parts name rows of the twist [v; ω]: linear rows are v, angular rows ω.
    assert {conventions.ROW_TEXT[r][0] for r in conventions.PART_ROWS["linear"]} == {"v"}
    assert {conventions.ROW_TEXT[r][0] for r in conventions.PART_ROWS["angular"]} == {"ω"}
    assert [conventions.ROW_TEXT[r] for r in conventions.PART_ROWS["planar"]] == ["vx", "vy", "ωz"]
