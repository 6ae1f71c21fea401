"""The course's derivations of the geometric Jacobian, each its own function, and a check that they agree.

All return the exact, unsimplified 6×n matrix in the joint symbols ``q1 … qn``
(rows [v; ω], v the velocity of the tool-frame origin), in base or tool axes:

* :func:`jacobian_differentiation`: explicit differentiation of the forward
  kinematics: v-rows ∂p/∂qⱼ, ω-rows from the skew matrix (∂R/∂qⱼ) Rᵀ;
* :func:`jacobian_whitney`: Whitney's columns zᵢ₋₁ × (pₙ − pᵢ₋₁), zᵢ₋₁
  (revolute) and zᵢ₋₁, 0 (prismatic);
* :func:`jacobian_velocity_propagation`: ω and v propagated link by link in
  each link's own frame up to the tool (Craig's outward iteration), then
  rotated to the base;
* :func:`jacobian_force_propagation`: a tool wrench propagated inward to
  joint torques, τ = Jᵀ F (Craig's inward iteration): the transpose view.

:func:`check_derivations` compares them exactly (for small robots) and
numerically against :func:`kinematics.jacobian` (for all).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..model import Robot
from ..numeric import jacobian as numeric_jacobian
from .chain import Frames, axis_motion, frames, frames_within
from .model import SymbolicModel, build_model, check_frame
from .trig import Deadline, is_zero
from .typeset.codegen import numeric_function

__all__ = [
    "jacobian_differentiation",
    "jacobian_whitney",
    "whitney_columns",
    "chain_elements",
    "carry_outward",
    "carry_inward",
    "jacobian_velocity_propagation",
    "jacobian_force_propagation",
    "DERIVATIONS",
    "Agreement",
    "check_derivations",
]

_EZ = sp.Matrix([0, 0, 1])


def _rotate(J: sp.Matrix, R: sp.Matrix) -> sp.Matrix:
    """blockdiag(R, R) · J."""
    return sp.Matrix.vstack(R * J[:3, :], R * J[3:, :])


def _in_frame(J_base: sp.Matrix, model: SymbolicModel, frame: str) -> sp.Matrix:
    return J_base if frame == "base" else _rotate(J_base, frames(model).tool[:3, :3].T)


def _joint_columns(model: SymbolicModel, axis_cols: list[sp.Matrix]) -> sp.Matrix:
    """Column j = Σ over axes k of ∂(axis value k)/∂qⱼ · axis column k (mimic joints add up)."""
    cols = []
    for qj in model.q:
        col = sp.zeros(6, 1)
        for value, c in zip(model.axis_value, axis_cols, strict=True):
            rate = sp.diff(value, qj)
            if rate != 0:
                col += rate * c
        cols.append(col)
    return sp.Matrix.hstack(*cols)


def whitney_columns(model: SymbolicModel, F: Frames, point: sp.Matrix) -> sp.Matrix:
    """Whitney's columns for the velocity of ``point``, all vectors in the axes of the frames ``F``."""
    cols = []
    for kind, W in zip(model.kinds, F.joint, strict=True):
        z, o = W[:3, 2], W[:3, 3]
        cols.append(
            sp.Matrix.vstack(z.cross(point - o), z)
            if kind == "revolute"
            else sp.Matrix.vstack(z, sp.zeros(3, 1))
        )
    return _joint_columns(model, cols)


def jacobian_whitney(
    robot: Robot,
    frame: str = "base",
    symbolic_params: bool = False,
    deadline: Deadline | None = None,
    exact: bool = False,
) -> sp.Matrix:
    """Whitney's geometric columns: [zᵢ₋₁ × (pₙ − pᵢ₋₁); zᵢ₋₁] or [zᵢ₋₁; 0], exact, unsimplified.

    With a ``deadline``, the chain's products stop being expanded once it has passed
    (:func:`.chain.frames_within`): the result is exact either way. ``exact``: the robot file's
    numbers as written, nothing snapped (:func:`.build_model`).
    """
    frame = check_frame(frame)
    model = build_model(robot, symbolic_params, exact)
    F, _ = frames_within(model, deadline)
    J = whitney_columns(model, F, F.tool[:3, 3])
    return J if frame == "base" else _rotate(J, F.tool[:3, :3].T)


def jacobian_differentiation(robot: Robot, frame: str = "base", symbolic_params: bool = False) -> sp.Matrix:
    """Differentiate the forward kinematics: v-rows ∂p/∂qⱼ, ω-rows vee((∂R/∂qⱼ) Rᵀ)."""
    frame = check_frame(frame)
    model = build_model(robot, symbolic_params)
    T = frames(model).tool
    R, p = T[:3, :3], T[:3, 3]
    cols = []
    for qj in model.q:
        S = R.diff(qj) * R.T  # Ṙ Rᵀ per unit q̇ⱼ: the skew matrix [ω]×
        cols.append(sp.Matrix([*p.diff(qj), S[2, 1], S[0, 2], S[1, 0]]))
    return _in_frame(sp.Matrix.hstack(*cols), model, frame)


def chain_elements(model: SymbolicModel) -> list[tuple[str, sp.Matrix | sp.Expr, int]]:
    """The chain as ("fixed", T, axis) and ("revolute"/"prismatic", axis value, axis) elements, base to
    tool; ``axis`` is the index of the axis the element belongs to (−1: the base, m: the tool)."""
    steps: list[tuple[str, sp.Matrix, int]] = [("fixed", model.base, -1)]
    for k, (kind, value, pj, jc) in enumerate(
        zip(model.kinds, model.axis_value, model.parent_joint, model.joint_child, strict=True)
    ):
        steps += [("fixed", pj, k), (kind, value, k), ("fixed", jc, k)]
    return steps + [("fixed", model.tool, len(model.kinds))]


def carry_outward(
    kind: str, X: sp.Matrix | sp.Expr, w: sp.Matrix, v: sp.Matrix, rate: Callable[[sp.Expr], sp.Expr]
) -> tuple[sp.Matrix, sp.Matrix]:
    """One element of Craig's outward iteration: ω and the origin velocity v (in the element's
    incoming axes) carried through it, in its outgoing axes; ``rate(value)`` is d(value)/dt."""
    if kind == "fixed":
        R, p = X[:3, :3], X[:3, 3]
        w, v = R.T * w, R.T * (v + w.cross(p))
    elif kind == "revolute":
        Rt = axis_motion(kind, X)[:3, :3].T
        w, v = Rt * (w + rate(X) * _EZ), Rt * v
    else:
        v = v + w.cross(X * _EZ) + rate(X) * _EZ
    return w.applyfunc(sp.expand), v.applyfunc(sp.expand)


def carry_inward(
    kind: str, X: sp.Matrix | sp.Expr, f: sp.Matrix, n: sp.Matrix
) -> tuple[sp.Matrix, sp.Matrix]:
    """One element of Craig's inward iteration: a force f and moment n (outgoing axes) carried to the
    element's incoming axes (f = R f', n = R n' + p × f)."""
    M = X if kind == "fixed" else axis_motion(kind, X)
    R, p = M[:3, :3], M[:3, 3]
    f = R * f
    return f.applyfunc(sp.expand), (R * n + p.cross(f)).applyfunc(sp.expand)


def jacobian_velocity_propagation(
    robot: Robot, frame: str = "base", symbolic_params: bool = False
) -> sp.Matrix:
    """Propagate (ω, v) outward link by link, each in its own frame; J_tool from the joint rates.

    Through a fixed transform (R, p): ω' = Rᵀ ω, v' = Rᵀ (v + ω × p). Through a
    revolute axis: ω' = Rz(θ)ᵀ (ω + θ̇ ẑ), v' = Rz(θ)ᵀ v; through a prismatic
    one: v' = v + ω × d ẑ + ḋ ẑ. The tool-frame J is the coefficient matrix
    of q̇; the base-frame J is blockdiag(R, R) J_tool.
    """
    frame = check_frame(frame)
    model = build_model(robot, symbolic_params)
    qd = [sp.Dummy(f"qd{i + 1}") for i in range(model.dof)]
    rate = lambda value: sum(sp.diff(value, qj) * d for qj, d in zip(model.q, qd, strict=True))
    w, v = sp.zeros(3, 1), sp.zeros(3, 1)
    for kind, X, _ in chain_elements(model):
        w, v = carry_outward(kind, X, w, v, rate)
    J_tool = sp.Matrix.vstack(v, w).jacobian(qd)
    return J_tool if frame == "tool" else _rotate(J_tool, frames(model).tool[:3, :3])


def jacobian_force_propagation(robot: Robot, frame: str = "base", symbolic_params: bool = False) -> sp.Matrix:
    """J from the transpose view τ = Jᵀ F: a tool wrench F = [f; n] propagated inward to joint torques.

    Through a fixed transform (R, p): f = R f', n = R n' + p × f. A revolute
    axis takes τ = n · ẑ, a prismatic one τ = f · ẑ. Jᵀ is the coefficient
    matrix of the wrench components; the returned matrix is its transpose.
    """
    frame = check_frame(frame)
    model = build_model(robot, symbolic_params)
    F = sp.Matrix(sp.symbols("fx fy fz nx ny nz", cls=sp.Dummy))
    f, n = F[:3, :], F[3:, :]
    tau = [sp.Integer(0)] * model.dof
    for kind, X, _ in reversed(chain_elements(model)):
        if kind != "fixed":
            torque = (n if kind == "revolute" else f)[2]
            for j, qj in enumerate(model.q):
                tau[j] += sp.diff(X, qj) * torque
        f, n = carry_inward(kind, X, f, n)
    J_tool = sp.Matrix(tau).jacobian(F).T
    return J_tool if frame == "tool" else _rotate(J_tool, frames(model).tool[:3, :3])


DERIVATIONS: dict[str, Callable[..., sp.Matrix]] = {
    "whitney": jacobian_whitney,
    "differentiation": jacobian_differentiation,
    "propagation": jacobian_velocity_propagation,
    "force": jacobian_force_propagation,
}
"""The derivations by name, spelled as :data:`kinematics.steps.METHODS` spells them (Whitney's columns is
the reference the others are compared with)."""


@dataclass(frozen=True)
class Agreement:
    """Result of :func:`check_derivations`.

    Attributes:
        robot: Robot name.
        frame: ``"base"`` or ``"tool"``.
        numeric: Derivation → max |J_derivation(q) − kinematics.jacobian(robot, q)| over the samples.
        symbolic: Derivation → whether J_derivation − J_whitney is identically zero
            (``None``: not checked).
        tol: Tolerance of the numeric comparison.
    """

    robot: str
    frame: str
    numeric: dict[str, float]
    symbolic: dict[str, bool | None]
    tol: float

    @property
    def ok(self) -> bool:
        """True if every numeric error is within ``tol`` and no symbolic check failed."""
        return all(e <= self.tol for e in self.numeric.values()) and False not in self.symbolic.values()


def _samples(robot: Robot, count: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    lim = robot.qlim
    lo = np.where(np.isfinite(lim[0]), lim[0], -np.pi)
    hi = np.where(np.isfinite(lim[1]), lim[1], np.pi)
    return rng.uniform(lo, hi, size=(count, robot.dof))


def check_derivations(
    robot: Robot,
    frame: str = "base",
    *,
    symbolic: bool | None = None,
    samples: int = 4,
    seed: int = 0,
    tol: float = 1e-9,
) -> Agreement:
    """Check that the four derivations agree, exactly and with the numeric Jacobian.

    Args:
        robot: The robot.
        frame: ``"base"`` or ``"tool"``.
        symbolic: Prove J_derivation − J_whitney ≡ 0 exactly (normal form modulo
            sin² + cos² = 1); default: only for robots with at most 4 joints.
        samples: Number of random configurations (within the joint limits) for the numeric check.
        seed: Seed of the random configurations.
        tol: Absolute tolerance of the numeric check.
    """
    frame = check_frame(frame)
    model = build_model(robot, False)
    symbolic = robot.dof <= 4 if symbolic is None else symbolic
    qs = _samples(robot, samples, seed)
    expected = [numeric_jacobian(robot, q, frame) for q in qs]
    results = {name: derive(robot, frame) for name, derive in DERIVATIONS.items()}
    numeric = {}
    for name, J in results.items():
        f = numeric_function(J, model)
        numeric[name] = max(float(np.max(np.abs(f(q) - Je))) for q, Je in zip(qs, expected, strict=True))
    ref = results["whitney"]
    sym: dict[str, bool | None] = {}
    for name, J in results.items():
        if name == "whitney" or not symbolic:
            sym[name] = None
        else:
            sym[name] = all(is_zero(e, model.q) for e in (J - ref))
    return Agreement(robot.name, frame, numeric, sym, tol)
