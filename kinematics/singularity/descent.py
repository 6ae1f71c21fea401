"""Descent toward a singularity (the engine of :func:`kinematics.singularity.nearest`).

The singular set is where w = Π σᵢ (the manipulability of the task rows) vanishes. The descent
takes Newton steps on w = 0 from q0:

    Δq = −w ∇w / ‖∇w‖² = −∇log w / ‖∇log w‖²,   ∂ log w/∂qᵢ = Σⱼ uⱼᵀ (∂J/∂qᵢ) vⱼ / σⱼ

(uⱼ, vⱼ the singular vectors; ∂J/∂qᵢ by central differences of the Jacobian, all 2n in one
batch). That is the minimum-norm step onto the linearised singular set, dominated by the σⱼ
that is closest to vanishing, so the path heads for a *nearby* singularity and converges
quadratically once close (a constant small σ, like a prismatic joint's, does not mislead it as
a descent on σmin alone would). Steps are capped in length and halved while w does not
decrease.

Limitation: for a redundant arm (more joints than task rows) the singular set has codimension
≥ 2, w behaves like a cone around it, and the descent converges only linearly and may stop
above the tolerance (``converged=False``).
"""

from __future__ import annotations

from typing import cast

import numpy as np

from ..conventions import FloatArray
from ..kernel import batched_jacobian, chain_single, jacobian_from_frames, kernel
from ..model import Robot

__all__ = ["descend_to_singularity", "sigma_ratio", "FD_STEP", "MAX_STEP", "POLISH_RATIO", "POLISH_STEPS"]

FD_STEP = 1e-6
"""Central-difference step [rad | m] for ∂J/∂qᵢ."""
MAX_STEP = 0.25
"""Largest joint-space step norm [rad | m] of one descent iteration."""
POLISH_RATIO = 1e-13
POLISH_STEPS = 40
"""Once σmin/σmax < tol, up to POLISH_STEPS more steps (while w decreases, down to
POLISH_RATIO) make the end singular at the 1e-9 tolerance of :func:`kinematics.singularity.assess`."""


def _svd(robot: Robot, q: FloatArray, rows: list[int]) -> tuple[FloatArray, FloatArray, FloatArray]:
    c = kernel(robot)
    J = jacobian_from_frames(c, *chain_single(c, q))[rows]
    return np.linalg.svd(J)


def sigma_ratio(robot: Robot, q: FloatArray, rows: list[int]) -> float:
    """σmin/σmax of the task rows at q (0 when the rows outnumber the joints)."""
    if len(rows) > len(q):
        return 0.0
    s = _svd(robot, q, rows)[1]
    return float(s[-1] / s[0]) if s[0] > 0 else 0.0


def _gradient(
    robot: Robot, q: FloatArray, rows: list[int], U: FloatArray, s: FloatArray, Vt: FloatArray
) -> FloatArray:
    """∇ log w (n,) = Σⱼ uⱼᵀ (∂J/∂qᵢ) vⱼ / σⱼ over the k singular triplets of the task rows."""
    n = len(q)
    k = len(s)
    H = FD_STEP * np.eye(n)
    _, J = batched_jacobian(kernel(robot), np.concatenate([q + H, q - H]))
    dJ = (J[:n, rows] - J[n:, rows]) / (2.0 * FD_STEP)  # (n, m, n): ∂J/∂qᵢ
    return cast(FloatArray, np.einsum("mk,imj,kj->i", U[:, :k] / s, dJ, Vt[:k]))


def _log_w(s: FloatArray) -> float:
    return float(np.sum(np.log(s))) if s[-1] > 0 else -np.inf


def descend_to_singularity(
    robot: Robot, q0: FloatArray, rows: list[int], max_iterations: int, tol: float
) -> tuple[FloatArray, float]:
    """Path (k+1, n) from q0 down w until σmin/σmax < tol (then polished, see
    :data:`POLISH_STEPS`; or until no further progress), and the final ratio. Checked input only."""
    q = q0.copy()
    path = [q]
    if len(rows) > len(q):
        return np.array(path), 0.0
    k = len(rows)
    U, s, Vt = _svd(robot, q, rows)
    s = s[:k]
    polish = 0
    for _ in range(max_iterations):
        if s[0] <= 0 or s[-1] / s[0] < POLISH_RATIO:
            break
        if s[-1] / s[0] < tol:
            polish += 1  # a few more (quadratically convergent) steps: exactly singular to assess()
            if polish > POLISH_STEPS:
                break
        g = _gradient(robot, q, rows, U, s, Vt)
        gg = float(g @ g)
        if gg <= 1e-300:
            break
        dq = -g / gg  # the Newton step on w = 0: −w ∇w / ‖∇w‖² = −∇log w / ‖∇log w‖²
        norm = float(np.linalg.norm(dq))
        if norm > MAX_STEP:
            dq *= MAX_STEP / norm
        f0 = _log_w(s)
        for _ in range(30):
            U2, s2, Vt2 = _svd(robot, q + dq, rows)
            if _log_w(s2[:k]) < f0:
                break
            dq *= 0.5
        else:
            break  # no decrease: a local minimum of w that is not zero
        q = q + dq
        U, s, Vt = U2, s2[:k], Vt2
        path.append(q)
    return np.array(path), float(s[-1] / s[0]) if s[0] > 0 else 0.0
