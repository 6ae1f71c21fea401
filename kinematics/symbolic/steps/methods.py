"""The method-specific steps of :func:`.steps.derivation_steps`: Whitney, differentiation,
velocity propagation and force propagation.

Each builder takes a :class:`Context` and returns its steps, the J they assemble (from the
steps' own simplified values) and the axes that J is in.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import sympy as sp

from ...text import N_, words
from ..chain import Frames
from ..derivations import carry_inward, carry_outward, chain_elements
from ..model import SymbolicModel
from ..simplify import simplify_matrix
from ..trig import AngleShift, Deadline
from .step import Step

__all__ = ["Context", "METHOD_STEPS", "rotate_rows", "rate_symbols", "wrench_symbols"]

_SUB = str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉")


def _s(i: int) -> str:
    return str(i).translate(_SUB)


def rotate_rows(J: sp.Matrix, R: sp.Matrix) -> sp.Matrix:
    """blockdiag(R, R) · J (J with rows [v; ω])."""
    return sp.Matrix.vstack(R * J[:3, :], R * J[3:, :])


def rate_symbols(model: SymbolicModel) -> tuple[tuple[sp.Symbol, ...], dict[sp.Symbol, str]]:
    """The joint-rate symbols q̇₁ … q̇ₙ and their LaTeX names (θ̇ᵢ or ḋᵢ)."""
    qd = tuple(sp.Symbol(f"qd_{i + 1}", real=True) for i in range(model.dof))
    names: dict[sp.Symbol, str] = {}
    for i, (s, kind) in enumerate(zip(qd, model.robot.joint_types, strict=True)):
        names[s] = f"\\dot{{\\theta}}_{{{i + 1}}}" if kind == "revolute" else f"\\dot{{d}}_{{{i + 1}}}"
    return qd, names


def wrench_symbols() -> tuple[tuple[sp.Symbol, ...], dict[sp.Symbol, str]]:
    """The tool wrench [f; n] symbols and their LaTeX names."""
    w = tuple(sp.Symbol(f"{a}_{b}", real=True) for a in "fn" for b in "xyz")
    return w, {s: f"{str(s)[0]}_{{{str(s)[2]}}}" for s in w}


@dataclass
class Context:
    """What every builder needs: the model, its frames (base axes), the deadline and the frame of J."""

    model: SymbolicModel
    F: Frames
    deadline: Deadline
    frame: str
    notes: list[str] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.shift = AngleShift(self.model.q, self.model.angle_offsets())
        self.values = self.model.numeric_values()

    def step(
        self,
        key: str,
        title: str,
        lhs: str,
        expr: sp.Matrix,
        joint: int | None,
        section: str = "transforms",
        *,
        inputs: tuple[sp.Symbol, ...] = (),
        names: dict[sp.Symbol, str] | None = None,
    ) -> Step:
        """A :class:`Step` with ``expr`` simplified within the deadline."""
        S = simplify_matrix(
            sp.Matrix(expr), self.model.q, self.deadline, None, key, self.shift, values=self.values
        )
        if S.pending:
            self.notes.append(
                "time limit reached: some steps are shown unsimplified (exact, but long); raise the timeout"
            )
        return Step(
            key, title, lhs, S.matrix, joint, self.model, section, inputs, names or {}, tuple(S.notes)
        )


def _labels(model: SymbolicModel) -> list[int]:
    """The frame index of each joint's axis in the convention: i−1 (standard DH, URDF) or i (modified)."""
    shift = 1 if model.dh and model.robot.convention == "modified" else 0
    return [k + shift for k in range(len(model.kinds))]


def _axes_of(model: SymbolicModel, j: int) -> list[int]:
    return [k for k, a in enumerate(model.axis_joint) if a == j]


def whitney(ctx: Context) -> tuple[list[Step], sp.Matrix, str]:
    """zᵢ₋₁, pᵢ₋₁, pₙ − pᵢ₋₁ and column i = [zᵢ₋₁ × (pₙ − pᵢ₋₁); zᵢ₋₁] (revolute) or [zᵢ₋₁; 0]."""
    m, F = ctx.model, ctx.F
    p_n = F.tool[:3, 3]
    out: list[Step] = []
    cols = []
    lab = _labels(m)
    for j, qj in enumerate(m.q):
        col = sp.zeros(6, 1)
        formula = ""
        for k in _axes_of(m, j):
            i, W = lab[k], F.joint[k]
            zs = ctx.step(
                f"whitney.z{k}",
                words(N_("{z}: the axis of joint {joint}, in the base axes"), z=f"z{_s(i)}", joint=k + 1),
                f"z_{{{i}}}",
                W[:3, 2],
                j,
                "whitney",
            )
            out.append(zs)
            z = zs.expr
            rate = sp.diff(m.axis_value[k], qj)
            if m.kinds[k] == "revolute":
                p = ctx.step(
                    f"whitney.p{k}",
                    words(
                        N_("{p}: a point of joint {joint}'s axis (its frame's origin)"),
                        p=f"p{_s(i)}",
                        joint=k + 1,
                    ),
                    f"p_{{{i}}}",
                    W[:3, 3],
                    j,
                    "whitney",
                )
                r = ctx.step(
                    f"whitney.r{k}",
                    words(
                        N_("{r}: from joint {joint}'s axis to the tool origin"),
                        r=f"pₙ − p{_s(i)}",
                        joint=k + 1,
                    ),
                    f"p_{{n}} - p_{{{i}}}",
                    p_n - W[:3, 3],
                    j,
                    "whitney",
                )
                out += [p, r]
                col += rate * sp.Matrix.vstack(z.cross(r.expr), z)
                formula = words(
                    N_("Column {j} = {formula}"), j=j + 1, formula=f"z{_s(i)} × (pₙ − p{_s(i)}), z{_s(i)}"
                )
            else:
                col += rate * sp.Matrix.vstack(z, sp.zeros(3, 1))
                formula = words(
                    N_("Column {j} = {z}, 0 (prismatic: the tool slides along the axis, no rotation)"),
                    j=j + 1,
                    z=f"z{_s(i)}",
                )
        step = ctx.step(f"whitney.col{j + 1}", formula, f"J_{{{j + 1}}}", col, j, "whitney")
        out.append(step)
        cols.append(step.expr)
    return out, sp.Matrix.hstack(*cols), "base"


def differentiation(ctx: Context) -> tuple[list[Step], sp.Matrix, str]:
    """∂p/∂qᵢ (the v part) and (∂R/∂qᵢ) Rᵀ = [ω]× (the ω part) of each column."""
    m, T = ctx.model, ctx.F.tool
    p, R = T[:3, 3], T[:3, :3]
    out: list[Step] = []
    cols = []
    for j, qj in enumerate(m.q):
        name = m.display[qj]
        dp = ctx.step(
            f"diff.dp{j + 1}",
            words(N_("{dp}: the v part of column {j}"), dp=f"∂p/∂q{_s(j + 1)}", j=j + 1),
            f"\\frac{{\\partial p}}{{\\partial {name}}}",
            p.diff(qj),
            j,
            "differentiation",
        )
        S = ctx.step(
            f"diff.S{j + 1}",
            words(
                N_("{S} = [ω]×: a skew matrix; the ω part of column {j} is (S₃₂, S₁₃, S₂₁)"),
                S=f"(∂R/∂q{_s(j + 1)}) Rᵀ",
                j=j + 1,
            ),
            f"\\frac{{\\partial R}}{{\\partial {name}}} R^{{T}}",
            R.diff(qj) * R.T,
            j,
            "differentiation",
        )
        s = S.expr
        col = ctx.step(
            f"diff.col{j + 1}",
            words(N_("Column {j} = {dp}, (S₃₂, S₁₃, S₂₁)"), j=j + 1, dp=f"∂p/∂q{_s(j + 1)}"),
            f"J_{{{j + 1}}}",
            sp.Matrix([*dp.expr, s[2, 1], s[0, 2], s[1, 0]]),
            j,
            "differentiation",
        )
        out += [dp, S, col]
        cols.append(col.expr)
    return out, sp.Matrix.hstack(*cols), "base"


def propagation(ctx: Context) -> tuple[list[Step], sp.Matrix, str]:
    """Craig's outward iteration: ω and the origin velocity of each link, in the link's own axes."""
    m = ctx.model
    qd, names = rate_symbols(m)
    rate = lambda value: sum(sp.diff(value, qj) * d for qj, d in zip(m.q, qd, strict=True))  # noqa: E731
    w, v = sp.zeros(3, 1), sp.zeros(3, 1)
    out: list[Step] = []

    def mk(key: str, title: str, lhs: str, e: sp.Matrix, j: int | None) -> Step:
        return ctx.step(key, title, lhs, e, j, "propagation", inputs=qd, names=names)

    chain = chain_elements(m)
    for idx, (kind, X, k) in enumerate(chain):
        w, v = carry_outward(kind, X, w, v, rate)
        last_of_link = 0 <= k < len(m.kinds) and idx + 1 < len(chain) and chain[idx + 1][2] != k
        if last_of_link:
            j, i = m.axis_joint[k], k + 1
            ws = mk(
                f"prop.w{i}",
                words(
                    N_(
                        "ω of link {i} in its own axes: link {before}'s ω carried into frame {i}, plus "
                        "{rate} about joint {i}'s axis"
                    )
                    if m.kinds[k] == "revolute"
                    else N_("ω of link {i} in its own axes: link {before}'s ω carried into frame {i}"),
                    i=i,
                    before=i - 1,
                    rate=f"θ̇{_s(j + 1)}",
                ),
                f"{{}}^{{{i}}}\\omega_{{{i}}}",
                w,
                j,
            )
            vs = mk(
                f"prop.v{i}",
                words(
                    N_(
                        "Velocity of link {i}'s origin in its own axes: link {before}'s origin velocity plus "
                        "ω × (the offset between the origins) plus ḋ along the axis"
                    )
                    if m.kinds[k] == "prismatic"
                    else N_(
                        "Velocity of link {i}'s origin in its own axes: link {before}'s origin velocity plus "
                        "ω × (the offset between the origins)"
                    ),
                    i=i,
                    before=i - 1,
                ),
                f"{{}}^{{{i}}}v_{{{i}}}",
                v,
                j,
            )
            out += [ws, vs]
            w, v = ws.expr, vs.expr
    if m.tool != sp.eye(4):
        ws = mk(
            "prop.wtool",
            words(N_("ω of the tool in the tool axes")),
            "{}^{\\mathrm{tool}}\\omega_{\\mathrm{tool}}",
            w,
            None,
        )
        vs = mk(
            "prop.vtool",
            words(N_("Velocity of the tool origin in the tool axes: v + ω × (the tool offset)")),
            "{}^{\\mathrm{tool}}v_{\\mathrm{tool}}",
            v,
            None,
        )
        out += [ws, vs]
        w, v = ws.expr, vs.expr
    if ctx.frame == "base":
        R = ctx.F.tool[:3, :3]
        end = "\\mathrm{tool}" if m.tool != sp.eye(4) else "n"
        ws = mk(
            "prop.w_base",
            words(N_("ω of the tool rotated to the base axes: ⁰R_tool ω")),
            f"{{}}^{{0}}\\omega_{{{end}}}",
            R * w,
            None,
        )
        vs = mk(
            "prop.v_base",
            words(N_("Velocity of the tool origin rotated to the base axes: ⁰R_tool v")),
            f"{{}}^{{0}}v_{{{end}}}",
            R * v,
            None,
        )
        out += [ws, vs]
        w, v = ws.expr, vs.expr
    return out, sp.Matrix.vstack(v, w).jacobian(qd), ctx.frame


def force(ctx: Context) -> tuple[list[Step], sp.Matrix, str]:
    """Craig's inward iteration of a tool wrench [f; n] (tool axes) to the torques τ = J_toolᵀ [f; n]."""
    m = ctx.model
    W, names = wrench_symbols()
    f, n = sp.Matrix(W[:3]), sp.Matrix(W[3:])  # the wrench at the tool origin, in the tool axes

    def mk(key: str, title: str, lhs: str, e: sp.Matrix, j: int | None) -> Step:
        return ctx.step(key, title, lhs, e, j, "force", inputs=W, names=names)

    out: list[Step] = []
    tau: dict[int, sp.Expr] = {}
    taus: dict[int, Step] = {}
    for kind, X, k in reversed(chain_elements(m)):
        if kind != "fixed":
            j, i = m.axis_joint[k], k + 1
            fs = mk(
                f"force.f{i}",
                words(
                    N_(
                        "Force on link {i} at joint {i}, in the axes of joint {i}'s frame (z along its "
                        "axis): link {next}'s force carried inward"
                    ),
                    i=i,
                    next=i + 1,
                ),
                f"f_{{{i}}}",
                f,
                j,
            )
            ns = mk(
                f"force.n{i}",
                words(
                    N_(
                        "Moment on link {i} about joint {i}'s frame origin: link {next}'s moment carried "
                        "inward plus p × f"
                    ),
                    i=i,
                    next=i + 1,
                ),
                f"n_{{{i}}}",
                n,
                j,
            )
            out += [fs, ns]
            f, n = fs.expr, ns.expr
            torque = (n if kind == "revolute" else f)[2]
            tau[j] = tau.get(j, sp.Integer(0)) + sp.diff(X, m.q[j]) * torque
            if k == min(_axes_of(m, j)):
                what = (
                    N_("{tau} = n · z: the moment about the axis")
                    if kind == "revolute"
                    else N_("{tau} = f · z: the force along the axis")
                )
                taus[j] = mk(
                    f"force.tau{j + 1}",
                    words(what, tau=f"τ{_s(j + 1)}"),
                    f"\\tau_{{{j + 1}}}",
                    sp.Matrix([[tau[j]]]),
                    j,
                )
                out.append(taus[j])
        f, n = carry_inward(kind, X, f, n)
    JT = sp.Matrix([taus[j].expr[0, 0] for j in range(m.dof)]).jacobian(sp.Matrix(W))
    title = words(N_("Jᵀ in the tool axes: the coefficients of the tool wrench in τ (τ = Jᵀ [f; n])"))
    jt = ctx.step("force.JT", title, "J_{\\mathrm{tool}}^{T}", JT, None, "force")
    out.append(jt)
    return out, jt.expr.T, "tool"


METHOD_STEPS: dict[str, Callable[[Context], tuple[list[Step], sp.Matrix, str]]] = {  # keys: kinematics.steps
    "whitney": whitney,
    "differentiation": differentiation,
    "propagation": propagation,
    "force": force,
}
