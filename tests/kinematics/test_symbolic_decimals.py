"""Numbers in the typeset J and det J: a rational with a finite decimal expansion prints as a decimal
when it has at most 12 significant digits, however many leading zeros (det J's products of lengths)."""

from __future__ import annotations

import sympy as sp

from kinematics.symbolic.typeset.printing import Notation, decimal_text


def test_decimal_text_counts_significant_digits_not_leading_zeros():
    assert decimal_text(sp.Rational(2159, 5000)) == "0.4318"
    assert decimal_text(sp.Rational(26673, 3200000000)) == "0.0000083353125"  # the UR5's det J factor
    assert decimal_text(sp.Rational(-3, 10**9)) == "-0.000000003"
    assert decimal_text(sp.Rational(1, 3)) is None  # no finite expansion: a fraction
    assert decimal_text(sp.Rational(123456789012345, 10**15)) is None  # 15 significant digits


def test_a_small_coefficient_of_det_j_prints_as_a_decimal_in_latex_and_mathml():
    q = sp.symbols("q1:4", real=True)
    notation = Notation(q, {s: f"\\theta_{{{i + 1}}}" for i, s in enumerate(q)}, ("revolute",) * 3)
    det = sp.Rational(26673, 3200000000) * sp.sin(q[2])
    latex = notation.latex(det)
    assert "0.0000083353125" in latex and "frac" not in latex
    assert "0.0000083353125" in notation.mathml(det)
