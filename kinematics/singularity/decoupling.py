"""Arm and wrist decoupled, as the course teaches a spherical wrist.

A spherical wrist has its last three axes revolute and meeting in one point,
the wrist centre c, at every configuration (course, 002: "since the wrist
axes intersect at a common point they cause zero translation" there). Take
the Jacobian with v the velocity of c instead of the tool point,

    v_c = v_tool + ω × (c − p_tool),

and the wrist columns have no v part: J_c = [[J₁₁, 0], [J₂₁, J₂₂]], block
lower-triangular. For a six-joint arm det J = det J_c = det J₁₁ · det J₂₂
(moving the reference point does not change det J), so the singularities
split in two:

* **arm**: det J₁₁ = 0, the arm joints cannot move the wrist centre along a
  direction u (a left null vector of J₁₁), and the wrist cannot either: the
  twist [u; 0] at c is lost exactly;
* **wrist**: det J₂₂ = 0, the three wrist axes lie in one plane (two in line,
  e.g. θ5 = 0 on a Puma 560), and the wrist cannot turn the tool about their
  common normal a (a left null vector of J₂₂) while the wrist centre stays put.

Tested against the full J (det J = det J₁₁ · det J₂₂ at random q) in tests/kinematics/test_decoupling.py.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import numpy as np

from ..errors import ConfigurationError
from ..model import Robot
from ..numeric import as_configuration, chain_frames, jacobian

__all__ = ["Decoupling", "spherical_wrist", "wrist_centre", "decouple", "DECOUPLED_RTOL", "block_losses"]

DECOUPLED_RTOL = 1e-7
"""σᵢ/σ_max of a block below this counts as zero (a lost direction of that block)."""

_SAMPLES = 4


@dataclass(frozen=True, eq=False)
class Decoupling:
    """J at the wrist centre split into the arm's and the wrist's blocks.

    Attributes:
        centre: The wrist centre c (3,) [m], base coordinates.
        J_centre: (6, n) geometric Jacobian with v the velocity of c, base axes.
        J11: (3, n − 3) v rows × arm columns [m/rad | 1].
        J21: (3, n − 3) ω rows × arm columns.
        J22: (3, 3) ω rows × wrist columns [1].
        sigma_arm, sigma_wrist: Singular values of J₁₁ and J₂₂, descending.
        det_arm, det_wrist: det J₁₁ (``None`` unless square) and det J₂₂.
        arm_lost: (k, 3) unit directions the wrist centre cannot move along (σ of J₁₁ ≈ 0).
        wrist_lost: (k, 3) unit axes the wrist cannot turn about (σ of J₂₂ ≈ 0).
    """

    centre: np.ndarray
    J_centre: np.ndarray
    J11: np.ndarray
    J21: np.ndarray
    J22: np.ndarray
    sigma_arm: np.ndarray
    sigma_wrist: np.ndarray
    det_arm: float | None
    det_wrist: float
    arm_lost: np.ndarray
    wrist_lost: np.ndarray

    @property
    def arm_singular(self) -> bool:
        return len(self.arm_lost) > 0

    @property
    def wrist_singular(self) -> bool:
        return len(self.wrist_lost) > 0

    @property
    def condition_arm(self) -> float:
        """κ of J₁₁ over the directions of c (``inf`` when the arm is singular)."""
        s = _padded(self.sigma_arm)
        return float(s[0] / s[-1]) if s[-1] > DECOUPLED_RTOL * max(s[0], 1e-300) else float("inf")

    @property
    def condition_wrist(self) -> float:
        """κ of J₂₂ (``inf`` when the wrist is singular)."""
        s = self.sigma_wrist
        return float(s[0] / s[-1]) if s[-1] > DECOUPLED_RTOL * max(s[0], 1e-300) else float("inf")


def _padded(sigma: np.ndarray) -> np.ndarray:
    return np.concatenate([sigma, np.zeros(3 - len(sigma))]) if len(sigma) < 3 else sigma


def _meeting_point(z: np.ndarray, p: np.ndarray, tol: float = 1e-9) -> np.ndarray | None:
    """The point where the three lines (pᵢ, zᵢ) meet, or None."""
    P = [np.eye(3) - np.outer(zi, zi) for zi in z]
    A = sum(P)
    b = sum(Pi @ pi for Pi, pi in zip(P, p, strict=True))
    if np.linalg.svd(A, compute_uv=False)[-1] < 1e-9:
        return None  # all three in line: no single point
    x = np.linalg.solve(A, b)
    scale = max(1.0, float(np.abs(p).max()))
    if max(float(np.linalg.norm(Pi @ (x - pi))) for Pi, pi in zip(P, p, strict=True)) > tol * scale:
        return None
    return x


_WRISTS: weakref.WeakKeyDictionary[Robot, tuple[tuple[int, int, int] | None]] = weakref.WeakKeyDictionary()


def spherical_wrist(robot: Robot) -> tuple[int, int, int] | None:
    """The joints (indices) of a spherical wrist, or None.

    The robot has one when it moves in space (not planar) with at least six joints, its last
    three joints are revolute and their axes meet in one point at home and at a few other
    configurations (a fixed seed inside the joint limits, so the answer is the same every time).
    """
    try:
        return _WRISTS[robot][0]
    except (KeyError, TypeError):
        pass
    found = _spherical_wrist(robot)
    try:
        _WRISTS[robot] = (found,)
    except TypeError:  # not weakly referenceable: just not cached
        pass
    return found


def _spherical_wrist(robot: Robot) -> tuple[int, int, int] | None:
    n = robot.dof
    if robot.planar or n < 6 or len(robot.axes) != n or any(a.kind != "revolute" for a in robot.axes[-3:]):
        return None
    wrist = (n - 3, n - 2, n - 1)
    lo, hi = robot.limits if hasattr(robot, "limits") else (np.full(n, -np.pi), np.full(n, np.pi))
    lo = np.where(np.isfinite(lo), lo, -np.pi)
    hi = np.where(np.isfinite(hi), hi, np.pi)
    rng = np.random.default_rng(20240521)
    samples = [np.asarray(robot.home, float)] + [rng.uniform(lo, hi) for _ in range(_SAMPLES)]
    for q in samples:
        W, _ = chain_frames(robot, q)
        if _meeting_point(W[list(wrist), :3, 2], W[list(wrist), :3, 3]) is None:
            return None
    return wrist


def wrist_centre(robot: Robot, q: object, wrist: tuple[int, int, int]) -> np.ndarray:
    """Where the wrist axes meet at ``q`` (3,) [m] (the first wrist joint's origin if they do not)."""
    W, _ = chain_frames(robot, as_configuration(robot, q))
    c = _meeting_point(W[list(wrist), :3, 2], W[list(wrist), :3, 3])
    return W[wrist[0], :3, 3].copy() if c is None else c


def block_losses(block: np.ndarray, rtol: float = DECOUPLED_RTOL) -> tuple[np.ndarray, np.ndarray]:
    """Singular values (descending) of a 3-row block and its lost directions (k, 3): the left singular
    vectors whose σ is ≤ rtol·σ_max (all three rows count, so a 3 × 2 block always loses one)."""
    U, s, _ = np.linalg.svd(block)
    full = _padded(s)
    lost = [U[:, i] for i in range(3) if full[i] <= rtol * max(full[0], 1e-300)]
    return s, np.array(lost).reshape(-1, 3)


def decouple(robot: Robot, q: object, J: np.ndarray | None = None) -> Decoupling | None:
    """J at the wrist centre in blocks, or None when ``robot`` has no spherical wrist.

    Args:
        robot: The robot.
        q: One configuration (n,) [rad | m].
        J: Its base-frame Jacobian (tool point), if already computed.
    """
    wrist = spherical_wrist(robot)
    if wrist is None:
        return None
    q = as_configuration(robot, q)
    if q.ndim != 1:
        raise ConfigurationError(f"decouple takes one configuration ({robot.dof},), got {q.shape}")
    if J is None:
        J = jacobian(robot, q)
    W, T = chain_frames(robot, q)
    c = _meeting_point(W[list(wrist), :3, 2], W[list(wrist), :3, 3])
    if c is None:  # a degenerate pose of the sampled wrist (cannot happen for a true spherical wrist)
        c = W[wrist[0], :3, 3].copy()
    r = c - T[:3, 3]
    Jc = np.array(J, float)
    Jc[:3] = J[:3] + np.cross(J[3:].T, r).T  # v_c = v_tool + ω × (c − p_tool), column by column
    arm = list(range(wrist[0]))
    J11, J21, J22 = Jc[:3, arm], Jc[3:, arm], Jc[3:, list(wrist)]
    s_arm, lost_arm = block_losses(J11)
    s_wrist, lost_wrist = block_losses(J22)
    return Decoupling(
        centre=c,
        J_centre=Jc,
        J11=J11,
        J21=J21,
        J22=J22,
        sigma_arm=s_arm,
        sigma_wrist=s_wrist,
        det_arm=float(np.linalg.det(J11)) if J11.shape == (3, 3) else None,
        det_wrist=float(np.linalg.det(J22)),
        arm_lost=lost_arm,
        wrist_lost=lost_wrist,
    )
