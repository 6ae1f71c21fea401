"""Inverse velocity kinematics: pseudo-inverse, damped least squares, null-space projector.

The course's resolved-rate step is ``q̇ = J⁺ v`` (``J⁻¹ v`` for a square,
regular J). Near a singularity ``J⁺`` blows up; damped least squares trades
accuracy for bounded joint rates. Redundant arms add self-motion through
the null-space projector ``N = I − J⁺ J``.
"""

from __future__ import annotations

import math
from typing import cast

import numpy as np
import numpy.typing as npt

from .analysis import DEFAULT_RTOL, check_rtol
from .conventions import FloatArray
from .errors import ArrayError, OptionError
from .validation import finite_matrix, is_number, show

__all__ = ["pinv", "dls", "nullspace_projector", "solve_rates"]


def pinv(J: npt.ArrayLike, rtol: float = DEFAULT_RTOL) -> FloatArray:
    """Moore–Penrose pseudo-inverse J⁺ (n, m), singular values below ``rtol · max(σmax, 1)`` dropped.

    Equals J⁻¹ for a square regular J; gives the minimum-norm least-squares
    solution q̇ = J⁺ v otherwise. Works on batches (N, m, n).
    """
    J = finite_matrix(J)
    U, s, Vt = np.linalg.svd(J, full_matrices=False)
    tol = check_rtol(rtol) * np.maximum(s[..., :1], 1.0)
    with np.errstate(divide="ignore"):
        s_inv = np.where(s > tol, 1.0 / np.where(s > tol, s, 1.0), 0.0)
    return cast(FloatArray, np.swapaxes(Vt, -1, -2) @ (s_inv[..., :, None] * np.swapaxes(U, -1, -2)))


def dls(J: npt.ArrayLike, damping: float = 0.05) -> FloatArray:
    """Damped least-squares inverse Jᵀ (J Jᵀ + λ² I)⁻¹ (n, m), λ = ``damping``.

    Each singular value σ maps to σ / (σ² + λ²) ≤ 1 / (2λ): joint rates stay
    bounded at a singularity. λ = 0 gives the pseudo-inverse of a full-row-rank J.
    """
    if not (is_number(damping) and 0 <= damping < math.inf):
        raise OptionError(f"damping must be a finite number ≥ 0, got {show(damping)}")
    J = finite_matrix(J)
    U, s, Vt = np.linalg.svd(J, full_matrices=False)
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.where(s**2 + damping**2 > 0, s / (s**2 + damping**2), 0.0)
    return cast(FloatArray, np.swapaxes(Vt, -1, -2) @ (f[..., :, None] * np.swapaxes(U, -1, -2)))


def nullspace_projector(J: npt.ArrayLike, rtol: float = DEFAULT_RTOL) -> FloatArray:
    """N = I − J⁺ J (n, n): projects joint rates onto motions that leave the task still.

    ``q̇ = J⁺ v + N q̇₀`` reaches the task velocity v while following q̇₀ as
    closely as the task allows (self-motion of a redundant arm).
    """
    J = finite_matrix(J)
    n = J.shape[-1]
    return np.eye(n) - pinv(J, rtol) @ J


def solve_rates(J: npt.ArrayLike, v: npt.ArrayLike, damping: float = 0.0) -> FloatArray:
    """Joint rates for a desired task velocity: J⁺ v (``damping`` = 0) or the DLS solution."""
    J = finite_matrix(J)
    v = _vector(v, J)
    inv = pinv(J) if damping == 0 else dls(J, damping)
    return inv @ v


def _vector(v: object, J: FloatArray) -> FloatArray:
    """``v`` as a finite float array with one component per row of ``J``, or ArrayError."""
    try:
        a = np.asarray(v)
    except (TypeError, ValueError, OverflowError):
        raise ArrayError(f"v must be an array of numbers, got {show(v)}") from None
    if a.dtype.kind not in "iuf" or a.ndim == 0 or a.shape[-1] != J.shape[-2]:
        raise ArrayError(f"v must hold {J.shape[-2]} numbers (one per row of J), got {show(v)}")
    a = a.astype(float, copy=False)
    if not np.isfinite(a).all():
        raise ArrayError("v contains NaN or infinity")
    return a
