"""Snapping the rounded numbers of robot files to the exact values they stand for.

Robot files write right angles as ``1.5708``, ``1.57079632679`` or ``3.14159``. Kept as
exact rationals, cos(1.5708) ≈ −3.7e-6 survives as a number that multiplies through every
formula (a 7-joint arm's J becomes megabytes of LaTeX). A :class:`Snapper` replaces

* an angle (a DH α or θ offset, a joint offset) within :data:`SNAP_TOL` of a multiple of
  π/12 by that multiple;
* a fixed rotation whose entries are within :data:`SNAP_TOL` of the sines and cosines of
  multiples of 15° (and exactly orthogonal once snapped) by that exact rotation; any other
  rotation by Rz(yaw) Ry(pitch) Rx(roll) of its roll-pitch-yaw angles, each snapped as an angle
  (so it stays exactly orthogonal);
* a length within :data:`LENGTH_NOISE` of 0 (float noise such as 1e-17), or within the error
  that snapping its transform's rotation explains, by 0,

and records every change larger than float noise as a :class:`Snap`, so that the outputs can
say what was snapped and by how much. Values already exact to 1e-12 are not reported.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..transforms import matrix_to_rpy
from .cachecodec import register_dataclass
from .exact import SPECIAL_VALUES, exact_angle, exact_number

__all__ = ["SNAP_TOL", "LENGTH_NOISE", "Snap", "Snapper", "snap_summary"]

SNAP_TOL = 5e-4
"""Largest change [rad] made when snapping an angle to a multiple of π/12 (``1.5708`` is 3.7e-6 off)."""

LENGTH_NOISE = 1e-9
"""Lengths [m] smaller than this are float noise and become 0."""

_STEP = math.pi / 12
_QUIET = 1e-12  # changes below this are float noise of exact values: not reported
_SPECIAL = SPECIAL_VALUES
_SPECIAL_F = np.array([float(v) for v in _SPECIAL])


@register_dataclass
@dataclass(frozen=True)
class Snap:
    """One value replaced by the exact value it stands for.

    Attributes:
        where: What was snapped (``"DH row 2: alpha"``, ``"joint 'j2': fixed rotation (rpy)"``).
        given: The value as given (``"1.5708"``, ``"(1.5708, 0, 3.14159)"``).
        exact: The exact value used (``"pi/2"``, ``"(pi/2, 0, pi)"``).
        change: Size of the change [rad] for angles and rotations, [m] for lengths.
        unit: ``"rad"`` or ``"m"``.
    """

    where: str
    given: str
    exact: str
    change: float
    unit: str

    def text(self) -> str:
        """One line: ``DH row 2: alpha 1.5708 -> pi/2 (3.7e-06 rad)``."""
        return f"{self.where}: {self.given} -> {self.exact} ({self.change:.2g} {self.unit})"


def snap_summary(snaps: tuple[Snap, ...] | list[Snap]) -> str:
    """The note the outputs show: how many values were snapped, the largest change, and which."""
    if not snaps:
        return ""
    angles = [s.change for s in snaps if s.unit == "rad"]
    lengths = [s.change for s in snaps if s.unit == "m"]
    largest = []
    if angles:
        largest.append(f"{max(angles):.2g} rad")
    if lengths:
        largest.append(f"{max(lengths):.2g} m")
    return (
        f"{len(snaps)} value(s) of the robot file snapped to exact multiples of pi/12 (angles) or 0 "
        f"(float noise in lengths), largest change {' and '.join(largest)}: "
        + "; ".join(s.text() for s in snaps)
    )


def _num(x: float) -> str:
    return f"{x + 0.0:.12g}"  # + 0.0: no "-0"


def _angle_text(e: sp.Expr) -> str:
    return str(e)


class Snapper:
    """Turns a robot's floats into exact SymPy values, snapping rounded ones and recording it.

    Args:
        tol: Largest angle change [rad] accepted when snapping (0 disables snapping: only
            values exact to 1e-12 are recognised, as before snapping existed).
    """

    def __init__(self, tol: float = SNAP_TOL) -> None:
        self.tol = float(tol)
        self.snaps: list[Snap] = []

    @property
    def largest(self) -> float:
        """Largest angle change made so far [rad] (0 if none)."""
        return max((s.change for s in self.snaps if s.unit == "rad"), default=0.0)

    # ------------------------------------------------------------- scalars
    def snapped_angle(self, x: float) -> sp.Expr | None:
        """k·π/12 if ``x`` [rad] is within the tolerance of it (no record), else None."""
        k = round(float(x) / _STEP)
        if abs(float(x) - k * _STEP) <= max(self.tol, _QUIET):
            return sp.Rational(k, 12) * sp.pi
        return None

    def angle(self, x: float, where: str) -> sp.Expr:
        """An exact angle for ``x`` [rad]: a snapped multiple of π/12, or :func:`exact_angle`."""
        x = float(x)
        snapped = self.snapped_angle(x)
        if snapped is None:
            return exact_angle(x)
        change = abs(x - float(snapped))
        if change > _QUIET:
            self.snaps.append(Snap(where, _num(x), _angle_text(snapped), change, "rad"))
        return snapped

    def length(self, x: float, where: str, noise: float = LENGTH_NOISE) -> sp.Expr:
        """An exact length for ``x`` [m]: 0 if ``|x| <= noise``, else :func:`exact_number`."""
        x = float(x)
        if abs(x) <= (max(noise, LENGTH_NOISE) if self.tol > 0 else _QUIET):  # tol 0: the file's numbers
            if abs(x) > _QUIET:
                self.snaps.append(Snap(where, _num(x), "0", abs(x), "m"))
            return sp.Integer(0)
        return exact_number(x)

    # ------------------------------------------------------------ rotations
    def _entries(self, R: np.ndarray) -> sp.Matrix | None:
        """R with every entry snapped to a sine/cosine of a multiple of 15°, if exactly orthogonal."""
        out = []
        for v in R.ravel():
            k = int(np.argmin(np.abs(np.abs(v) - _SPECIAL_F)))
            if abs(abs(v) - _SPECIAL_F[k]) > max(self.tol, _QUIET):
                return None
            out.append(_SPECIAL[k] if v >= 0 else -_SPECIAL[k])
        E = sp.Matrix(3, 3, out)
        if E.free_symbols or not all(e == 0 for e in (E.T * E - sp.eye(3)).applyfunc(sp.expand)):
            return None
        return E if sp.expand(E.det()) == 1 else None

    def _rpy(self, R: np.ndarray) -> tuple[sp.Matrix, tuple[sp.Expr, ...], bool]:
        """Rz(yaw) Ry(pitch) Rx(roll) of R's angles, each snapped or exact to 12 digits; and whether
        an angle was snapped (moved by more than float noise)."""
        rpy, moved = [], False
        for a in matrix_to_rpy(R):
            s = self.snapped_angle(a)
            moved |= s is not None and abs(a - float(s)) > _QUIET
            rpy.append(s if s is not None else exact_angle(float(_num(a))))
        r, p, y = rpy
        cr, sr, cp, spi, cy, sy = sp.cos(r), sp.sin(r), sp.cos(p), sp.sin(p), sp.cos(y), sp.sin(y)
        Rz = sp.Matrix([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
        Ry = sp.Matrix([[cp, 0, spi], [0, 1, 0], [-spi, 0, cp]])
        Rx = sp.Matrix([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
        return Rz * Ry * Rx, (r, p, y), moved

    def rotation(self, R: np.ndarray, where: str) -> tuple[sp.Matrix, float]:
        """An exactly orthogonal SymPy rotation for the numeric rotation ``R``, and the change [rad]."""
        R = np.asarray(R, dtype=float)
        E = self._entries(R)
        rebuilt, angles, moved = self._rpy(R)
        if E is None:
            E = rebuilt
        else:
            moved = True
        exact = "rpy (" + ", ".join(_angle_text(a) for a in angles) + ")"
        numeric = np.array(E.evalf(), dtype=float)
        # ‖R₁ − R₂‖_F = 2√2 sin(φ/2) for the angle φ of R₁ᵀR₂
        change = 2 * math.asin(min(1.0, float(np.linalg.norm(numeric - R)) / (2 * math.sqrt(2))))
        if change > 2 * max(self.tol, _QUIET) + 1e-9:  # should not happen: keep the numbers as given
            return sp.Matrix(3, 3, [exact_number(v) for v in R.ravel()]), 0.0
        if change > _QUIET and moved:
            given = "rpy (" + ", ".join(_num(a) for a in matrix_to_rpy(R)) + ")"
            self.snaps.append(Snap(where + ": fixed rotation", given, exact, change, "rad"))
        return E, change

    def transform(self, T: np.ndarray, where: str) -> sp.Matrix:
        """An exact rigid 4×4 transform for ``T``: rotation snapped, translation noise removed."""
        T = np.asarray(T, dtype=float)
        R, change = self.rotation(T[:3, :3], where)
        M = sp.eye(4)
        M[:3, :3] = R
        p = T[:3, 3]
        noise = 2 * change * float(np.linalg.norm(p))
        for r, axis in enumerate("xyz"):
            M[r, 3] = self.length(float(p[r]), f"{where}: translation {axis}", noise)
        return M
