"""Course 000's per-joint J̇ᵢ (§7) in symbols, from the symbolic J (the numeric version is
:func:`kinematics.jacobian_dot_alone`; the tests hold one against the other).

Column i of J is [zᵢ₋₁ × (pₙ − pᵢ₋₁); zᵢ₋₁] for a revolute joint, so 000's
J̇ᵢ = [zᵢ₋₁ × (zᵢ₋₁ × (pₙ − pᵢ₋₁)) q̇ᵢ; 0] is [Jω,ᵢ × Jv,ᵢ q̇ᵢ; 0] (0 for a prismatic joint). It is
the rate of column i when joint i alone moves, ∂Jᵢ/∂qᵢ q̇ᵢ: :func:`jacobian_dot_alone_symbolic`
builds the first, and the tests check it equals the second after simplification.
"""

from __future__ import annotations

import sympy as sp

from ..model import Robot
from .core import DEFAULT_TIMEOUT, jacobian

__all__ = ["jacobian_dot_alone_symbolic", "rate_symbols_of"]


def rate_symbols_of(robot: Robot) -> tuple[sp.Symbol, ...]:
    """The real symbols ``qd1 … qdn`` (q̇ᵢ) of ``robot``'s joints."""
    return tuple(sp.Symbol(f"qd{i + 1}", real=True) for i in range(robot.dof))


def jacobian_dot_alone_symbolic(robot: Robot, timeout: float | None = DEFAULT_TIMEOUT) -> sp.Matrix:
    """000's [J̇₁ … J̇ₙ] (6×n ``sympy.Matrix``) in ``q1 … qn`` and ``qd1 … qdn``, base axes.

    Only for a chain whose joint i moves one axis (a DH table): column i is built from column i of J.
    """
    J = jacobian(robot, "base", timeout=timeout)
    qd = rate_symbols_of(robot)
    out = sp.zeros(6, robot.dof)
    for i, kind in enumerate(robot.joint_types):
        if kind == "revolute":
            top = J[3:, i].cross(J[:3, i]) * qd[i]
            for r in range(3):
                out[r, i] = sp.expand_trig(top[r])
    return out
