"""Exact SymPy numbers from floats, and elementary symbolic transforms.

Angles that are rational multiples of π stay so (π/2 stays π/2), rotation
entries such as √2/2 are recognised, and other floats become the rational
with the same decimal digits (0.4318 → 2159/5000, printed back as 0.4318).
Only floats are converted: no text is ever parsed into SymPy.
"""

from __future__ import annotations

import math
import operator
from fractions import Fraction

import numpy as np
import sympy as sp

from ..dh import MatrixOps

__all__ = [
    "exact_number",
    "exact_angle",
    "is_right_angle_multiple",
    "exact_transform",
    "SPECIAL_VALUES",
    "rot_x",
    "rot_z",
    "trans",
    "SYMPY_OPS",
]

SPECIAL_VALUES = (
    sp.Integer(0),
    sp.Integer(1),
    sp.Rational(1, 2),
    sp.sqrt(2) / 2,
    sp.sqrt(3) / 2,
    (sp.sqrt(6) - sp.sqrt(2)) / 4,
    (sp.sqrt(6) + sp.sqrt(2)) / 4,
)
"""Exact sines and cosines of the multiples of 15° (0, 1, 1/2, √2/2, √3/2, (√6 ∓ √2)/4)."""
_SPECIAL_F = [float(v) for v in SPECIAL_VALUES]


def exact_number(x: float, tol: float = 1e-12) -> sp.Expr:
    """An exact SymPy number for the float ``x``.

    Values within ``tol`` of 0, ±1, ±1/2, ±√2/2, ±√3/2 or ±(√6 ∓ √2)/4 (the sines and cosines
    of multiples of 15°) become those; any other float becomes the rational with its decimal
    digits (``sympy.nsimplify(x, rational=True)``: 0.4318 → 2159/5000).
    """
    x = float(x)
    for exact, approx in zip(SPECIAL_VALUES, _SPECIAL_F, strict=True):
        if abs(abs(x) - approx) < tol:
            return exact if x >= 0 else -exact
    return sp.nsimplify(x, rational=True)


def exact_angle(x: float, tol: float = 1e-12) -> sp.Expr:
    """An exact angle [rad]: k·π/m (m ≤ 12) when ``x`` is within ``tol`` of one, else :func:`exact_number`."""
    frac = Fraction(float(x) / math.pi).limit_denominator(12)
    if abs(float(frac) * math.pi - x) < tol:
        return sp.Rational(frac.numerator, frac.denominator) * sp.pi
    return exact_number(x, tol)


def is_right_angle_multiple(x: float) -> bool:
    return abs(x / (math.pi / 2) - round(x / (math.pi / 2))) < 1e-12


def rot_z(t: sp.Expr) -> sp.Matrix:
    """4×4 symbolic rotation about z by ``t`` [rad]."""
    c, s = sp.cos(t), sp.sin(t)
    return sp.Matrix([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])


def rot_x(t: sp.Expr) -> sp.Matrix:
    """4×4 symbolic rotation about x by ``t`` [rad]."""
    c, s = sp.cos(t), sp.sin(t)
    return sp.Matrix([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])


def trans(x: sp.Expr = 0, y: sp.Expr = 0, z: sp.Expr = 0) -> sp.Matrix:
    """4×4 symbolic translation by (x, y, z) [m]."""
    T = sp.eye(4)
    T[0, 3], T[1, 3], T[2, 3] = x, y, z
    return T


SYMPY_OPS: MatrixOps[sp.Matrix] = MatrixOps(
    eye=lambda: sp.eye(4),
    rot_x=rot_x,
    rot_z=rot_z,
    trans_x=lambda a: trans(x=a),
    trans_z=lambda d: trans(z=d),
    mul=operator.mul,
)
"""The DH factors as SymPy matrices, for :func:`kinematics.dh.dh_factors`."""


def exact_transform(T: np.ndarray) -> sp.Matrix:
    """A 4×4 numeric transform with every entry made exact by :func:`exact_number`."""
    return sp.Matrix(4, 4, [exact_number(v) for v in np.asarray(T, dtype=float).ravel()])
