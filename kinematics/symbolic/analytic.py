"""The analytic Jacobian J_A = blockdiag(I, B(φ)⁻¹) · J in symbolic form, with its representation singularity.

Conventions match :mod:`kinematics.analytic_jacobian`: ``"zyx"`` (roll-pitch-yaw),
R = Rz(yaw) Ry(pitch) Rx(roll), angles (yaw, pitch, roll); ``"zyz"``,
R = Rz(φ) Ry(θ) Rz(ψ), angles (φ, θ, ψ). ω = B(φ) φ̇ in the base frame, so
J_A maps q̇ to [v; φ̇]. J_A is written in the joint symbols and the Euler-angle
symbols (φ(q) itself is an arctangent of entries of R(q), which nobody
writes out); det B = 0 is the representation singularity, where J_A does
not exist whatever the robot does.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import sympy as sp

from ..model import Robot
from .core import DEFAULT_TIMEOUT, derive
from .exact import rot_x, rot_z
from .model import SymbolicError
from .trig import collapse, nest, normal_form

__all__ = ["AnalyticJacobian", "analytic_jacobian", "euler_rate_matrix", "CONVENTIONS"]

CONVENTIONS = {
    "zyx": (("yaw", "pitch", "roll"), ("\\psi", "\\vartheta", "\\varphi")),
    "zyz": (("phi", "theta", "psi"), ("\\varphi", "\\vartheta", "\\psi")),
}
"""Convention → (symbol names, LaTeX display names) of its three angles, in rotation order."""


def _rot_y(t: sp.Expr) -> sp.Matrix:
    c, s = sp.cos(t), sp.sin(t)
    return sp.Matrix([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]])


@functools.cache
def euler_rate_matrix(convention: str = "zyx") -> tuple[tuple[sp.Symbol, ...], sp.Matrix]:
    """(angle symbols, B(φ)) with ω = B(φ) φ̇ (base frame), derived from ω = vee(Ṙ Rᵀ).

    Raises:
        SymbolicError: unknown convention.
    """
    if convention not in CONVENTIONS:
        raise SymbolicError(f"Euler convention must be 'zyx' or 'zyz', got {convention!r}")
    angles = tuple(sp.Symbol(n, real=True) for n in CONVENTIONS[convention][0])
    a, b, c = angles
    last = rot_x(c) if convention == "zyx" else rot_z(c)
    R = (rot_z(a) * _rot_y(b) * last)[:3, :3]
    cols = []
    for x in angles:
        S = (R.diff(x) * R.T).applyfunc(lambda e: normal_form(e, angles))
        cols.append([S[2, 1], S[0, 2], S[1, 0]])
    return angles, sp.Matrix(cols).T


@functools.cache
def _inverse(convention: str) -> tuple[tuple[sp.Symbol, ...], sp.Matrix, sp.Expr, sp.Matrix]:
    angles, B = euler_rate_matrix(convention)
    det_B = sp.factor(normal_form(B.det(), angles))
    B_inv = B.adjugate().applyfunc(lambda e: sp.factor(collapse(normal_form(e, angles), angles)) / det_B)
    return angles, B, det_B, B_inv


@dataclass(frozen=True, eq=False)
class AnalyticJacobian:
    """The symbolic analytic Jacobian of one robot and one Euler convention.

    Attributes:
        convention: ``"zyx"`` or ``"zyz"``.
        angles: The three Euler-angle symbols, in rotation order.
        display: LaTeX display names of the angle symbols.
        B: ω = B φ̇ (3×3).
        B_inv: B⁻¹ (3×3, with det B in the denominators).
        JA: 6×n, rows [v; φ̇], in the joint and angle symbols.
        det_B: det B, e.g. −cos(pitch) or −sin θ.
        condition: The factor of det B that vanishes at the representation singularity.
        singular_values: Values of the middle angle in (−π, π] where it does.
        notes: Notes from the derivation of J (e.g. unsimplified entries).
    """

    convention: str
    angles: tuple[sp.Symbol, ...]
    display: dict[sp.Symbol, str]
    B: sp.Matrix
    B_inv: sp.Matrix
    JA: sp.Matrix
    det_B: sp.Expr
    condition: sp.Expr
    singular_values: tuple[sp.Expr, ...]
    notes: tuple[str, ...] = ()


def analytic_jacobian(
    robot: Robot,
    convention: str = "zyx",
    *,
    symbolic_params: bool = False,
    timeout: float | None = DEFAULT_TIMEOUT,
    use_cache: bool = True,
) -> AnalyticJacobian:
    """Symbolic J_A(q, φ) = blockdiag(I, B(φ)⁻¹) J(q) of ``robot`` (base frame).

    Args:
        robot: The robot.
        convention: ``"zyx"`` (roll-pitch-yaw) or ``"zyz"``.
        symbolic_params: Keep DH lengths and offsets as symbols.
        timeout: Simplification budget for J [s].
        use_cache: Read and write the cache of J.

    Example:
        >>> from kinematics import Robot
        >>> row = dict(joint="revolute", a=1.0, alpha=0.0, d=0.0, theta=0.0)
        >>> planar2 = Robot.from_dh([row, row], planar=True)
        >>> A = analytic_jacobian(planar2, "zyz", use_cache=False)
        >>> A.condition, A.singular_values
        (sin(theta), (0, pi))
    """
    angles, B, det_B, B_inv = _inverse(convention)
    d = derive(robot, "base", symbolic_params=symbolic_params, timeout=timeout, use_cache=use_cache)
    rows = []
    for e in B_inv * d.J[3:, :]:
        num, den = sp.fraction(sp.together(e))
        num = nest(collapse(normal_form(num, d.q), d.q), (*d.q, *angles))
        rows.append(num / den)
    JA = sp.Matrix.vstack(d.J[:3, :], sp.Matrix(3, d.J.cols, rows))
    middle = angles[1]
    condition = next((f for f in sp.Mul.make_args(det_B) if f.has(middle)), det_B)
    sol = sp.solveset(condition, middle, sp.Interval(-sp.pi, sp.pi, left_open=True))
    values = tuple(sorted(sol, key=float)) if isinstance(sol, sp.FiniteSet) else ()
    display = dict(zip(angles, CONVENTIONS[convention][1], strict=True))
    return AnalyticJacobian(convention, angles, display, B, B_inv, JA, det_B, condition, values, d.notes)
