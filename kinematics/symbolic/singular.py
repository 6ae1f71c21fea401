"""det J factored, and the singular sets it implies.

:func:`determinant` takes the task rows of J (:func:`det_rows`): when they
form a square matrix it factors det J; for a redundant arm it gives
det(J Jᵀ) as the sum of the squared maximal minors (Cauchy–Binet), each
factored, and the factors common to all minors. It works in the frame and
reference point where J is shortest (:func:`.det.shortest_rows`), with the DH
parameters as symbols (so a₂ = d₄ on a Puma cannot merge terms), and
substitutes their values afterwards unless ``symbolic_params``.

Every factor that depends on q is a singular set (a :class:`SingularSet`),
solved for its joint when it involves only one (sin q₅ = 0 → q₅ ∈ {0, π}),
and named wrist, elbow or shoulder from the joints it involves.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import sympy as sp

from ..analysis import PART_ROWS, task_rows
from ..model import Robot
from . import cache
from .classify import kind, kind_context, solve_single
from .core import DEFAULT_TIMEOUT
from .derivations import jacobian_whitney
from .det import MAX_FACTOR_TERMS, Factored, TrigPolynomials, shortest_rows
from .model import SymbolicError, build_model
from .trig import Deadline, Progress, collapse, is_zero, nest

__all__ = ["SingularSet", "Determinant", "determinant", "singular_sets", "det_rows", "MAX_DET_TERMS"]

MAX_DET_TERMS = 160
"""A J with more terms than this (in its shortest form) gets no symbolic determinant: expanding
it can take hours. The library's robots have at most 60; a 6R arm with arbitrary twists and
offsets, 300 or more."""


@cache.register_dataclass
@dataclass(frozen=True)
class SingularSet:
    """Configurations where one factor of the determinant vanishes.

    Attributes:
        factor: The factor (simplified); the set is ``factor = 0``.
        joints: The joint symbols it involves.
        kind: ``"wrist"``, ``"elbow"``, ``"shoulder"`` or ``""``.
        solutions: For a single joint: its values in (−π, π] (revolute) or the reals (prismatic)
            where the factor vanishes; ``None`` if not solved.
    """

    factor: sp.Expr
    joints: tuple[sp.Symbol, ...]
    kind: str
    solutions: tuple[sp.Expr, ...] | None

    @property
    def equation(self) -> sp.Eq:
        """``factor = 0`` as a SymPy equation."""
        return sp.Eq(self.factor, 0)


@dataclass(frozen=True, eq=False)
class Determinant:
    """det J (square task rows) or det(J Jᵀ) / det(Jᵀ J), factored.

    Attributes:
        robot: Robot name.
        rows: Rows of J used (0–2: v, 3–5: ω).
        gram: False for det J; True for det(J Jᵀ) (wide) or det(Jᵀ J) (tall), the sum of
            the squared maximal minors.
        factored: (constant, ((factor, multiplicity), …)) of det J, or of the factor common to all
            minors when ``gram``; ``None`` when not computed (see ``notes``).
        minors: When ``gram``: each maximal minor, factored.
        singular_sets: One per factor of ``factored``.
        q, display, joint_kinds, params: Symbols and names, for printing.
        notes: Human-readable notes.
    """

    robot: str
    rows: tuple[int, ...]
    gram: bool
    factored: Factored | None
    minors: tuple[Factored | None, ...]
    singular_sets: tuple[SingularSet, ...]
    q: tuple[sp.Symbol, ...]
    display: dict[sp.Symbol, str]
    joint_kinds: tuple[str, ...]
    params: dict[sp.Symbol, float]
    notes: tuple[str, ...] = ()

    @staticmethod
    def product(f: Factored) -> sp.Expr:
        """The factored form as one unevaluated product (keeps the factors visible)."""
        const, facs = f
        parts = [] if const == 1 else list(sp.Mul.make_args(const))
        parts += [b if m == 1 else sp.Pow(b, m, evaluate=False) for b, m in facs]
        return sp.Mul(*parts, evaluate=False) if len(parts) > 1 else (parts[0] if parts else sp.Integer(1))

    @property
    def expr(self) -> sp.Expr | None:
        """det J as a product, or det(J Jᵀ) as a sum of squared products; None if not computed."""
        if not self.gram:
            return None if self.factored is None else self.product(self.factored)
        minors = [m for m in self.minors if m is not None]
        if len(minors) < len(self.minors) or not minors:
            return None
        return sp.Add(
            *[sp.Pow(self.product(m), 2, evaluate=False) for m in minors if m[0] != 0], evaluate=False
        )

    @property
    def identically_zero(self) -> bool:
        """True if the selected rows never have full rank."""
        if self.gram:
            return bool(self.minors) and all(m is not None and m[0] == 0 for m in self.minors)
        return self.factored is not None and self.factored[0] == 0


def _parse_rows(rows: object) -> tuple[int, ...]:
    if isinstance(rows, str):
        if rows not in PART_ROWS:
            raise SymbolicError(f"rows must be one of {', '.join(PART_ROWS)} or row indices, got {rows!r}")
        return PART_ROWS[rows]
    try:
        out = tuple(sorted(int(r) for r in rows))  # type: ignore[attr-defined]
    except (TypeError, ValueError):
        raise SymbolicError(
            f"rows must be a part name or a sequence of row indices 0-5, got {rows!r}"
        ) from None
    if not out or len(set(out)) != len(out) or not all(0 <= r <= 5 for r in out):
        raise SymbolicError(f"rows must be distinct indices between 0 and 5, got {rows!r}")
    return out


def det_rows(robot: Robot, deadline: Deadline | None = None) -> tuple[int, ...]:
    """The rows whose determinant describes the robot's singularities.

    The task rows (:func:`kinematics.task_rows`) when they are square; else the
    rows of J that are not identically zero when there are exactly n of them
    (SCARA: vx, vy, vz, ωz); else for a planar arm with fewer than 3 joints its
    position rows (2R: vx, vy, as the course writes det J = a₁a₂s₂); else the
    task rows (det(J Jᵀ) or det(JᵀJ)). At the ``deadline``, the task rows.
    """
    rows, n = task_rows(robot), robot.dof
    if len(rows) == n or (deadline is not None and deadline.expired()):
        return rows
    J = jacobian_whitney(robot, deadline=deadline)
    if deadline is not None and deadline.expired():
        return rows
    q = build_model(robot).q
    nonzero = tuple(i for i in range(6) if not all(is_zero(e, q) for e in J[i, :]))
    if len(nonzero) == n:
        return nonzero
    if robot.planar and len(rows) > n:
        return PART_ROWS["planar"][:n]
    return rows


def _tidy(f: Factored, values: dict[sp.Symbol, float], q: tuple[sp.Symbol, ...]) -> Factored:
    """Substitute parameter values, merge equal factors, simplify each factor for display."""
    const, facs = f
    const = const.xreplace(values)
    found: dict[sp.Expr, int] = {}
    for b, m in facs:
        b = sp.expand(b.xreplace(values))
        if not b.free_symbols & set(q):
            const *= b**m
            continue
        if b.could_extract_minus_sign():
            b, const = -b, const * (-1) ** m
        found[b] = found.get(b, 0) + m
    return sp.factor(const), tuple((nest(collapse(b, q), q), m) for b, m in found.items())


def _compute(
    robot: Robot, rows: tuple[int, ...], symbolic_params: bool, deadline: Deadline, progress: Progress | None
) -> tuple[bool, Factored | None, tuple[Factored | None, ...], list[str]]:
    try:
        model = build_model(robot, True)  # factor with the DH parameters as symbols
    except SymbolicError:
        model = build_model(robot, False)
    values = {} if symbolic_params else model.exact_values()
    if progress:
        progress(f"det: expressing rows {rows} of J where they are shortest")
    gram = len(rows) != robot.dof
    if deadline.expired():
        return gram, None, (), ["determinant skipped: time limit reached before it started"]
    M = shortest_rows(model, rows, deadline)
    size = sum(len(sp.Add.make_args(e)) for e in M)
    if size > MAX_DET_TERMS or deadline.expired():
        why = "time limit reached" if size <= MAX_DET_TERMS else f"J has {size} terms in its shortest form"
        return gram, None, (), [f"determinant not computed: {why} (library robots have at most 60)"]
    P = TrigPolynomials(model.q)
    Mp = M.applyfunc(P.poly)
    if not gram:
        if progress:
            progress("det: determinant and factors")
        det = P.det(Mp)
        if deadline.expired():
            return False, None, (), ["determinant not computed: time limit reached while expanding it"]
        notes = [] if len(sp.Add.make_args(det)) <= MAX_FACTOR_TERMS else ["det J too large to factor"]
        return False, _tidy(P.factor(det), values, model.q), (), notes
    if progress:
        progress(f"det: {sp.binomial(max(M.shape), min(M.shape))} maximal minors (Cauchy-Binet)")
    minors = P.minors(Mp, deadline)
    if minors is None:
        return True, None, (), [f"time limit of {deadline.seconds:g} s reached while computing the minors"]
    g = P.common_factor([d for _, d in minors], deadline)
    if g == 0:
        return True, (sp.Integer(0), ()), tuple((sp.Integer(0), ()) for _ in minors), []
    common = P.factor(g)
    if deadline.expired():
        return True, None, (), [f"time limit of {deadline.seconds:g} s reached while factoring the minors"]
    shown: list[Factored] = []  # each minor as (common factors) × (its own cofactor, not factored further)
    for _, d in minors:
        if d == 0:
            shown.append((sp.Integer(0), ()))
            continue
        rest = P.trig(d if g == 1 else sp.quo(d, g))
        shown.append(_tidy((common[0], (*common[1], (rest, 1))), values, model.q))
    return True, _tidy(common, values, model.q), tuple(shown), []


def determinant(
    robot: Robot,
    rows: object = None,
    *,
    symbolic_params: bool = False,
    timeout: float | None = DEFAULT_TIMEOUT,
    use_cache: bool = True,
    progress: Progress | None = None,
    deadline: Deadline | None = None,
) -> Determinant:
    """Factored det J of the task rows (or det(J Jᵀ) for a redundant arm) and its singular sets.

    Args:
        robot: The robot.
        rows: Rows of J: a part name (``"full"``, ``"linear"``, ``"angular"``, ``"planar"``),
            row indices, or ``None`` for :func:`det_rows`.
        symbolic_params: Keep the DH parameters as symbols in the result.
        timeout: Time budget [s]; past it the result says what was not computed.
        use_cache: Read and write the on-disk cache.
        progress: Called with short progress messages.
        deadline: A deadline shared with other steps (an export); replaces ``timeout``.

    Example:
        >>> from kinematics import Robot
        >>> row = dict(joint="revolute", a=1.0, alpha=0.0, d=0.0, theta=0.0)
        >>> planar2 = Robot.from_dh([row, row], planar=True)
        >>> d = determinant(planar2, symbolic_params=True, use_cache=False)
        >>> d.expr, [s.solutions for s in d.singular_sets]
        (a1*a2*sin(q2), [(0, pi)])
    """
    deadline = deadline if deadline is not None else Deadline(timeout)
    rows = det_rows(robot, deadline) if rows is None else _parse_rows(rows)
    display_model = build_model(robot, symbolic_params)
    key = f"det|{display_model.cache_key()}|{rows}"
    hit = cache.load(key) if use_cache else None
    if isinstance(hit, dict):
        return Determinant(**{**hit, "robot": robot.name})
    gram, factored, minors, notes = _compute(robot, rows, symbolic_params, deadline, progress)
    sets = []
    if factored is not None and factored[0] != 0:
        ctx = kind_context(robot, rows)
        for b, _ in factored[1]:
            joints = tuple(s for s in display_model.q if b.has(s))
            idx = {display_model.q.index(s) for s in joints}
            sol = None
            if len(joints) == 1 and not deadline.expired():
                sol = solve_single(b, joints[0], robot.joint_types[idx.pop()] == "revolute")
            sets.append(
                SingularSet(b, joints, kind({display_model.q.index(s) for s in joints}, robot, ctx), sol)
            )
    result = Determinant(
        robot.name,
        rows,
        gram,
        factored,
        minors,
        tuple(sets),
        display_model.q,
        dict(display_model.display),
        robot.joint_types,
        dict(display_model.params),
        tuple(notes),
    )
    if result.identically_zero:
        notes.append("identically zero: these rows of J never have full rank; choose other rows")
        result = dataclasses.replace(result, notes=tuple(notes))
    if use_cache and not deadline.expired():
        cache.store(key, {f.name: getattr(result, f.name) for f in dataclasses.fields(result)})
    return result


def singular_sets(robot: Robot, rows: object = None, **kwargs: object) -> tuple[SingularSet, ...]:
    """The singular sets of ``robot`` (see :func:`determinant`; same arguments)."""
    return determinant(robot, rows, **kwargs).singular_sets  # type: ignore[arg-type]
