"""Measures of a Jacobian: singular values, manipulability, conditioning, ellipsoids.

Every function takes a Jacobian ``J`` of shape (6, n) — rows [v; ω] — or a
batch (N, 6, n), and a ``part`` naming which rows to measure:

* ``"full"``: all rows of ``J`` as given (a 6×n Jacobian mixes [m/s] and
  [rad/s]: prefer the parts below for anything physical);
* ``"linear"``: rows 0–2, the tool-point velocity [m/s];
* ``"angular"``: rows 3–5, the angular velocity [rad/s];
* ``"planar"``: rows (vx, vy, ωz), the task of a planar arm.

:func:`task_rows` picks the rows the course uses for a given robot (planar
task for planar arms, position for spatial arms with fewer than six joints,
all six otherwise). Manipulability of a robot with fewer joints than rows is
zero over the full Jacobian; measure its task rows instead.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import cast

import numpy as np
import numpy.typing as npt

from .conventions import PART_ROWS, FloatArray, Part
from .errors import ArrayError, OptionError
from .model import Robot
from .numeric import chain_frames
from .validation import finite_matrix, is_number, show

__all__ = [
    "Part",
    "PART_ROWS",
    "select_rows",
    "task_rows",
    "singular_values",
    "Measures",
    "measures",
    "condition_of",
    "manipulability",
    "condition_number",
    "inverse_condition_number",
    "rank",
    "null_space",
    "Ellipsoid",
    "velocity_ellipsoid",
    "force_ellipsoid",
    "DEFAULT_RTOL",
    "as_jacobian",
    "check_rtol",
    "part_rows",
    "is_planar_chain",
]

DEFAULT_RTOL = 1e-9
"""Relative tolerance: σ ≤ DEFAULT_RTOL · max(σmax, 1) counts as zero (rank, singularity)."""


def as_jacobian(J: object, what: str = "J") -> FloatArray:
    """``J`` as a float array of shape (6, n) or (N, 6, n) with finite entries, or ArrayError."""
    return finite_matrix(J, what, rows=6)


def check_rtol(rtol: object) -> float:
    """``rtol`` as a float in [0, 1), or OptionError."""
    if not (is_number(rtol) and 0.0 <= rtol < 1.0):
        raise OptionError(f"rtol must be a number in [0, 1), got {show(rtol)}")
    return float(rtol)


def _rows(part: object) -> tuple[int, ...]:
    if isinstance(part, str):
        if part not in PART_ROWS:
            raise OptionError(f"part must be one of {', '.join(map(repr, PART_ROWS))}, got {show(part)}")
        return PART_ROWS[part]
    if not isinstance(part, (Sequence, np.ndarray)) or isinstance(part, bytes):
        raise OptionError(
            f"part must be one of {', '.join(map(repr, PART_ROWS))} or row indices, got {show(part)}"
        )
    rows = tuple(part)
    ok = all(isinstance(r, (int, np.integer)) and not isinstance(r, bool) and 0 <= r < 6 for r in rows)
    if not rows or not ok or len(set(rows)) != len(rows):
        raise OptionError(f"rows of J must be distinct indices 0…5 (0-2 v, 3-5 ω), got {show(part)}")
    return tuple(int(r) for r in rows)


def part_rows(part: Part | tuple[int, ...]) -> tuple[int, ...]:
    """The row indices of J named by ``part`` (a :data:`PART_ROWS` key or distinct indices 0…5).

    Raises:
        OptionError: ``part`` is neither a part name nor distinct row indices 0…5.
    """
    return _rows(part)


def select_rows(J: npt.ArrayLike, part: Part | tuple[int, ...] = "full") -> FloatArray:
    """Rows of ``J`` (…, 6, n) named by ``part`` (a :data:`PART_ROWS` key or explicit row indices).

    Raises:
        ArrayError: ``J`` is not (6, n) or (N, 6, n), or not finite.
        OptionError: ``part`` is neither a part name nor distinct row indices 0…5.
    """
    J = as_jacobian(J)
    rows = _rows(part)
    if rows == PART_ROWS["full"]:
        return J
    return J[..., list(rows), :]


def task_rows(robot: Robot) -> tuple[int, ...]:
    """The rows of J that form the robot's task: what the course's det J and cond J refer to.

    ``robot.task`` when set; otherwise planar robots: (vx, vy, ωz), or (vx, vy)
    with fewer than three joints; spatial
    robots with fewer than 6 joints: the tool-point velocity (vx, vy, vz);
    otherwise all six rows.
    """
    if robot.task != "auto":
        return PART_ROWS[robot.task]
    if robot.planar:
        # Two joints cannot control the tool's orientation too: the task is its position.
        return PART_ROWS["planar"] if robot.dof >= 3 else (0, 1)
    if robot.dof < 6:
        return PART_ROWS["linear"]
    return PART_ROWS["full"]


def _sigma(A: FloatArray) -> FloatArray:
    """Singular values of A (…, m, n), descending."""
    return np.linalg.svd(A, compute_uv=False).astype(np.float64, copy=False)


def singular_values(J: npt.ArrayLike, part: Part | tuple[int, ...] = "full") -> FloatArray:
    """Singular values σ1 ≥ σ2 ≥ … of the selected rows, shape (k,) or (N, k), k = min(rows, n)."""
    return _sigma(select_rows(J, part))


def _zero_tol(sigma: FloatArray, rtol: float) -> FloatArray:
    return check_rtol(rtol) * np.maximum(sigma[..., :1], 1.0)


def manipulability(J: npt.ArrayLike, part: Part | tuple[int, ...] = "full") -> FloatArray | float:
    """Yoshikawa's manipulability w = √det(J Jᵀ) = Π σᵢ of the selected rows.

    Zero when the selected rows outnumber the joints (det(J Jᵀ) = 0): use a
    task part for such robots. Returns a float, or (N,) for a batch.
    """
    Js = select_rows(J, part)
    if Js.shape[-2] > Js.shape[-1]:
        w = np.zeros(Js.shape[:-2])
    else:
        w = np.prod(np.linalg.svd(Js, compute_uv=False), axis=-1)
    return float(w) if np.ndim(w) == 0 else w


def condition_number(
    J: npt.ArrayLike, part: Part | tuple[int, ...] = "full", rtol: float = DEFAULT_RTOL
) -> FloatArray | float:
    """2-norm condition number σmax / σmin of the selected rows; ``inf`` at a singularity.

    σmin is the smallest of min(rows, n) singular values; when it is below
    ``rtol · max(σmax, 1)`` the result is exactly ``inf``. A robot with
    fewer joints than rows has cond = ∞ over all rows (it cannot move in
    every direction): measure a part.
    """
    Js = select_rows(J, part)
    s = _sigma(Js)
    return condition_of(s, rtol, missing=Js.shape[-2] > Js.shape[-1])


def condition_of(sigma: FloatArray, rtol: float = DEFAULT_RTOL, missing: bool = False) -> FloatArray | float:
    """σmax / σmin of singular values ``sigma`` (descending, (k,) or (N, k)); ``inf`` when σmin is below
    ``rtol · max(σmax, 1)`` or when ``missing`` (fewer joints than rows: a direction has no σ at all).

    For singular values already at hand, e.g. the radii of a velocity ellipsoid (zero-padded to 3).
    """
    s = np.asarray(sigma, dtype=float)
    smin = s[..., -1]
    singular = (smin <= _zero_tol(s, rtol)[..., 0]) | missing
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.where(singular, np.inf, s[..., 0] / np.where(singular, 1.0, smin))
    return float(c) if np.ndim(c) == 0 else c


@dataclass(frozen=True)
class Measures:
    """Every measure of the selected rows of one Jacobian, from one SVD.

    Attributes:
        sigma: Singular values, descending (k,), k = min(rows, n).
        manipulability: Π σᵢ (0 with more rows than joints), as :func:`manipulability`.
        rank: Numerical rank, as :func:`rank`.
        condition: σmax / σmin (``inf`` when singular), as :func:`condition_number`.
    """

    sigma: FloatArray
    manipulability: float
    rank: int
    condition: float


def measures(J: npt.ArrayLike, part: Part | tuple[int, ...] = "full", rtol: float = DEFAULT_RTOL) -> Measures:
    """:func:`singular_values`, :func:`manipulability`, :func:`rank` and :func:`condition_number` of one
    Jacobian at the price of one SVD (what an app redrawing on every slider move needs)."""
    Js = select_rows(J, part)
    if Js.ndim != 2:
        raise ArrayError(f"measures takes one Jacobian (6, n), not a batch {Js.shape}")
    s = _sigma(Js)
    missing = Js.shape[0] > Js.shape[1]
    return Measures(
        sigma=s,
        manipulability=0.0 if missing else float(np.prod(s)),
        rank=int(np.sum(s > _zero_tol(s, rtol))),
        condition=float(condition_of(s, rtol, missing)),
    )


def inverse_condition_number(J: npt.ArrayLike, part: Part | tuple[int, ...] = "full") -> FloatArray | float:
    """σmin / σmax in [0, 1]: 1 is isotropic, 0 singular (finite everywhere, good for colour maps)."""
    c = condition_number(J, part)
    return 1.0 / c if np.ndim(c) == 0 else 1.0 / np.asarray(c)


def rank(
    J: npt.ArrayLike, part: Part | tuple[int, ...] = "full", rtol: float = DEFAULT_RTOL
) -> int | FloatArray:
    """Numerical rank: the number of σᵢ above ``rtol · max(σmax, 1)``."""
    s = singular_values(J, part)
    r = np.sum(s > _zero_tol(s, rtol), axis=-1)
    return int(r) if np.ndim(r) == 0 else r


def null_space(
    J: npt.ArrayLike, part: Part | tuple[int, ...] = "full", rtol: float = DEFAULT_RTOL
) -> FloatArray:
    """Orthonormal basis (n, k) of the joint rates that produce no motion of the selected rows.

    For one Jacobian only. Self-motions of a redundant arm, or the joint
    motion lost at a singularity.
    """
    Js = select_rows(J, part)
    if Js.ndim != 2:
        raise ArrayError(f"null_space takes one Jacobian (6, n), not a batch {Js.shape}")
    _, s, Vt = np.linalg.svd(Js)
    r = int(np.sum(s > _zero_tol(s, rtol)))
    return cast(FloatArray, Vt[r:].T.copy())


@dataclass(frozen=True)
class Ellipsoid:
    """An ellipsoid {x : x = Σ rᵢ aᵢ uᵢ, Σ uᵢ² ≤ 1} centred at the tool point.

    Attributes:
        axes: (3, 3) orthonormal, right-handed; column i is the direction of semi-axis i
            (expressed in the frame of the Jacobian rows).
        radii: (3,) semi-axis lengths, descending for velocity ellipsoids; a zero
            radius means the ellipsoid is flat in that direction, ``inf`` (force
            ellipsoid at a singularity) means unbounded.
    """

    axes: FloatArray
    radii: FloatArray

    def capped(self, cap: float) -> Ellipsoid:
        """The same ellipsoid with radii clipped to [0, cap] (for drawing)."""
        return Ellipsoid(self.axes, np.minimum(self.radii, cap))


def _three_row_svd(J: npt.ArrayLike, part: Part | tuple[int, ...]) -> tuple[FloatArray, FloatArray]:
    Js = select_rows(J, part)
    if Js.ndim != 2:
        raise ArrayError(f"an ellipsoid is drawn for one Jacobian (6, n), not a batch {Js.shape}")
    if Js.shape[0] != 3:
        raise OptionError(f"ellipsoids need three rows of J (part 'linear' or 'angular'), got {show(part)}")
    U, s, _ = np.linalg.svd(Js)  # U is 3×3 even when n < 3
    sigma = np.zeros(3)
    sigma[: len(s)] = s
    if np.linalg.det(U) < 0:
        U = U.copy()
        U[:, 2] *= -1.0
    return U, sigma


def velocity_ellipsoid(J: npt.ArrayLike, part: Part | tuple[int, ...] = "linear") -> Ellipsoid:
    """Manipulability (velocity) ellipsoid: {J q̇ : ‖q̇‖ ≤ 1}.

    Semi-axes σᵢ along the *left* singular vectors uᵢ of the selected 3 rows
    of J (use the base-frame Jacobian to get them in base axes). At a
    singularity it is flat (a radius is 0); it never has NaN.
    """
    U, sigma = _three_row_svd(J, part)
    return Ellipsoid(U, sigma)


def force_ellipsoid(
    J: npt.ArrayLike, part: Part | tuple[int, ...] = "linear", rtol: float = DEFAULT_RTOL
) -> Ellipsoid:
    """Force ellipsoid: {F : ‖Jᵀ F‖ ≤ 1}, semi-axes 1/σᵢ along the same uᵢ.

    Where σᵢ is zero (a singular direction) the radius is ``inf``: the
    structure holds any force along it. Cap with :meth:`Ellipsoid.capped` to draw.
    """
    U, sigma = _three_row_svd(J, part)
    tol = check_rtol(rtol) * max(sigma[0], 1.0)
    with np.errstate(divide="ignore"):
        radii = np.where(sigma > tol, 1.0 / np.where(sigma > tol, sigma, 1.0), np.inf)
    return Ellipsoid(U, radii)


_PLANAR_TOL = 1e-9


def is_planar_chain(robot: Robot) -> bool:
    """True when, at home and at a few other configurations (fixed seed, inside the limits), every
    revolute axis is parallel to the base z axis and every prismatic axis perpendicular to it."""
    n = robot.dof
    if n == 0 or len(robot.axes) != n:
        return False
    lo, hi = robot.qlim
    lo = np.where(np.isfinite(lo), lo, -np.pi)
    hi = np.where(np.isfinite(hi), hi, np.pi)
    rng = np.random.default_rng(5)
    for q in [np.asarray(robot.home, float)] + [rng.uniform(lo, hi) for _ in range(3)]:
        W, _ = chain_frames(robot, q)
        for ax, frame in zip(robot.axes, W, strict=True):
            z = frame[:3, 2]
            along = abs(float(z[2]))
            if ax.kind == "revolute" and abs(along - 1.0) > _PLANAR_TOL:
                return False
            if ax.kind != "revolute" and along > _PLANAR_TOL:
                return False
    return True
