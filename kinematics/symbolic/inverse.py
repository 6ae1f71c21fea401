"""The symbolic inverse Jacobian the way the course writes it: J⁻¹ = adj(J) / det J.

For a square task Jacobian (as many task rows as joints), :func:`inverse`
gives the adjugate of the task rows of J, entry by entry simplified, and the
factored det J (:func:`.singular.determinant`), so J⁻¹ = adj(J) / det J
exists exactly where det J ≠ 0: the singular sets of det J are where the
inverse blows up. :func:`inverse_mathml` typesets it for the browser.

The adjugate of an n×n symbolic matrix grows fast with n; it is computed for
up to :data:`MAX_JOINTS` joints (the course's examples have two and three).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..analysis import task_rows
from ..model import Robot
from .core import DEFAULT_TIMEOUT, derive
from .model import SymbolicError
from .simplify import simplify_matrix
from .singular import Determinant, determinant
from .trig import Deadline
from .typeset.escape import NOTE_CHARS, xml_text
from .typeset.layout import MATHML_WIDTH, mathml_matrix
from .typeset.render import MATH_STYLE, notation_for

__all__ = ["SymbolicInverse", "inverse", "inverse_mathml", "MAX_JOINTS"]

MAX_JOINTS = 4
"""Largest number of joints whose adjugate is worked out symbolically."""


@dataclass(frozen=True, eq=False)
class SymbolicInverse:
    """J⁻¹ = adj(J) / det J of the task rows of the base-frame J.

    Attributes:
        rows: The task rows of J used (0–2: v, 3–5: ω).
        J: Those rows of J(q) (n×n).
        adj: adj(J) (n×n), simplified (J · adj(J) = det J · I).
        det: The factored det J and its singular sets.
        notes: Human-readable notes (time limits, snapped values).
    """

    rows: tuple[int, ...]
    J: sp.Matrix
    adj: sp.Matrix
    det: Determinant
    notes: tuple[str, ...]

    @property
    def matrix(self) -> sp.Matrix:
        """J⁻¹ as one matrix, adj(J) / det J (``None`` entries never: raises if det J is unknown)."""
        expr = self.det.expr
        if expr is None:
            raise SymbolicError("det J was not computed (time limit): J⁻¹ is not known")
        return self.adj / expr


def inverse(
    robot: Robot, *, symbolic_params: bool = False, timeout: float | None = DEFAULT_TIMEOUT
) -> SymbolicInverse:
    """adj(J) and det J of the robot's square task Jacobian (its task rows, base axes).

    Raises:
        SymbolicError: the task rows are not square (use J⁺), det J is identically zero,
            or the robot has more than :data:`MAX_JOINTS` joints.
    """
    if robot.dof > MAX_JOINTS:
        raise SymbolicError(
            f"J⁻¹ is worked out symbolically for up to {MAX_JOINTS} joints; "
            f"{robot.name} has {robot.dof} (its numeric J⁻¹ is shown)"
        )
    rows = task_rows(robot)
    if len(rows) != robot.dof:
        raise SymbolicError(
            f"{robot.name}'s task J has {len(rows)} rows and {robot.dof} columns: "
            "it has no inverse, only the pseudo-inverse J⁺"
        )
    deadline = Deadline(timeout)
    det = determinant(robot, rows, symbolic_params=symbolic_params, deadline=deadline)
    if det.identically_zero:
        raise SymbolicError(f"det J of {robot.name} is identically zero: J⁻¹ never exists")
    d = derive(robot, "base", symbolic_params=symbolic_params, deadline=deadline)
    J = d.J.extract(list(det.rows), list(range(robot.dof)))
    adj = simplify_matrix(J.adjugate(), d.q, deadline, label="adj J", values=dict(d.params) or None)
    notes = tuple(dict.fromkeys([*d.notes, *det.notes, *adj.notes]))
    return SymbolicInverse(tuple(det.rows), J, adj.matrix, det, notes)


def inverse_mathml(
    robot: Robot, *, symbolic_params: bool = False, timeout: float | None = DEFAULT_TIMEOUT
) -> str:
    """``<math>J⁻¹ = adj J / det J</math>``, ``adj J = […]``, det J factored, where J⁻¹ does not exist,
    the legend and notes (for the browser; see :func:`inverse`)."""
    inv = inverse(robot, symbolic_params=symbolic_params, timeout=timeout)
    d = derive(robot, "base", symbolic_params=symbolic_params, timeout=timeout)  # cached by inverse()
    N = notation_for(d, robot)
    expr = inv.det.expr
    if expr is None:
        raise SymbolicError("det J was not computed within the time limit: J⁻¹ is not shown")
    adj, skipped = mathml_matrix(N, inv.adj, None, MATHML_WIDTH)
    j_inv = "<msup><mi>J</mi><mrow><mo>−</mo><mn>1</mn></mrow></msup>"
    eq = "<mo>=</mo>"
    over = (
        "<mfrac><mrow><mi>adj</mi><mo>&#x2061;</mo><mi>J</mi></mrow>"
        "<mrow><mi>det</mi><mo>&#x2061;</mo><mi>J</mi></mrow></mfrac>"
    )
    parts = [
        f"{j_inv}{eq}{over}",  # adj J on a line of its own: the panel is narrow
        f"<mi>adj</mi><mo>&#x2061;</mo><mi>J</mi>{eq}{adj}",
        f"<mi>det</mi><mo>&#x2061;</mo><mi>J</mi>{eq}{N.mathml(expr)}",
    ]
    for s in inv.det.singular_sets:
        text = f"{N.mathml(s.factor)}{eq}<mn>0</mn>"
        if s.solutions is not None and len(s.joints) == 1 and s.factor != s.joints[0]:
            where = N.mathml(sp.FiniteSet(*s.solutions))
            text += f"<mo>&#x21D2;</mo>{N.mathml(s.joints[0])}<mo>&#x2208;</mo>{where}"
        parts.append(f'{text}<mspace width="1em"/><mtext>(no J⁻¹ there)</mtext>')
    out = "\n".join(f'<math display="block" style="{MATH_STYLE}"><mrow>{p}</mrow></math>' for p in parts)
    items = N.mathml_legend_items()
    if items:
        out += (
            '\n<p class="jl-legend">where '
            + ", ".join(f'<math style="{MATH_STYLE}">{item}</math>' for item in items)
            + "</p>"
        )
    notes = list(inv.notes)
    if skipped:
        notes.append(f"{len(skipped)} entries of adj J are too long to typeset and are shown as ∗")
    for note in notes:
        out += f'\n<p class="jl-note">{xml_text(note, NOTE_CHARS)}</p>'
    return out
