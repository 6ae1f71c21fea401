"""The first hint: what a new tab says to do first, in the 3-D view's lower corner, until its first change."""

from __future__ import annotations

from ...core.i18n import N_, Translator, translations
from ...core.state import LabState

__all__ = ["FIRST_HINT", "hint_html"]

FIRST_HINT = N_(
    "<b>First:</b> drag a joint slider and watch J(q) change; then pick a singularity under Configuration."
)
"""What a new tab says to do first, in the 3-D view's lower corner, until its first change."""


def hint_html(state: LabState, tr: Translator | None = None) -> str:
    """The first hint ("" once the tab has changed anything: gone for good)."""
    hint = (tr or translations()).gettext(FIRST_HINT)
    return "" if state.started else f'<div class="jl jl-hint">{hint}</div>'
