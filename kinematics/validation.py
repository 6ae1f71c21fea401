"""Checks shared by every way a robot is built (DH table, robot file, URDF, by hand).

Each check returns the clean value or raises :class:`~kinematics.errors.RobotDefinitionError`
with a message that starts with ``where`` (the row, key, joint or attribute) and says what was
expected. The bounds keep every later computation finite:

* :data:`MAX_LENGTH`: lengths (DH ``a`` and ``d``, base/tool and joint-origin translations,
  prismatic offsets and joint values) [m];
* :data:`MAX_ANGLE`: angles (DH ``alpha`` and ``theta``, revolute offsets and joint values) [rad];
* :data:`UNLIMITED`: a joint limit of at least this magnitude (``±1e16`` in URDFs, ``±inf``,
  ``1e308``) is a sentinel for "no limit on that side";
* :data:`MAX_MULTIPLIER` (mimic multipliers) and :data:`MAX_AXES` (moving axes per robot).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping, Sequence
from typing import TypeGuard

import numpy as np

from .conventions import FloatArray
from .errors import ArrayError, RobotDefinitionError

__all__ = [
    "MAX_LENGTH",
    "MAX_ANGLE",
    "UNLIMITED",
    "MAX_MULTIPLIER",
    "MAX_AXES",
    "show",
    "is_number",
    "real_number",
    "bounded_number",
    "joint_limits",
    "frozen_array",
    "finite_matrix",
    "finite_array",
]

MAX_LENGTH = 1e15
"""Largest length [m] accepted anywhere: the magnitude that marks an unlimited joint limit, so
that every finite limit is a value the kinematics accept, and small enough that products of
lengths (σ² in damped least squares, J̇) stay far from overflow."""
MAX_ANGLE = 1e18
"""Largest angle [rad] accepted: beyond about 5.7e16 rad (2⁵³ · 2π) a float cannot even tell
which turn it is on. Angles are reduced modulo 2π before sines and cosines are formed, so any
accepted angle gives a rigid transform."""
UNLIMITED = 1e15
"""A joint limit with magnitude ≥ this (or infinite) means "unlimited on that side"."""
MAX_MULTIPLIER = 1e6
"""Largest |multiplier| of a mimic axis (axis value = multiplier · q + offset)."""
MAX_AXES = 1000
"""Most moving axes a robot may have (every kernel is linear in the axes; this bounds memory)."""


def show(x: object, limit: int = 40) -> str:
    """``repr(x)`` cut to ``limit`` characters (huge integers and long texts stay readable)."""
    try:
        text = repr(x)
    except ValueError:  # int too large for its decimal representation
        return f"<{type(x).__name__} too large to print>"
    return text if len(text) <= limit else f"{text[: limit - 1]}…"


def is_number(x: object) -> TypeGuard[float]:
    """True for a real number (int, float, NumPy int or float, Fraction), False for bools and all else.

    (Typed as a guard for ``float``: every such number compares and converts like one.)
    """
    return isinstance(x, numbers.Real) and not isinstance(x, (bool, np.bool_))


def _describe(x: object) -> str:
    if isinstance(x, (str, bytes)):
        return f"{show(x)} (a {'string' if isinstance(x, str) else 'bytes value'})"
    if isinstance(x, (bool, np.bool_)):
        return f"{x!r} (a bool)"
    return f"{show(x)} (a {type(x).__name__})"


def real_number(x: object, where: str) -> float:
    """``x`` as a finite float: an int or float (NumPy ones included), not a bool nor a string.

    Raises:
        RobotDefinitionError: ``x`` is not a real number, is NaN or infinite, or is an
            integer beyond float range (``10**400``).
    """
    if not is_number(x):
        raise RobotDefinitionError(f"{where}: expected a number, got {_describe(x)}")
    try:
        v = float(x)
    except (OverflowError, ValueError, TypeError):
        raise RobotDefinitionError(
            f"{where}: expected a finite number, got {show(x)}, beyond the range of a float (±1.8e308)"
        ) from None
    if not math.isfinite(v):
        raise RobotDefinitionError(f"{where}: expected a finite number, got {v}")
    return v


def bounded_number(x: object, bound: float, unit: str, where: str) -> float:
    """``x`` as a finite float with ``|x| ≤ bound`` (``unit`` names the unit in the message)."""
    v = real_number(x, where)
    if abs(v) > bound:
        raise RobotDefinitionError(
            f"{where}: {v:g} {unit} is out of range; expected |value| ≤ {bound:g} {unit}"
        )
    return v


def _limit_value(x: object, where: str) -> float:
    """A limit: a real number where ±inf and integers beyond float range stand for "no limit"."""
    if not is_number(x):
        raise RobotDefinitionError(f"{where}: expected a number, got {_describe(x)}")
    try:
        v = float(x)
    except OverflowError:
        v = math.inf if x > 0 else -math.inf
    except (ValueError, TypeError):
        raise RobotDefinitionError(f"{where}: expected a number, got {_describe(x)}") from None
    if math.isnan(v):
        raise RobotDefinitionError(f"{where}: expected a number, got NaN")
    return v


def joint_limits(qlim: object, where: str) -> tuple[float, float] | None:
    """Normalised joint limits: a finite ``(lower, upper)`` with lower < upper, or ``None``.

    Both sides of magnitude ≥ :data:`UNLIMITED` (``-1e16``, ``-inf``, ``1e308``) mean an unlimited
    joint (``None``). One such side beside a finite one is refused in words (limits bound sliders
    and sampling, which need both ends; dropping the finite one would change the file silently).
    A lower limit of ``+inf`` (or an upper limit of ``-inf``) is not a sentinel but an error, as is
    NaN.

    Args:
        qlim: ``None`` or a pair (lower, upper) [rad] or [m].
        where: Start of the error message (``"DH row 2, key 'qlim'"``).
    """
    if qlim is None:
        return None
    if (
        isinstance(qlim, (str, bytes, Mapping))
        or not isinstance(qlim, (Sequence, np.ndarray))
        or len(qlim) != 2
    ):
        raise RobotDefinitionError(f"{where}: expected (lower, upper), got {show(qlim)}")
    lo, hi = (_limit_value(v, where) for v in qlim)
    if lo >= UNLIMITED or hi <= -UNLIMITED:
        raise RobotDefinitionError(
            f"{where}: lower limit {lo:g} must be below upper limit {hi:g}; "
            f"an unlimited side is written -inf (lower) or inf (upper), or beyond ±{UNLIMITED:g}"
        )
    if lo <= -UNLIMITED and hi >= UNLIMITED:
        return None
    if lo <= -UNLIMITED or hi >= UNLIMITED:  # dropping the finite side would be a silent change
        side, bound = ("lower", hi) if lo <= -UNLIMITED else ("upper", lo)
        raise RobotDefinitionError(
            f"{where}: a joint limited on one side only ({side} unlimited, the other {bound:g}) is "
            "not supported: give both limits, or neither for an unlimited joint"
        )
    if not lo < hi:
        raise RobotDefinitionError(f"{where}: lower limit {lo} must be below upper limit {hi}")
    return (lo, hi)


def frozen_array(a: object, dtype: type = float) -> FloatArray:
    """A read-only copy of ``a`` as an array of ``dtype``."""
    out: FloatArray = np.array(a, dtype=dtype)
    out.flags.writeable = False
    return out


def finite_matrix(J: object, what: str = "J", rows: int | None = None) -> FloatArray:
    """``J`` as a finite float array of shape (m, n) or a batch (N, m, n), or ArrayError.

    Args:
        J: The array.
        what: Its name in messages.
        rows: The number of rows m required (6 for a Jacobian), or None for any non-empty matrix.
    """
    try:
        A = np.asarray(J)
    except (TypeError, ValueError, OverflowError):
        raise ArrayError(f"{what} must be an array of numbers, got {show(J)}") from None
    if A.dtype.kind not in "iuf":
        raise ArrayError(f"{what} must hold ints or floats, got dtype {A.dtype}")
    A = A.astype(float, copy=False)
    if rows is not None and (A.ndim not in (2, 3) or A.shape[-2] != rows):
        raise ArrayError(f"{what} should have shape ({rows}, n) or (N, {rows}, n), got {A.shape}")
    if rows is None and (A.ndim not in (2, 3) or 0 in A.shape):
        raise ArrayError(f"{what} should have shape (m, n) or (N, m, n), got {A.shape}")
    if not np.isfinite(A).all():
        raise ArrayError(f"{what} contains NaN or infinity")
    return A


def finite_array(x: object, shapes: tuple[tuple[int, ...], ...], what: str) -> FloatArray:
    """``x`` as a float array of one of ``shapes`` with finite entries, or ArrayError naming ``what``."""
    try:
        a = np.asarray(x)
    except (TypeError, ValueError, OverflowError):
        raise ArrayError(f"{what} must be an array of numbers, got {show(x)}") from None
    if a.dtype.kind not in "iuf" or a.shape not in shapes:
        expected = " or ".join(str(s) for s in shapes)
        raise ArrayError(f"{what} must be numbers of shape {expected}, got {show(x)}")
    a = a.astype(float, copy=False)
    if not np.isfinite(a).all():
        raise ArrayError(f"{what} contains NaN or infinity")
    return a
