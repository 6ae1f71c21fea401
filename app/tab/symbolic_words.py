"""What a tab is told, in whole sentences, when the server stopped or did not start a symbolic
computation for it (issue 26: the limits of :mod:`app.services.symbolic_process` and the rule
:data:`~app.services.symbolic_requests.MAX_SYMBOLIC_JOINTS`).

Each sentence names what it still has (the numeric J, the numbers of the step) and takes its figures
as named placeholders (``{joints}``, ``{seconds}``, ``{megabytes}``, ``{most}``, ``{label}``), so that
a catalogue can translate it whole.
"""

from __future__ import annotations

from ..core.i18n import N_, Translator, translations
from ..services.symbolic_requests import SymbolicNotAttempted, SymbolicStopped

__all__ = ["SENTENCES", "TITLES", "told"]

SENTENCES: dict[tuple[str, str], str] = {
    ("matrix", "time"): N_(
        "The symbolic J of this {joints}-joint arm did not finish within {seconds} s and was stopped; "
        "the numeric J above is live."
    ),
    ("matrix", "memory"): N_(
        "The symbolic J of this {joints}-joint arm needed more than {megabytes} MB of the server's "
        "memory and was stopped; the numeric J above is live."
    ),
    ("matrix", "not attempted"): N_(
        "The symbolic J of this {joints}-joint arm is not worked out: the server works out arms of up to "
        "{most} joints in symbols, as larger ones do not finish within its limits. "
        "The numeric J above is live."
    ),
    ("inverse", "time"): N_(
        "The symbolic J⁻¹ of this {joints}-joint arm did not finish within {seconds} s and was stopped; "
        "the numeric J above is live."
    ),
    ("inverse", "memory"): N_(
        "The symbolic J⁻¹ of this {joints}-joint arm needed more than {megabytes} MB of the server's "
        "memory and was stopped; the numeric J above is live."
    ),
    ("inverse", "not attempted"): N_(
        "The symbolic J⁻¹ of this {joints}-joint arm is not worked out: the server works out arms of up to "
        "{most} joints in symbols. The numeric J above is live."
    ),
    ("derive", "time"): N_(
        "The steps in symbols for this {joints}-joint arm did not finish within {seconds} s and were "
        "stopped; the numbers above are live."
    ),
    ("derive", "memory"): N_(
        "The steps in symbols for this {joints}-joint arm needed more than {megabytes} MB of the server's "
        "memory and were stopped; the numbers above are live."
    ),
    ("derive", "not attempted"): N_(
        "The steps in symbols for this {joints}-joint arm are not worked out: the server works out arms of "
        "up to {most} joints in symbols. The numbers above are live."
    ),
    ("download", "time"): N_(
        "J(q) of this {joints}-joint arm as {label} did not finish within {seconds} s and was stopped; "
        "nothing was downloaded."
    ),
    ("download", "memory"): N_(
        "J(q) of this {joints}-joint arm as {label} needed more than {megabytes} MB of the server's memory "
        "and was stopped; nothing was downloaded."
    ),
    ("download", "not attempted"): N_(
        "J(q) of this {joints}-joint arm is not exported as {label}: the server works out arms of up to "
        "{most} joints in symbols."
    ),
}
"""The sentence for each (part of the tab, what happened)."""

TITLES: dict[str, str] = {
    "time": N_("Symbolic form stopped"),
    "memory": N_("Symbolic form stopped"),
    "not attempted": N_("Symbolic form not attempted"),
}
"""The title of the notice for each outcome."""


def told(
    part: str, exc: BaseException, joints: int, label: str = "", tr: Translator | None = None
) -> tuple[str, str] | None:
    """(title, sentence) for ``exc`` if it is a limit of the server's (else None), in ``tr``'s language.

    Args:
        part: ``"matrix"``, ``"inverse"``, ``"derive"`` or ``"download"``.
        exc: The error the computation's future failed with.
        joints: The arm's joints.
        label: The download's format ("LaTeX", "Python" …).
        tr: The tab's language (default English).
    """
    if isinstance(exc, SymbolicStopped):
        outcome = exc.limit
        figures = {"seconds": f"{exc.seconds:.0f}", "megabytes": f"{exc.memory_mb:.0f}", "most": ""}
    elif isinstance(exc, SymbolicNotAttempted):
        outcome, figures = "not attempted", {"seconds": "", "megabytes": "", "most": str(exc.most)}
    else:
        return None
    sentence = SENTENCES.get((part, outcome))
    if sentence is None:
        return None
    _ = (tr or translations()).gettext
    return _(TITLES[outcome]), _(sentence).format(joints=joints, label=label, **figures)
