"""The course's derivations of J, step by step: what a teacher writes on the board.

:func:`derivation_steps` returns the working of one method as a tuple of :class:`.step.Step`:

1. shared by all methods (section ``"transforms"``): the link transforms ``A1 … An``
   (``{}^{i-1}T_{i}``; the robot's base transform ``"base"`` first and the tool transform
   ``"Atool"`` last when they are not the identity) and their products ``T0_1 … T0_n``
   (``{}^{0}T_{i}``) and ``T0_tool``;
2. the method's own steps (:mod:`.steps_methods`):

   * ``"whitney"``: for joint i, ``whitney.z{i-1}``, ``whitney.p{i-1}``, ``whitney.r{i-1}``
     (pₙ − pᵢ₋₁; revolute joints only) and ``whitney.col{i}``;
   * ``"differentiation"``: ``diff.dp{i}`` (∂p/∂qᵢ), ``diff.S{i}`` ((∂R/∂qᵢ) Rᵀ, the skew
     matrix of the ω part) and ``diff.col{i}``;
   * ``"propagation"``: ``prop.w{i}``, ``prop.v{i}`` (link i's ω and origin velocity in its own
     axes, Craig's outward iteration, with the joint rates q̇ as :attr:`.Step.inputs`), then
     ``prop.wtool``, ``prop.vtool`` (when there is a tool transform) and, for the base frame,
     ``prop.w_base``, ``prop.v_base`` (rotated to the base axes);
   * ``"force"``: inward from the tool, ``force.f{i}``, ``force.n{i}`` (in the axes of joint i's
     frame, z along its axis), ``force.tau{i}``, with the tool wrench [f; n] (in the axes of
     ``frame``) as :attr:`.Step.inputs`; then ``force.JT`` = Jᵀ;

   (the index in a key is always the joint's: ``whitney.z0`` is the axis of joint 1 whatever
   the convention calls it; the :attr:`.Step.lhs` uses the convention's names);
3. section ``"result"``: ``"J"`` assembled from the method's own steps (for the tool frame
   after ``"J_base"`` rotated, for Whitney and differentiation), and ``"detJ"``: det J of the
   square task rows, or det(J Jᵀ), factored, with its singular sets (:attr:`.Step.singular`),
   when it could be computed in time.

Everything is exact; each step is simplified (:mod:`.simplify`) within one shared time limit,
past which the remaining steps stay exact but unsimplified (their notes say so). Results are
kept in memory per (robot, method, frame, symbolic_params).
"""

from __future__ import annotations

import dataclasses
import functools
from typing import Literal

import sympy as sp

from ...model import Robot
from ...text import N_, words
from ..chain import frames_within, multiply
from ..core import DEFAULT_TIMEOUT, check_timeout
from ..model import SymbolicError, build_model, check_frame
from ..singular import determinant
from ..trig import Deadline
from ..typeset.render import det_label
from .methods import METHOD_STEPS, Context, rotate_rows
from .step import DHRow, Step

__all__ = ["METHODS", "Method", "derivation_steps", "dh_rows", "Step", "DHRow"]

Method = str
"""A key of :data:`METHODS`."""
METHODS: tuple[str, ...] = tuple(METHOD_STEPS)
"""The derivations :func:`derivation_steps` knows: the keys of :data:`.methods.METHOD_STEPS`, spelled as
:data:`kinematics.steps.METHODS` spells them."""


def dh_rows(robot: Robot, symbolic_params: bool = False) -> tuple[DHRow, ...]:
    """The robot's DH table with symbolic θ, d, a, α per row (standard or modified convention).

    Angles are exact (π/2 stays π/2; rounded values of the file snapped as in :mod:`.snap`),
    lengths exact decimals, or symbols (the course's letters) with ``symbolic_params``. The
    joint variable appears in θᵢ (revolute) or dᵢ (prismatic). A robot without a DH table
    (a URDF chain) has none: the result is empty.

    Raises:
        SymbolicError: ``symbolic_params`` for a robot without a DH table.
    """
    model = build_model(robot, symbolic_params)
    if not model.dh:
        return ()
    return tuple(
        DHRow(i + 1, kind, robot.joints[j].name, *values, model.q[j], robot.convention or "standard")
        for i, (kind, j, values) in enumerate(zip(model.kinds, model.axis_joint, model.dh, strict=True))
    )


def _is_identity(T: sp.Matrix) -> bool:
    return bool(T == sp.eye(4))


def _transform_steps(ctx: Context) -> list[Step]:
    m, F = ctx.model, ctx.F
    out: list[Step] = []
    dh = bool(m.dh)
    what = (
        N_("{A} = {T}, the DH link transform of joint {joint}{formula}")
        if dh
        else N_("{A} = {T}, the link transform of the chain of joint {joint}{formula}")
    )
    if not _is_identity(m.base):
        out.append(
            ctx.step(
                "base",
                words(N_("The robot's base transform: frame 0 seen from the base")),
                "T_{\\mathrm{base}}",
                m.base,
                None,
            )
        )
    for k, (kind, value) in enumerate(zip(m.kinds, m.axis_value, strict=True)):
        A = multiply(multiply(m.parent_joint[k], _axis(kind, value)), m.joint_child[k])
        formula = ""
        if dh:
            formula = (
                ": Rz(θ) Tz(d) Tx(a) Rx(α)"
                if m.robot.convention == "standard"
                else ": Rx(α) Tx(a) Rz(θ) Tz(d)"
            )
        out.append(
            ctx.step(
                f"A{k + 1}",
                words(what, A=f"A{_sub(k + 1)}", T=f"{_sup(k)}T{_sub(k + 1)}", joint=k + 1, formula=formula),
                f"A_{{{k + 1}}}",
                A,
                m.axis_joint[k],
            )
        )
    if not _is_identity(m.tool):
        n = len(m.kinds)
        out.append(
            ctx.step(
                "Atool",
                words(N_("The tool transform: the tool frame seen from frame {n}"), n=n),
                f"{{}}^{{{n}}}T_{{\\mathrm{{tool}}}}",
                m.tool,
                None,
            )
        )
    for k in range(len(m.kinds)):
        title = f"⁰T{_sub(k + 1)} = " + (" ".join(f"A{_sub(i + 1)}" for i in range(k + 1)) if k else "A₁")
        if not _is_identity(m.base):
            title = title.replace("= ", "= T_base ", 1)
        out.append(
            ctx.step(
                f"T0_{k + 1}",
                words(N_("{T}: frame {i} in the base frame"), T=title, i=k + 1),
                f"{{}}^{{0}}T_{{{k + 1}}}",
                F.link[k],
                m.axis_joint[k],
            )
        )
    if not _is_identity(m.tool):
        out.append(
            ctx.step(
                "T0_tool",
                words(
                    N_("{T} = {product}: the tool pose ({p} is its origin)"),
                    T="⁰T_tool",
                    product=f"⁰T{_sub(len(m.kinds))} · {_sup(len(m.kinds))}T_tool",
                    p="pₙ",
                ),
                "{}^{0}T_{\\mathrm{tool}}",
                F.tool,
                None,
            )
        )
    return out


def _axis(kind: str, value: sp.Expr) -> sp.Matrix:
    from ..chain import axis_motion

    return axis_motion(kind, value)


_SUB = str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉")
_SUP = str.maketrans("0123456789", "⁰¹²³⁴⁵⁶⁷⁸⁹")


def _sub(i: int) -> str:
    return str(i).translate(_SUB)


def _sup(i: int) -> str:
    return str(i).translate(_SUP)


_DET_TITLES = {
    ("all", True): N_("{det} of all six rows, factored: J is singular where a factor vanishes"),
    ("all", False): N_("{det} of all six rows, factored: never zero: J never loses rank"),
    ("position", True): N_("{det} of the position rows, factored: J is singular where a factor vanishes"),
    ("position", False): N_("{det} of the position rows, factored: never zero: J never loses rank"),
    ("orientation", True): N_(
        "{det} of the orientation rows, factored: J is singular where a factor vanishes"
    ),
    ("orientation", False): N_("{det} of the orientation rows, factored: never zero: J never loses rank"),
    ("task", True): N_("{det} of the task rows, factored: J is singular where a factor vanishes"),
    ("task", False): N_("{det} of the task rows, factored: never zero: J never loses rank"),
}
"""det J's caption by the rows it is of and whether J has singular sets (whole sentences for the catalogs)."""


def _det_step(ctx: Context, robot: Robot, symbolic_params: bool) -> Step | None:
    det = determinant(robot, symbolic_params=symbolic_params, deadline=ctx.deadline)
    if det.expr is None:
        ctx.notes.extend(det.notes or ("det J was not computed within the time limit",))
        return None
    kind = "det(J Jᵀ)" if det.gram else "det J"
    named: dict[tuple[int, ...], str] = {(0, 1, 2): "position", (3, 4, 5): "orientation"}
    rows = "all" if len(det.rows) == 6 else named.get(det.rows, "task")
    # The sets themselves are typeset under the formula (Step.singular: the handouts and the Derive tab
    # show "s₂ = 0 ⇒ θ₂ ∈ {0, π}" in the joints' notation), not repeated here as SymPy text.
    title = words(_DET_TITLES[rows, bool(det.singular_sets)], det=kind)
    return Step(
        "detJ",
        title,
        det_label(det.rows, det.gram, robot.dof, latex=True),
        sp.Matrix([[det.expr]]),
        None,
        ctx.model,
        "result",
        notes=tuple(det.notes),
        singular=det.singular_sets,
    )


@functools.lru_cache(maxsize=32)
def _cached(
    robot: Robot, method: str, frame: str, symbolic_params: bool, timeout: float | None
) -> tuple[Step, ...]:
    return _build(robot, method, frame, symbolic_params, Deadline(timeout))


def _build(
    robot: Robot, method: str, frame: str, symbolic_params: bool, deadline: Deadline
) -> tuple[Step, ...]:
    model = build_model(robot, symbolic_params)
    F, _ = frames_within(model, deadline)
    ctx = Context(model, F, deadline, frame)
    steps = _transform_steps(ctx)
    own, J, axes = METHOD_STEPS[method](ctx)
    steps += own
    if axes != frame:  # Whitney and differentiation give J in the base axes, force propagation in the tool's
        what = {
            "base": N_("J in the base axes: the columns side by side"),
            "tool": N_("J in the tool axes"),
        }[axes]
        lhs = {"base": "J_{\\mathrm{base}}", "tool": "J_{\\mathrm{tool}}"}[axes]
        steps.append(ctx.step(f"J_{axes}", words(what), lhs, J, None, "result"))
        R = F.tool[:3, :3]
        J = rotate_rows(J, R.T if frame == "tool" else R)
    title = {
        "base": N_(
            "J: the columns side by side, rows [v; ω] in the base axes (v: velocity of the tool origin)"
        ),
        "tool": N_("J in the tool axes: blockdiag(Rᵀ, Rᵀ) J_base, R the tool's rotation"),
    }[frame]
    if method == "propagation":
        title = (
            N_("J: the coefficients of q̇ in [v; ω] (base axes)")
            if frame == "base"
            else N_("J: the coefficients of q̇ in [v; ω] (tool axes)")
        )
    if method == "force" and frame == "base":
        title = N_("J = blockdiag(R, R) J_tool, R the tool's rotation: rows [v; ω] in the base axes")
    steps.append(
        ctx.step("J", words(title), "J" if frame == "base" else "J_{\\mathrm{tool}}", J, None, "result")
    )
    det = _det_step(ctx, robot, symbolic_params) if frame == "base" else None
    if det is not None:
        steps.append(det)
    if ctx.notes:
        last = steps[-1]
        steps[-1] = dataclasses.replace(last, notes=tuple(dict.fromkeys((*last.notes, *ctx.notes))))
    return tuple(steps)


def derivation_steps(
    robot: Robot,
    method: Method,
    frame: Literal["base", "tool"] = "base",
    symbolic_params: bool = False,
    timeout: float | None = DEFAULT_TIMEOUT,
    *,
    deadline: Deadline | None = None,
) -> tuple[Step, ...]:
    """The steps of one derivation of J (see the module docstring for the keys).

    Args:
        robot: Any robot: a DH table or a URDF chain (then the link and joint frames of the chain
            take the place of the DH frames).
        method: ``"whitney"``, ``"differentiation"``, ``"propagation"`` or ``"force"``.
        frame: Axes of J's rows, ``"base"`` or ``"tool"`` (``"detJ"`` only for the base frame:
            the determinant does not depend on the axes).
        symbolic_params: DH lengths and offsets as symbols (the course's letters where the robot
            file names them).
        timeout: Simplification budget [s] shared by all steps; past it the remaining steps
            stay exact and unsimplified (their notes say so). ``None``: no limit.
        deadline: A deadline shared with other work (a handout); replaces ``timeout`` and is not
            cached.

    Raises:
        SymbolicError: unknown method or frame, bad timeout, symbolic parameters without a DH table.
    """
    if method not in METHODS:
        raise SymbolicError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    frame = check_frame(frame)
    timeout = check_timeout(timeout)
    if not isinstance(robot, Robot):
        raise SymbolicError(f"expected a kinematics.Robot, got {type(robot).__name__}")
    if deadline is not None:
        return _build(robot, method, frame, bool(symbolic_params), deadline)
    return _cached(robot, method, frame, bool(symbolic_params), timeout)
