"""The mappings' shared pieces: bars of joint values and tables of twists (the v = J q̇, q̇ = J⁺ v and
τ = Jᵀ F tabs of :mod:`.mappings`), in the tab's language."""

from __future__ import annotations

import math

import numpy as np
import viser

from kinematics import Robot

from ...core.i18n import Translator, translations
from ...core.ranges import Range
from .. import fmt
from ..palette import joint_hex, joint_text_hex
from .readouts import ROW_NAMES

__all__ = ["bars_html", "vector_table_html", "TYPED_DIGITS"]


def _display(kind: str, value: float) -> tuple[float, str]:
    return (math.degrees(value), "°/s") if kind == "revolute" else (float(value), "m/s")


def bars_html(
    values: list[tuple[float, str]],
    robot: Robot,
    full_scale: list[float],
    caption: str,
    tr: Translator | None = None,
) -> str:
    """One centred bar per joint, coloured like the joint; a bar beyond ``full_scale`` is hatched.

    Args:
        values: (value, unit) per joint, in display units (float noise already cleaned).
        robot: The robot (joint count).
        full_scale: Value at which each bar reaches the edge.
        caption: Text under the bars (HTML).
        tr: The tab's language (how the values' numbers are written).
    """
    rows = []
    for i, ((v, unit), full) in enumerate(zip(values, full_scale, strict=True)):
        v = float(v) if math.isfinite(v) else 0.0
        frac = min(abs(v) / full, 1.0) if full > 0 else 0.0
        left = 50.0 if v >= 0 else 50.0 - 50.0 * frac
        bar_class = "jl-bar over" if abs(v) > full else "jl-bar"
        bar_style = f"left:{left:.2f}%;width:{50.0 * frac:.2f}%;background-color:{joint_hex(i)}"
        title = fmt.escape(robot.joints[i].name)
        rows.append(
            f'<tr><td class="name" style="color:{joint_text_hex(i)}" title="{title}">q{i + 1}</td>'
            f'<td class="track"><div class="jl-bar-bg"><div class="jl-bar-mid"></div>'
            f'<div class="{bar_class}" style="{bar_style}"></div></div></td>'
            f'<td class="val">{fmt.quantity(v, unit, tr=tr)}</td></tr>'
        )
    table = f'<table class="jl-bars">{"".join(rows)}</table>'
    return f'<div class="jl">{table}<div class="jl-note">{caption}</div></div>'


def vector_table_html(
    rows: tuple[int, ...], columns: list[tuple[str, np.ndarray, str]], tr: Translator | None = None
) -> str:
    """A table of twists: one line per (label, twist (6,), css class), one column per row of ``rows``.

    v rows are in m/s, ω rows in °/s (like the sliders).
    """
    tr = tr or translations()
    head = "".join(f"<th>{ROW_NAMES[r]}</th>" for r in rows)
    body = []
    for label, twist, css in columns:
        shown = fmt.cleaned([twist[r] if r < 3 else math.degrees(twist[r]) for r in rows])
        cells = "".join(f"<td>{fmt.number(x, 5, tr)}</td>" for x in shown)  # the course's 17.256
        body.append(f'<tr class="{css}"><th class="rowname">{label}</th>{cells}</tr>')
    if any(r >= 3 for r in rows):
        units = tr.gettext("v in m/s, ω in °/s, base axes")
    else:
        units = tr.gettext("m/s, base axes")
    return (
        f'<div class="jl"><table class="jl-vec"><tr><th></th>{head}</tr>{"".join(body)}</table>'
        f'<div class="jl-note">{units}</div></div>'
    )


TYPED_DIGITS = 4
"""Decimals a slider's box keeps when a value is typed (the course's v = 17.256 m/s, 89.98 °/s); the
slider's step only sets how far one drag or arrow key moves."""


def _slider(gui: viser.GuiApi, label: str, r: Range, hint: str) -> viser.GuiSliderHandle:
    slider = gui.add_slider(
        f"{label} [{r.unit}]", min=r.lo, max=r.hi, step=r.step, initial_value=0.0, hint=hint
    )
    slider.precision = max(int(slider.precision), TYPED_DIGITS)
    return slider
