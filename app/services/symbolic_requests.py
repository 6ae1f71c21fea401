"""What a :class:`~app.services.symbolic_service.SymbolicService` may have computed, by name.

:data:`REQUESTS` is the fixed table of kinds ("mathml", "inverse", "steps", "export"): each names a
function run in a symbolic worker process and the types of its arguments. A service sends a kind and
arguments, never a function; the parent's one pool of ``serve --workers N``
(:mod:`app.services.symbolic_relay`) runs nothing else, and checks the arguments first. The functions
import the symbolic modules lazily, in the worker, and say so plainly when they are missing.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from kinematics import Robot

if TYPE_CHECKING:
    from kinematics.symbolic.steps.step import Step

__all__ = [
    "REQUESTS",
    "Request",
    "SymbolicUnavailable",
    "SymbolicStopped",
    "SymbolicNotAttempted",
    "MAX_SYMBOLIC_JOINTS",
    "STEP_WIDTH_PX",
]

MAX_SYMBOLIC_JOINTS = 7
"""The most joints of an arm whose symbolic J, J⁻¹, steps or export the server attempts. Measured cold
(``bench/bench_symbolic_size.py``, docs/performance.md): a general 7-joint URDF chain takes 39 s and
97 MB, the library's 7-joint arms less; no 8-joint chain of general axes, and no 12- or 24-joint
chain at all, finished in 60 s, and their memory kept growing (to gigabytes in minutes)."""


class SymbolicUnavailable(RuntimeError):
    """The symbolic module (or the export module) is not installed in this build."""


class SymbolicStopped(RuntimeError):
    """The server stopped a symbolic computation at one of its limits
    (:class:`~app.services.symbolic_process.Limits`).

    Attributes:
        limit: ``"time"`` or ``"memory"``: the limit it reached.
        seconds: The time limit [s].
        memory_mb: The memory limit [MB].
    """

    def __init__(self, limit: str, seconds: float, memory_mb: float) -> None:
        super().__init__(limit, seconds, memory_mb)  # pickled between processes as these three
        self.limit, self.seconds, self.memory_mb = limit, seconds, memory_mb

    def __str__(self) -> str:
        if self.limit == "time":
            return f"stopped after {self.seconds:.0f} s"
        return f"stopped at {self.memory_mb:.0f} MB"


class SymbolicNotAttempted(RuntimeError):
    """A symbolic computation the server does not start: the arm has more joints than
    :data:`MAX_SYMBOLIC_JOINTS` (from ``bench/bench_symbolic_size.py``).

    Attributes:
        joints: The arm's joints.
        most: The most joints attempted.
    """

    def __init__(self, joints: int, most: int) -> None:
        super().__init__(joints, most)
        self.joints, self.most = joints, most

    def __str__(self) -> str:
        return f"{self.joints} joints, more than the {self.most} worked out symbolically"


STEP_WIDTH_PX = 370
"""Width [px] the Derive tab's formulas are typeset for (the docked panel, less its padding)."""


def _math_blocks(rows: list[str]) -> str:
    """Each MathML row as a display formula of its own (det J, singular sets), one per line."""
    from kinematics.symbolic.typeset.render import MATH_STYLE

    return "".join(f'\n<math display="block" style="{MATH_STYLE}"><mrow>{r}</mrow></math>' for r in rows)


def _mathml(robot: Robot, frame: str, timeout: float, letters: bool = False) -> str:
    """In the worker process: the MathML of J(q) (with letters: and det J, its factors, singular sets)."""
    try:
        from kinematics.symbolic import jacobian_mathml, mathml_parts
    except ImportError as exc:
        raise SymbolicUnavailable("symbolic form not available (kinematics.symbolic is missing)") from exc
    if not letters:
        return jacobian_mathml(robot, frame=frame, timeout=timeout)
    out = jacobian_mathml(robot, frame=frame, timeout=timeout, symbolic_params=True)
    parts = mathml_parts(robot, frame, symbolic_params=True, with_det=True, timeout=timeout, wrap=True)
    extra = _math_blocks(([parts.det] if parts.det else []) + list(parts.singular))
    at = out.find('\n<p class="jl-legend">')  # det J under J, before the legend of both
    return out + extra if at < 0 else out[:at] + extra + out[at:]


def _inverse_mathml(robot: Robot, letters: bool, timeout: float) -> str:
    """In the worker process: the MathML of J⁻¹ = adj(J) / det J."""
    try:
        from kinematics.symbolic.inverse import inverse_mathml
    except ImportError as exc:
        raise SymbolicUnavailable("symbolic form not available (kinematics.symbolic is missing)") from exc
    return inverse_mathml(robot, symbolic_params=letters, timeout=timeout)


def _steps_mathml(
    robot: Robot, method: str, timeout: float, letters: bool = False
) -> tuple[tuple[int | None, str, str, str, tuple[str, tuple[tuple[str, str], ...]]], ...]:
    """In the worker process: every step of one derivation, its caption and its MathML (panel width),
    and the caption's catalog id with its arguments (("", ()) for a caption not marked for the catalogs)
    so the tab shows it in its own language."""
    try:
        from kinematics.symbolic import derivation_steps
        from kinematics.symbolic.handout.parts import singular_texts
    except ImportError as exc:
        raise SymbolicUnavailable("symbolic steps not available (kinematics.symbolic is missing)") from exc

    def body(s: Step) -> str:  # det J's step: its singular sets under it, as in the handout
        ml = s.mathml(STEP_WIDTH_PX)
        return ml + _math_blocks(singular_texts(s.notation(), s, latex=False)) if s.singular else ml

    def words(s: Step) -> tuple[str, tuple[tuple[str, str], ...]]:
        return (str(getattr(s.title, "msgid", "")), tuple(getattr(s.title, "args", ())))

    return tuple(
        (s.joint, s.key, s.title_html(), body(s), words(s))
        for s in derivation_steps(robot, method, symbolic_params=letters, timeout=timeout)
    )


def _export(robot: Robot, fmt: str, frame: str, timeout: float, name: str) -> tuple[str, bytes]:
    """In the worker process: J(q) exported by kinematics.symbolic.typeset.export."""
    try:
        from kinematics.symbolic.typeset.export import export
    except ImportError as exc:
        raise SymbolicUnavailable(
            "export not available (kinematics.symbolic.typeset.export is missing)"
        ) from exc
    return name, export(robot, fmt, frame=frame, timeout=timeout).encode("utf-8")


@dataclasses.dataclass(frozen=True)
class Request:
    """One kind of computation a :class:`SymbolicService` asks for.

    Attributes:
        fn: The function run in the worker process (module-level, imported there by name).
        types: The type of each argument (``bool`` and ``float`` exactly: a bool is no time limit).
        timeout_at: Which argument is the time limit [s] (it is not part of the request's key).
    """

    fn: Callable[..., Any]
    types: tuple[type, ...]
    timeout_at: int

    def check(self, args: tuple) -> None:
        """Raise ``TypeError`` unless ``args`` are of :attr:`types` (what the relay lets a worker send)."""
        if len(args) != len(self.types):
            raise TypeError(f"{self.fn.__name__} takes {len(self.types)} arguments, got {len(args)}")
        for value, kind in zip(args, self.types, strict=True):
            ok = type(value) is kind if kind in (bool, float, str) else isinstance(value, kind)
            if not ok:
                raise TypeError(
                    f"{self.fn.__name__}: {type(value).__name__} given where {kind.__name__} belongs"
                )


REQUESTS: dict[str, Request] = {
    "mathml": Request(_mathml, (Robot, str, float, bool), 2),
    "inverse": Request(_inverse_mathml, (Robot, bool, float), 2),
    "steps": Request(_steps_mathml, (Robot, str, float, bool), 2),
    "export": Request(_export, (Robot, str, str, float, str), 3),
}
"""Every computation a service asks for, by name: the only functions a worker of ``serve --workers N``
can have the parent's symbolic pool run (it sends a name and arguments, never a function)."""
