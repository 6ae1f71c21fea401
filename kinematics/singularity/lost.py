"""The lost direction at (or near) a singularity, with metres and radians weighed explicitly.

A 6-row Jacobian mixes [m/s] (v rows) and [rad/s] (ω rows), so "the
direction of σmin" depends on how a metre is compared with a radian. This
module states that choice: angular rows are multiplied by a characteristic
length L [m] (by default the arm's reach, :func:`characteristic_length`),
so a rotation of 1 rad/s counts like the tool moving L m/s. The smallest
singular direction of the weighted task rows is then split into a lost
translation (a direction of v) and a lost rotation (an axis of ω), each with
its share of the weighted unit vector, so a drawing can show only the part
that matters.

Example: a planar 2R arm stretched out loses the radial translation.

>>> import numpy as np
>>> from kinematics import Robot, jacobian
>>> arm = Robot.from_dh([dict(joint="revolute", a=1.0, alpha=0.0, d=0.0, theta=0.0)] * 2, planar=True)
>>> lost = lost_direction(jacobian(arm, [0.0, 0.0]), (0, 1), length=2.0)
>>> np.round(np.abs(lost.translation), 6).tolist(), round(lost.translation_share, 6)
([1.0, 0.0, 0.0], 1.0)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model import Robot
from ..numeric import link_frames

__all__ = ["LostDirection", "lost_direction", "lost_directions", "characteristic_length"]


@dataclass(frozen=True, eq=False)
class LostDirection:
    """The task direction of the smallest weighted singular value.

    Attributes:
        sigma: Smallest singular value of the weighted task rows [m/s per unit joint rate].
        translation: Unit direction (3,) of the lost tool-point velocity (zero if none).
        rotation: Unit axis (3,) of the lost angular velocity (zero if none).
        translation_share: |u_v|² in [0, 1]: how much of the lost direction is translation.
        rotation_share: |u_ω|² = 1 − translation_share.
        length: The characteristic length L used to weigh ω rows [m].
    """

    sigma: float
    translation: np.ndarray
    rotation: np.ndarray
    translation_share: float
    rotation_share: float
    length: float


def characteristic_length(robot: Robot) -> float:
    """The length L [m] that weighs rotations against translations: the arm's reach.

    The length of the polyline through the link-frame origins at home (at
    least 0.1 m, so an arm whose frames share one point, a wrist alone, still
    gets a finite weight).

    >>> from kinematics import Robot
    >>> row = dict(joint="revolute", alpha=0.0, d=0.0, theta=0.0)
    >>> characteristic_length(Robot.from_dh([dict(row, a=0.5), dict(row, a=0.3)]))
    0.8
    """
    L = link_frames(robot, robot.home)
    length = float(np.linalg.norm(np.diff(L[:, :3, 3], axis=0), axis=1).sum())
    return max(round(length, 12), 0.1)


def lost_direction(J: np.ndarray, rows: tuple[int, ...], length: float) -> LostDirection:
    """The direction of σmin of the task rows of ``J`` with ω rows weighted by ``length``.

    Args:
        J: Geometric Jacobian (6, n), rows [v; ω].
        rows: The task rows (e.g. (0, 1, 2, 3, 4, 5), (0, 1, 5)).
        length: Characteristic length L [m] (> 0).

    With more task rows than joints the smallest direction is one the arm
    cannot produce at all (σ = 0).
    """
    if not (np.isfinite(length) and length > 0):
        raise ValueError(f"length must be a positive number of metres, got {length!r}")
    rows = tuple(rows)
    weights = np.array([1.0 if r < 3 else length for r in rows])
    Jw = J[list(rows)] * weights[:, None]
    U, s, _ = np.linalg.svd(Jw)
    m, n = Jw.shape
    sigma = float(s[m - 1]) if m <= n else 0.0
    u = U[:, m - 1]
    full = np.zeros(6)
    full[list(rows)] = u
    uv, uw = full[:3], full[3:]
    share_v = float(uv @ uv)
    share_w = float(uw @ uw)
    norm_v, norm_w = np.sqrt(share_v), np.sqrt(share_w)
    translation = uv / norm_v if norm_v > 1e-12 else np.zeros(3)
    rotation = uw / norm_w if norm_w > 1e-12 else np.zeros(3)
    return LostDirection(sigma, translation, rotation, share_v, share_w, float(length))


def lost_directions(
    J: np.ndarray, rows: tuple[int, ...], length: float, rtol: float = 1e-7
) -> tuple[LostDirection, ...]:
    """Every lost direction of a multi-rank loss: one :class:`LostDirection` per σ ≤ ``rtol``·σmax of the
    weighted task rows (at least the smallest one, so a near-singular configuration still gets one).

    The lost directions span a subspace; they are returned in the basis of that subspace that
    separates translation from rotation as far as it can (pure translations first, then mixed
    ones, then pure rotations), so that, e.g., a stretched arm that also loses a rotation gets one
    arrow and one axis instead of two mixtures.
    """
    if not (np.isfinite(length) and length > 0):
        raise ValueError(f"length must be a positive number of metres, got {length!r}")
    rows = tuple(rows)
    weights = np.array([1.0 if r < 3 else length for r in rows])
    Jw = J[list(rows)] * weights[:, None]
    U, s, _ = np.linalg.svd(Jw)
    m, n = Jw.shape
    full = np.concatenate([s, np.zeros(max(0, m - len(s)))])
    small = [i for i in range(m) if full[i] <= rtol * max(full[0], 1e-300)] or [m - 1]
    N = np.zeros((6, len(small)))
    N[list(rows)] = U[:, small]
    sigmas = full[small]
    if len(small) > 1:  # rotate the basis so its vectors are as purely translation or rotation as can be
        _, _, Vt = np.linalg.svd(N[:3])
        N = N @ Vt.T
        sigmas = np.zeros(len(small)) if np.all(sigmas <= rtol * max(full[0], 1e-300)) else sigmas
    out = []
    for k in range(N.shape[1]):
        uv, uw = N[:3, k], N[3:, k]
        share_v = float(uv @ uv)
        share_w = max(0.0, 1.0 - share_v)
        nv, nw = np.sqrt(share_v), np.sqrt(share_w)
        out.append(
            LostDirection(
                float(sigmas[k]),
                uv / nv if nv > 1e-6 else np.zeros(3),
                uw / nw if nw > 1e-6 else np.zeros(3),
                share_v if nv > 1e-6 else 0.0,
                share_w if nw > 1e-6 else 0.0,
                float(length),
            )
        )
    return tuple(out)
