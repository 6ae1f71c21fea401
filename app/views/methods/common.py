"""What the method views share: the course's vectors as HTML rows, the check line, the drawn colours.

A method's ``draw`` returns :data:`Drawn`: (thick arrows, thin arrows, lines, labels) with arrows
(start, vector, rgb), lines (a, b, rgb) and labels (text, position), all in base axes [m];
:class:`app.views.scene.derive.DeriveScene` puts them on its few nodes.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from kinematics import Robot
from kinematics.steps import StepMethod

from ...core.i18n import Translator
from ...core.snapshot import Snapshot
from ...core.snapshot.derive import Derivation
from .. import fmt

__all__ = ["MethodView", "vec", "row", "check", "note", "matrix4_html", "Drawn", "AXIS_RGB", "LEVER_RGB"]

Drawn = tuple[list[Any], list[Any], list[Any], list[Any]]
"""(thick arrows, thin arrows, lines, labels) of one step."""


@dataclass(frozen=True)
class MethodView:
    """One derivation method as the app shows it: the record of :data:`app.views.methods.METHODS`.

    Attributes:
        steps: Its numbers, label, title and intro (:data:`kinematics.steps.METHODS`), shared with the
            handout; its symbolic steps are :data:`kinematics.symbolic.steps.methods.METHOD_STEPS` under
            the same key.
        html: ``html(robot, derivation, snapshot, tr)`` → one step in the Derive tab, with its check against
            J, in the tab's language ``tr`` (its words from the catalogs, escaped; its numbers' decimal mark).
        draw: ``draw(robot, derivation, snapshot, unit, lin, tr)`` → :data:`Drawn` for the 3-D view
            (``unit``: length of a unit direction [m]; ``lin``: seconds a velocity is drawn for, both with
            the scale; ``tr``: the language of its labels, plain text).
    """

    steps: StepMethod
    html: Callable[[Robot, Derivation, Snapshot, Translator], str]
    draw: Callable[[Robot, Derivation, Snapshot, float, float, Translator], Drawn]

    @property
    def key(self) -> str:
        return self.steps.key

    @property
    def label(self) -> str:
        return self.steps.label

    @property
    def title(self) -> str:
        return self.steps.title

    @property
    def intro(self) -> str:
        return self.steps.intro

    @property
    def numeric(self) -> Callable[..., Any] | None:
        """The numbers of one step (``None``: the DH frames, which every step has)."""
        return self.steps.step

    @property
    def symbolic(self) -> Callable[..., Any] | None:
        """Its symbolic steps (imports SymPy; ``None`` for the DH frames, whose ⁰Tᵢ every method has)."""
        from kinematics.symbolic.steps.methods import METHOD_STEPS

        return METHOD_STEPS.get(self.key)

    @property
    def symbols(self) -> tuple[str, ...]:
        """Key prefixes of the symbolic steps shown for one joint."""
        return self.steps.symbols


AXIS_RGB = ((214, 40, 40), (30, 150, 60), (35, 80, 220))
"""Colours of drawn frame axes x, y, z."""
LEVER_RGB = (60, 64, 72)
"""The lever from a joint axis to the tool point (pₙ − pᵢ₋₁): dark, to read against the floor grid."""


def vec(values: np.ndarray, unit: str = "", tr: Translator | None = None) -> str:
    """A vector as "(x, y, z) unit", three decimals, round-off zeros cleaned, in ``tr``'s numbers:
    "(0,125; −0,3; 1)" where the decimal mark is a comma (a semicolon then parts the components, as
    the courses 000, 002 and 004 write them)."""
    sep = "; " if tr is not None and tr.decimal_symbol == "," else ", "
    return (
        "("
        + sep.join(fmt.fixed(x, 3, tr) for x in fmt.cleaned(values, 1e-12))
        + ")"
        + (f" {unit}" if unit else "")
    )


def row(name: str, value: str, cls: str = "") -> str:
    """One named row of a step's table of vectors (``name`` and ``value``: HTML, escaped already)."""
    return f'<tr{cls}><th class="rowname">{name}</th><td>{value}</td></tr>'


def check(ok: bool, what: str) -> str:
    """The line that says whether the step agrees with J (``what``: plain text, escaped here)."""
    return f'<div class="jl-note">{"✓" if ok else "✗"} {fmt.escape(what)}</div>'


def note(text: str) -> str:
    """A note under a step (``text``: plain text, a translated sentence: escaped here)."""
    return f'<div class="jl-note">{fmt.escape(text)}</div>'


def matrix4_html(T: np.ndarray, title: str, tr: Translator | None = None) -> str:
    """A 4×4 transform as a small bracketed table under ``title`` (plain text, escaped here), its
    numbers in ``tr``'s decimal mark."""
    rows = "".join(
        "<tr>" + "".join(f"<td>{fmt.fixed(x, 3, tr)}</td>" for x in fmt.cleaned(r, 1e-12)) + "</tr>"
        for r in T
    )
    table = f'<table class="jl-matrix jl-br">{rows}</table>'
    return f'<div class="jl-t4"><div class="jl-t4-title">{fmt.escape(title)}</div>{table}</div>'
