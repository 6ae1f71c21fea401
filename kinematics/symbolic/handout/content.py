"""A handout's content: the derivation of a robot's J as a teacher hands it out, as HTML (MathML) or LaTeX.

:func:`handout` returns the text of a document (no file is written): the robot and its DH
table, each link transform Aᵢ, the products ⁰Tᵢ, the steps of the chosen method(s)
(:func:`.steps.derivation_steps`), the assembled J, det J factored with its singular sets named,
and a worked numeric example at a named configuration (J, det J, and, when joint rates or a
tool velocity are given, v = J q̇ and q̇ = J⁻¹ v). This module is the content
(:func:`build_handout` → :class:`Handout`); the writers :mod:`.html` and :mod:`.tex` take it, and
escape every name from the robot file; :mod:`.document` picks the writer.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import sympy as sp

from ...analysis import task_rows
from ...conventions import ROW_TEXT
from ...errors import JacobianLabError
from ...model import Robot
from ...motion.closed_form import closed_form, closed_form_inverse_jacobian
from ...numeric import as_configuration, jacobian_dot, jacobian_dot_alone
from ...numeric import jacobian as numeric_jacobian
from ...steps import METHODS as STEP_METHODS
from ..core import DEFAULT_TIMEOUT, check_timeout
from ..model import build_model, check_frame
from ..steps import METHODS, derivation_steps, dh_rows
from ..steps.methods import rate_symbols, wrench_symbols
from ..steps.step import DHRow, Step
from ..trig import Deadline
from .words import ENGLISH, Words

__all__ = [
    "HANDOUT_FORMATS",
    "HANDOUT_METHODS",
    "HandoutError",
    "Handout",
    "Example",
    "build_handout",
    "INTRO",
    "TITLES",
    "ROW_NAMES",
    "angle_parts",
    "degrees_text",
]

HANDOUT_FORMATS = ("html", "tex")
HANDOUT_METHODS = (*METHODS, "all")

ROW_NAMES = ROW_TEXT

INTRO = {k: STEP_METHODS[k].intro for k in METHODS}
"""The paragraph that opens each method's section (from :data:`kinematics.steps.METHODS`)."""
TITLES = {k: STEP_METHODS[k].title for k in METHODS}
"""Each method's heading (from :data:`kinematics.steps.METHODS`)."""


class HandoutError(JacobianLabError):
    """A handout request is invalid (unknown format, method or configuration, wrong rates)."""


@dataclass
class Example:
    """The worked numeric example.

    Attributes:
        name, description: Of the named configuration ("" when none).
        q: The configuration (n,) [rad | m].
        rows: The task rows of J used (0–2: v, 3–5: ω).
        J: J(q) of the task rows (rows × n).
        det: det of J (square) or √det(J Jᵀ) (manipulability) at q.
        square: Whether the task rows make J square.
        rates: The given joint rates q̇ (n,) [rad/s | m/s], or None.
        velocity: J q̇ (task rows), or None.
        twist: The given task velocity (task rows), or None.
        inverse: J⁻¹ when square and regular, else None.
        closed_form: J⁻¹ = ∂g/∂x from the closed-form inverse kinematics q = g(x) (course 002's third
            way) when the robot has one (:mod:`kinematics.motion.closed_form`), the frame is the base and
            it exists here, else None.
        solved: J⁻¹ · twist, or None.
        jdot_qd: J̇ q̇ (task rows) [m/s², rad/s²] for the given rates in base axes, the tool's acceleration
            ẍ = J q̈ + J̇ q̇ at q̈ = 0, or None.
        jdot_alone_qd: Σᵢ J̇ᵢ q̇ᵢ with course 000's per-joint J̇ᵢ (task rows), or None.
    """

    name: str
    description: str
    q: np.ndarray
    rows: tuple[int, ...]
    J: np.ndarray
    det: float
    square: bool
    rates: np.ndarray | None = None
    velocity: np.ndarray | None = None
    twist: np.ndarray | None = None
    inverse: np.ndarray | None = None
    closed_form: np.ndarray | None = None
    solved: np.ndarray | None = None
    jdot_qd: np.ndarray | None = None
    jdot_alone_qd: np.ndarray | None = None


@dataclass
class Handout:
    """Everything a handout shows, before it is written out (by :mod:`.html` or :mod:`.tex`)."""

    robot: Robot
    frame: str
    methods: tuple[str, ...]
    symbolic_params: bool
    table: tuple[DHRow, ...]
    transforms: list[Step]
    method_steps: dict[str, list[Step]]
    result: list[Step]
    example: Example
    names: dict[sp.Symbol, str] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    same_J: bool = True
    words: Words = ENGLISH


def _example(robot: Robot, frame: str, configuration: str | None, rates: object, twist: object) -> Example:
    if configuration is None:
        named = next((c for c in robot.configurations if c.name == "home"), None)
        q = np.asarray(robot.home, dtype=float)
    else:
        named = next((c for c in robot.configurations if c.name == configuration), None)
        if named is None:
            available = ", ".join(c.name for c in robot.configurations) or "none"
            raise HandoutError(f"robot has no configuration {configuration!r}; available: {available}")
        q = np.asarray(named.q, dtype=float)
    rows = tuple(task_rows(robot))
    J = numeric_jacobian(robot, q, check_frame(frame))[list(rows)]
    square = J.shape[0] == J.shape[1]
    det = float(np.linalg.det(J)) if square else float(np.sqrt(max(np.linalg.det(J @ J.T), 0.0)))
    ex = Example(named.name if named else "", named.description if named else "", q, rows, J, det, square)
    if rates is not None:
        qd = as_configuration(robot, rates, "rates")
        if qd.ndim != 1:
            raise HandoutError(f"rates: one value per joint expected, got shape {qd.shape}")
        ex.rates, ex.velocity = qd, J @ qd
        if frame == "base":
            ex.jdot_qd = (jacobian_dot(robot, q, qd) @ qd)[list(rows)]
            ex.jdot_alone_qd = (jacobian_dot_alone(robot, q, qd) @ qd)[list(rows)]
    if square and abs(det) > 1e-9 * max(1.0, float(np.abs(J).max()) ** J.shape[0]):
        ex.inverse = np.linalg.inv(J)
    if frame == "base" and closed_form(robot) is not None:
        ex.closed_form = closed_form_inverse_jacobian(robot, q)
    if twist is not None:
        t = np.asarray(twist, dtype=float).reshape(-1)
        if t.shape != (6,) or not np.isfinite(t).all():
            raise HandoutError(f"twist: 6 finite numbers [v; ω] expected, got shape {t.shape}")
        ex.twist = t[list(rows)]
        if ex.inverse is not None:
            ex.solved = ex.inverse @ ex.twist
    return ex


def build_handout(
    robot: Robot,
    method: str = "all",
    *,
    frame: str = "base",
    symbolic_params: bool = False,
    configuration: str | None = None,
    rates: Sequence[float] | None = None,
    twist: Sequence[float] | None = None,
    timeout: float | None = DEFAULT_TIMEOUT,
    progress: Callable[[str], None] | None = None,
    words: Words = ENGLISH,
) -> Handout:
    """The content of a handout (see :func:`handout` for the arguments)."""
    if method not in HANDOUT_METHODS:
        raise HandoutError(f"method must be one of {', '.join(HANDOUT_METHODS)}, got {method!r}")
    if not isinstance(robot, Robot):
        raise HandoutError(f"expected a kinematics.Robot, got {type(robot).__name__}")
    frame = check_frame(frame)
    deadline = Deadline(check_timeout(timeout))
    example = _example(robot, frame, configuration, rates, twist)
    methods = METHODS if method == "all" else (method,)
    model = build_model(robot, symbolic_params)
    per: dict[str, tuple[Step, ...]] = {}
    for m in methods:
        if progress is not None:
            progress(f"{m}: deriving the steps")
        per[m] = derivation_steps(robot, m, frame, symbolic_params, deadline=deadline)
    first = per[methods[0]]
    transforms = [s for s in first if s.section == "transforms"]
    result = [s for s in first if s.section == "result" and s.key in ("J", "detJ")]
    method_steps = {
        m: [s for s in steps if s.section not in ("transforms",) and s.key not in ("J", "detJ")]
        for m, steps in per.items()
    }
    _, rate_names = rate_symbols(model)
    _, wrench_names = wrench_symbols()
    notes = [model.snap_note] if model.snaps else []
    for steps in per.values():
        for s in steps:
            notes += list(s.notes)
    same = _agree([steps for steps in per.values()], robot)
    return Handout(
        robot,
        frame,
        methods,
        symbolic_params,
        dh_rows(robot, symbolic_params),
        transforms,
        method_steps,
        result,
        example,
        {**rate_names, **wrench_names},
        list(dict.fromkeys(n for n in notes if n)),
        same,
        words,
    )


def _agree(all_steps: list[tuple[Step, ...]], robot: Robot) -> bool:
    """Whether every method's J is the same at a few random configurations."""
    rng = np.random.default_rng(0)
    Js = [next(s for s in steps if s.key == "J") for steps in all_steps]
    for _ in range(3):
        q = rng.uniform(-np.pi, np.pi, robot.dof)
        ref = Js[0].numeric(q)
        if not all(np.allclose(J.numeric(q), ref, atol=1e-9) for J in Js[1:]):
            return False
    return True


def angle_parts(e: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """(the part with symbols, the constant part) of an angle."""
    e = sp.expand(e)
    const = sp.Add(*[t for t in sp.Add.make_args(e) if not t.free_symbols])
    return e - const, const


def degrees_text(c: sp.Expr) -> str:
    """A constant angle [rad] in degrees: "90", "-15", "57.3"."""
    deg = sp.nsimplify(c * 180 / sp.pi) if c.is_number else c
    if deg.is_Integer:
        return str(int(deg))
    return f"{float(deg):.4g}"
