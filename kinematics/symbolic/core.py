"""The symbolic forward kinematics and Jacobian, simplified and cached: what the exports show.

:func:`derive` computes J with Whitney's columns (the fastest of the
derivations in :mod:`.derivations`), simplifies every entry the way a person
would (:mod:`.trig`) within a time limit, and caches the result on disk keyed
by the robot's fingerprint and the options, so a second request is instant.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass
from typing import Any

import sympy as sp

from ..model import Robot
from . import cache
from .chain import frames, frames_within
from .derivations import jacobian_whitney
from .model import SymbolicError, build_model, check_frame
from .simplify import simplify_matrix
from .snap import Snap, snap_summary
from .trig import AngleShift, Deadline, Progress

__all__ = ["Derivation", "derive", "fk", "jacobian", "joint_symbols", "DEFAULT_TIMEOUT", "check_timeout"]

DEFAULT_TIMEOUT = 60.0
"""Default time budget [s] for simplification; past it, entries stay unsimplified (with a note)."""


@dataclass(frozen=True, eq=False)
class Derivation:
    """A simplified symbolic Jacobian and forward kinematics, with what is needed to print them.

    Attributes:
        robot: Robot name.
        frame: ``"base"`` or ``"tool"``: the axes of J's rows.
        q: Joint symbols ``q1 … qn``.
        joint_kinds: ``"revolute"`` or ``"prismatic"`` per joint.
        T: ``T_base_tool`` (4×4), simplified.
        J: Geometric Jacobian (6×n), rows [v; ω], simplified.
        params: Symbolic parameters → values [m] / [rad] (empty without ``symbolic_params``).
        display: LaTeX display names of the symbols (θᵢ / dᵢ for joints).
        notes: Human-readable notes: values snapped to exact ones (first, if any), entries left
            unsimplified at the time limit or shown expanded, negligible terms dropped.
        complete: True if every entry was simplified (none left as derived at the time limit).
        seconds: Time the derivation took when it was computed [s].
        timeout: Time budget of the request it was computed for [s] (``None``: unlimited).
        from_cache: True if this result was read from the cache.
        snaps: The robot's rounded values replaced by exact ones (see :mod:`.snap`).
        pending: ("J" or "T", i, j) of the entries left unsimplified (resumed by a later call
            with a larger timeout).
    """

    robot: str
    frame: str
    q: tuple[sp.Symbol, ...]
    joint_kinds: tuple[str, ...]
    T: sp.Matrix
    J: sp.Matrix
    params: dict[sp.Symbol, float]
    display: dict[sp.Symbol, str]
    notes: tuple[str, ...]
    complete: bool
    seconds: float
    timeout: float | None
    from_cache: bool = False
    snaps: tuple[Snap, ...] = ()
    pending: tuple[tuple[str, int, int], ...] = ()

    @property
    def snap_note(self) -> str:
        """Which values were snapped and the largest change ("" if none)."""
        return snap_summary(self.snaps)

    @property
    def largest_snap(self) -> float:
        """Largest angle change made by snapping [rad] (0 if none)."""
        return max((s.change for s in self.snaps if s.unit == "rad"), default=0.0)


def check_timeout(timeout: object) -> float | None:
    """``timeout`` as a float [s] or None; raises :class:`SymbolicError` unless positive or None."""
    if timeout is None:
        return None
    if isinstance(timeout, bool) or not isinstance(timeout, (int, float)) or not timeout > 0:
        raise SymbolicError(f"timeout must be a positive number of seconds or None, got {timeout!r}")
    return float(timeout)


def derive(
    robot: Robot,
    frame: str = "base",
    *,
    symbolic_params: bool = False,
    timeout: float | None = DEFAULT_TIMEOUT,
    use_cache: bool = True,
    progress: Progress | None = None,
    deadline: Deadline | None = None,
    exact: bool = False,
) -> Derivation:
    """Derive, simplify and cache J(q) and T_base_tool(q) of ``robot``.

    Args:
        robot: The robot.
        frame: ``"base"`` or ``"tool"``.
        symbolic_params: Keep DH lengths and offsets as symbols (a2, d4, …; l1, l2, l3 for the
            course's robots).
        timeout: Simplification budget [s]; past it the remaining entries stay unsimplified
            (exact but long) and :attr:`Derivation.notes` says so. ``None``: no limit.
        use_cache: Read and write the cache (memory and ``kinematics.cache_dir()/symbolic``).
            An incomplete cached result is returned for a budget no larger than the one it had,
            and resumed (only its unsimplified entries) for a larger one.
        progress: Called with short progress messages.
        deadline: A deadline shared with other steps (an export); replaces ``timeout``.
        exact: Keep the robot file's numbers as written (no snapping; see :func:`.build_model`).

    Raises:
        SymbolicError: unknown frame, bad timeout, or symbolic parameters for a non-DH robot.
    """
    frame = check_frame(frame)
    timeout = check_timeout(timeout)
    deadline = deadline if deadline is not None else Deadline(timeout)
    budget = deadline.seconds  # the request's whole budget (an export's), not what is left of it
    model = build_model(robot, symbolic_params, exact)
    key = f"derive|{model.cache_key()}|{frame}"
    loaded = cache.load(key) if use_cache else None
    hit: dict[str, Any] | None = loaded if isinstance(loaded, dict) else None
    if hit is not None and (
        hit["complete"] or (budget is not None and hit["timeout"] is not None and budget <= hit["timeout"])
    ):
        return Derivation(**{**hit, "robot": robot.name, "from_cache": True})
    start = time.perf_counter()
    if progress is not None:
        progress(f"deriving the {frame}-frame Jacobian of {robot.name} ({robot.dof} joints)")
    shift = AngleShift(model.q, model.angle_offsets())
    values = model.numeric_values()
    only_J: list[tuple[int, int]] | None = None
    only_T: list[tuple[int, int]] | None = None
    if hit is not None:  # resume: simplify only what the cached run left
        J_raw, T_raw = hit["J"], hit["T"]
        only_J = [(i, j) for m, i, j in hit["pending"] if m == "J"]
        only_T = [(i, j) for m, i, j in hit["pending"] if m == "T"]
        earlier = float(hit["seconds"])
    else:
        limit = None if deadline.seconds is None else deadline  # no limit: the cached frames
        J_raw = jacobian_whitney(robot, frame, symbolic_params, limit, exact)
        T_raw = frames_within(model, limit)[0].tool
        earlier = 0.0
    sJ = simplify_matrix(J_raw, model.q, deadline, progress, "J", shift, only=only_J, values=values)
    sT = simplify_matrix(T_raw, model.q, deadline, progress, "T", shift, only=only_T, values=values)
    pending = tuple(("J", i, j) for i, j in sJ.pending) + tuple(("T", i, j) for i, j in sT.pending)
    notes = ([model.snap_note] if model.snaps else []) + sJ.notes + sT.notes
    result = Derivation(
        robot.name,
        frame,
        model.q,
        robot.joint_types,
        sT.matrix,
        sJ.matrix,
        dict(model.params),
        dict(model.display),
        tuple(notes),
        not pending,
        earlier + time.perf_counter() - start,
        budget if budget is None or hit is None else max(budget, hit["timeout"] or 0.0),
        snaps=model.snaps,
        pending=pending,
    )
    if use_cache:
        cache.store(key, {f.name: getattr(result, f.name) for f in dataclasses.fields(result)})
    return result


def fk(
    robot: Robot,
    *,
    symbolic_params: bool = False,
    simplify: bool = True,
    timeout: float | None = DEFAULT_TIMEOUT,
    use_cache: bool = True,
) -> sp.Matrix:
    """Symbolic forward kinematics ``T_base_tool(q)`` (4×4 ``sympy.Matrix``) in ``q1 … qn``.

    Args:
        robot: The robot.
        symbolic_params: Keep DH lengths and offsets as symbols.
        simplify: Simplified and cached (default) or the raw expanded product.
        timeout: Simplification budget [s] (see :func:`derive`).
        use_cache: Read and write the cache.

    Example:
        >>> from kinematics import Robot
        >>> row = dict(joint="revolute", a=1.0, alpha=0.0, d=0.0, theta=0.0)
        >>> planar2 = Robot.from_dh([row, row], planar=True)
        >>> fk(planar2, use_cache=False)[0, 3]
        cos(q1) + cos(q1 + q2)
    """
    if not simplify:
        return frames(build_model(robot, symbolic_params)).tool
    return derive(robot, "base", symbolic_params=symbolic_params, timeout=timeout, use_cache=use_cache).T


def jacobian(
    robot: Robot,
    frame: str = "base",
    *,
    symbolic_params: bool = False,
    simplify: bool = True,
    timeout: float | None = DEFAULT_TIMEOUT,
    use_cache: bool = True,
) -> sp.Matrix:
    """Symbolic geometric Jacobian J(q) (6×n ``sympy.Matrix``), rows [v; ω], in ``q1 … qn``.

    Args:
        robot: The robot.
        frame: ``"base"`` or ``"tool"`` axes.
        symbolic_params: Keep DH lengths and offsets as symbols.
        simplify: Simplified and cached (default) or Whitney's raw columns.
        timeout: Simplification budget [s] (see :func:`derive`).
        use_cache: Read and write the cache.

    Example:
        >>> from kinematics import Robot
        >>> row = dict(joint="revolute", a=1.0, alpha=0.0, d=0.0, theta=0.0)
        >>> planar2 = Robot.from_dh([row, row], planar=True)
        >>> jacobian(planar2, symbolic_params=True, use_cache=False)[:2, :]
        Matrix([
        [-a1*sin(q1) - a2*sin(q1 + q2), -a2*sin(q1 + q2)],
        [ a1*cos(q1) + a2*cos(q1 + q2),  a2*cos(q1 + q2)]])
    """
    if not simplify:
        return jacobian_whitney(robot, frame, symbolic_params)
    return derive(robot, frame, symbolic_params=symbolic_params, timeout=timeout, use_cache=use_cache).J


def joint_symbols(robot: Robot) -> tuple[sp.Symbol, ...]:
    """The real symbols ``q1 … qn`` used for ``robot``'s joints."""
    return build_model(robot, False).q
