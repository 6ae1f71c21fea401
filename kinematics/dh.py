"""Denavit–Hartenberg tables: reading and checking the rows, and turning them into axes.

A row is a mapping with the keys ``joint`` (``"revolute"`` or ``"prismatic"``), ``a`` [m],
``alpha`` [rad], ``d`` [m], ``theta`` [rad], and optionally ``qlim`` (lower, upper) and
``name``. Every defect raises :class:`~kinematics.errors.RobotDefinitionError` naming the row
(counted from 1) and the key, and saying what was expected:

* a row that is not a mapping, keys that are not strings, missing keys, unknown keys (with
  the closest allowed key for a typo);
* ``joint`` not one of the two kinds (``"revolut"`` suggests ``"revolute"``);
* numbers: bools and strings (even ``"1e400"``) are not numbers; NaN, ±inf and integers
  beyond float range (``10**400``) are refused; lengths must be within
  ±:data:`~kinematics.validation.MAX_LENGTH` m and angles within
  ±:data:`~kinematics.validation.MAX_ANGLE` rad;
* ``qlim``: see :func:`~kinematics.validation.joint_limits` (±inf or a magnitude ≥ 1e15
  means unlimited, NaN is an error).
"""

from __future__ import annotations

import difflib
import functools
import operator
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Generic, TypeVar

import numpy as np

from .conventions import FloatArray
from .errors import RobotDefinitionError
from .parts import JOINT_TYPES, Axis, Convention, DHRow, Joint, check_choice
from .transforms import rot_x, rot_z, trans
from .validation import MAX_ANGLE, MAX_LENGTH, bounded_number, joint_limits, show

__all__ = [
    "DH_KEYS",
    "DH_OPTIONAL_KEYS",
    "parse_dh_table",
    "parse_dh_row",
    "dh_chain",
    "dh_factors",
    "MatrixOps",
    "NUMPY_OPS",
]

DH_KEYS = ("joint", "a", "alpha", "d", "theta")
"""Keys every DH row must have."""
DH_OPTIONAL_KEYS = ("qlim", "name")
"""Keys a DH row may have."""
_LENGTHS = ("a", "d")


def parse_dh_table(rows: object) -> tuple[DHRow, ...]:
    """Check a whole DH table (a non-empty sequence of row mappings) and return its rows.

    Example:
        >>> parse_dh_table([{"joint": "revolute", "a": 1, "alpha": 0, "d": 0, "theta": 0}])[0].a
        1.0
    """
    if isinstance(rows, (str, bytes, Mapping)) or not isinstance(rows, Sequence):
        raise RobotDefinitionError(
            f"DH rows: expected a sequence of mappings, one per joint, got {show(rows)}"
        )
    if len(rows) == 0:
        raise RobotDefinitionError("DH table is empty: expected at least one row")
    return tuple(parse_dh_row(i, row) for i, row in enumerate(rows))


def parse_dh_row(i: int, row: object) -> DHRow:
    """Check row ``i`` (0-based; messages count from 1) of a DH table and return it as a :class:`DHRow`."""
    where = f"DH row {i + 1}"
    if not isinstance(row, Mapping):
        raise RobotDefinitionError(
            f"{where}: expected a mapping with keys {', '.join(DH_KEYS)}, got {show(row)}"
        )
    bad_keys = [k for k in row if not isinstance(k, str)]
    if bad_keys:
        raise RobotDefinitionError(
            f"{where}: keys must be strings, got {', '.join(show(k) for k in bad_keys)}; "
            f"expected {', '.join(DH_KEYS)}"
        )
    missing = [k for k in DH_KEYS if k not in row]
    if missing:
        raise RobotDefinitionError(f"{where}: missing key(s) {', '.join(map(repr, missing))}")
    allowed = DH_KEYS + DH_OPTIONAL_KEYS
    unknown = sorted(set(row) - set(allowed))
    if unknown:
        hints = [difflib.get_close_matches(k, allowed, n=1) for k in unknown]
        named = ", ".join(
            f"{show(k)}" + (f" (did you mean {h[0]!r}?)" if h else "")
            for k, h in zip(unknown, hints, strict=True)
        )
        raise RobotDefinitionError(f"{where}: unknown key(s) {named}; allowed: {', '.join(allowed)}")
    kind = check_choice(row["joint"], JOINT_TYPES, f"{where}, key 'joint'")
    values = {
        k: bounded_number(
            row[k], *((MAX_LENGTH, "m") if k in _LENGTHS else (MAX_ANGLE, "rad")), f"{where}, key {k!r}"
        )
        for k in ("a", "alpha", "d", "theta")
    }
    qlim = joint_limits(row.get("qlim"), f"{where}, key 'qlim'")
    name = row.get("name", "")
    if not isinstance(name, str):
        raise RobotDefinitionError(f"{where}, key 'name': expected a string, got {show(name)}")
    return DHRow(
        "revolute" if kind == "revolute" else "prismatic",
        values["a"],
        values["alpha"],
        values["d"],
        values["theta"],
        qlim,
        name,
    )


M = TypeVar("M")


@dataclass(frozen=True)
class MatrixOps(Generic[M]):
    """The 4×4 factors a DH row is made of, in one math module (NumPy floats or SymPy expressions)."""

    eye: Callable[[], M]
    rot_x: Callable[[Any], M]
    rot_z: Callable[[Any], M]
    trans_x: Callable[[Any], M]
    trans_z: Callable[[Any], M]
    mul: Callable[[M, M], M]


NUMPY_OPS: MatrixOps[FloatArray] = MatrixOps(
    eye=lambda: np.eye(4),
    rot_x=rot_x,
    rot_z=rot_z,
    trans_x=lambda a: trans(x=a),
    trans_z=lambda d: trans(z=d),
    mul=operator.matmul,
)
"""The DH factors as float arrays (the numeric model)."""


def dh_factors(
    ops: MatrixOps[M], revolute: bool, convention: Convention, a: Any, alpha: Any, d: Any, theta: Any
) -> tuple[M, M]:
    """(T_parent_joint, T_joint_child) of one DH row, the joint's own motion left out.

    Standard: A = Rz(θ) Tz(d) Tx(a) Rx(α); modified (Craig): A = Rx(α) Tx(a) Rz(θ) Tz(d). The joint
    moves about (revolute) or along (prismatic) z between the two factors, so the row's θ
    (revolute) or d (prismatic) is the joint's offset and is not in either factor. Written once for
    :data:`NUMPY_OPS` and for the SymPy factors of :mod:`kinematics.symbolic.exact`.
    """

    def prod(*factors: M) -> M:
        return functools.reduce(ops.mul, factors)

    if convention == "modified":
        if revolute:
            return prod(ops.rot_x(alpha), ops.trans_x(a)), ops.trans_z(d)
        return prod(ops.rot_x(alpha), ops.trans_x(a), ops.rot_z(theta)), ops.eye()
    if revolute:
        return ops.eye(), prod(ops.trans_z(d), ops.trans_x(a), ops.rot_x(alpha))
    return ops.rot_z(theta), prod(ops.trans_x(a), ops.rot_x(alpha))


def dh_chain(dh: Sequence[DHRow], convention: Convention) -> tuple[tuple[Joint, ...], tuple[Axis, ...]]:
    """The joints and axes of a checked DH table in ``convention``.

    Standard: A = Rz(θ) Tz(d) Tx(a) Rx(α); modified (Craig): A = Rx(α) Tx(a) Rz(θ) Tz(d).
    Each row gives one joint (named ``name`` or ``q{i}``) and one axis moving about the z of its
    joint frame, with the row's ``theta`` (revolute) or ``d`` (prismatic) as the offset.
    """
    joints, axes = [], []
    for i, r in enumerate(dh):
        name_i = r.name or f"q{i + 1}"
        joints.append(Joint(name_i, r.joint, r.qlim))
        revolute = r.joint == "revolute"
        T_pj, T_jc = dh_factors(NUMPY_OPS, revolute, convention, r.a, r.alpha, r.d, r.theta)
        corners: tuple[tuple[float, float, float], ...] = ()
        if convention == "standard" and revolute:
            corners = ((0.0, 0.0, r.d),) if r.d != 0 and r.a != 0 else ()
        elif convention == "standard":
            # The slide ends at the moved joint origin; the link then runs along x by a.
            corners = ((0.0, 0.0, 0.0),) if r.a != 0 else ()
        offset = r.theta if revolute else r.d
        axes.append(Axis(name_i, r.joint, i, 1.0, offset, T_pj, T_jc, corners))
    return tuple(joints), tuple(axes)
