"""Symbolic forward kinematics: the chain of a :class:`SymbolicModel` multiplied out.

The chain is a list of elementary transforms::

    base, PJ_1, M_1(q), JC_1, PJ_2, M_2(q), JC_2, …, PJ_m, M_m(q), JC_m, tool

(``PJ`` = ``T_parent_joint``, ``M`` = Rz(θ) or Tz(d), ``JC`` = ``T_joint_child``).
Products are expanded step by step: every entry stays a polynomial of degree
one in each (cos qᵢ, sin qᵢ), which keeps them small.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import sympy as sp

from .exact import rot_z, trans
from .model import SymbolicModel
from .trig import Deadline

__all__ = ["Frames", "frames", "frames_within", "relative_frames", "axis_motion", "rigid_inverse", "multiply"]


def axis_motion(kind: str, value: sp.Expr) -> sp.Matrix:
    """The moving transform of an axis: Rz(θ) (revolute) or Tz(d) (prismatic)."""
    return rot_z(value) if kind == "revolute" else trans(z=value)


def rigid_inverse(T: sp.Matrix) -> sp.Matrix:
    """Inverse of a 4×4 rigid transform: [Rᵀ, −Rᵀ p]."""
    R, p = T[:3, :3], T[:3, 3]
    out = sp.eye(4)
    out[:3, :3] = R.T
    out[:3, 3] = -R.T * p
    return out


def multiply(A: sp.Matrix, B: sp.Matrix) -> sp.Matrix:
    """A · B with every entry expanded."""
    return (A * B).applyfunc(sp.expand)


@dataclass(frozen=True, eq=False)
class Frames:
    """Frames of a chain in one reference frame (4×4 SymPy matrices).

    Attributes:
        joint: ``T_ref_joint`` of every axis, before it moves: its z axis is the
            joint axis and its origin lies on it (Whitney's zᵢ₋₁, pᵢ₋₁).
        link: ``T_ref_link`` of every axis (the DH frame i for a DH robot).
        tool: ``T_ref_tool``.
    """

    joint: tuple[sp.Matrix, ...]
    link: tuple[sp.Matrix, ...]
    tool: sp.Matrix


def _elements(model: SymbolicModel) -> list[sp.Matrix]:
    out = [model.base]
    for kind, value, pj, jc in zip(
        model.kinds, model.axis_value, model.parent_joint, model.joint_child, strict=True
    ):
        out += [pj, axis_motion(kind, value), jc]
    return out + [model.tool]


@functools.lru_cache(maxsize=64)
def frames(model: SymbolicModel) -> Frames:
    """All frames of the chain in the robot's base frame (cached per model)."""
    return relative_frames(model, 0)


def frames_within(model: SymbolicModel, deadline: Deadline | None) -> tuple[Frames, bool]:
    """:func:`frames`, but products are left unexpanded once ``deadline`` has passed.

    Expanding the chain of an arm whose twists are not multiples of π/12 takes seconds per
    product; unexpanded, the frames are exact and quick to build (and the simplification that
    follows expands each entry when it has the time). Returns the frames and whether they are
    fully expanded (then they equal :func:`frames`).
    """
    if deadline is None:
        return frames(model), True
    E = _elements(model)
    out, acc, expanded = [], sp.eye(4), True
    for el in E:
        expanded = expanded and not deadline.expired()
        acc = multiply(acc, el) if expanded else acc * el
        out.append(acc)
    m = len(model.kinds)
    F = Frames(tuple(out[1 + 3 * a] for a in range(m)), tuple(out[3 + 3 * a] for a in range(m)), out[-1])
    return F, expanded


@functools.lru_cache(maxsize=256)
def relative_frames(model: SymbolicModel, k: int) -> Frames:
    """All frames of the chain expressed in frame ``k``: 0 the base frame, i ≥ 1 link frame i.

    Seen from a frame in the middle of the chain the expressions are shorter:
    joints before k appear only through the inverse of their own motion.
    Used to compute determinants in the frame where they are smallest.
    """
    E = _elements(model)
    ref = 0 if k == 0 else 1 + 3 * k  # index of the first element after the reference frame
    before = [sp.eye(4)] * ref  # before[j] = T_ref_(frame before element j) = inv(E[j] ⋯ E[ref-1])
    acc = sp.eye(4)
    for idx in range(ref - 1, -1, -1):
        acc = multiply(acc, rigid_inverse(E[idx]))
        before[idx] = acc
    after, acc = [], sp.eye(4)
    for idx in range(ref, len(E)):
        acc = multiply(acc, E[idx])
        after.append(acc)

    def frame_after(idx: int) -> sp.Matrix:
        if idx >= ref:
            return after[idx - ref]
        return before[idx + 1] if idx + 1 < ref else sp.eye(4)

    m = len(model.kinds)
    joint = tuple(frame_after(1 + 3 * a) for a in range(m))
    link = tuple(frame_after(3 + 3 * a) for a in range(m))
    return Frames(joint, link, after[-1])
