"""A handout as a document: the content (:mod:`.content`) written by the writer of the format asked."""

from __future__ import annotations

from collections.abc import Callable, Sequence

from ...model import Robot
from ..core import DEFAULT_TIMEOUT
from .content import HANDOUT_FORMATS, HandoutError, build_handout
from .html import render_html
from .tex import render_tex
from .words import ENGLISH, Words

__all__ = ["handout"]


def handout(
    robot: Robot,
    fmt: str,
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
) -> str:
    """The derivation of ``robot``'s J as a complete document: ``fmt`` ``"html"`` (MathML, no script,
    no network) or ``"tex"`` (a LaTeX document, amsmath).

    Args:
        robot: Any robot (a URDF chain has no DH table; its joint and link frames are used).
        fmt: ``"html"`` or ``"tex"``.
        method: ``"whitney"``, ``"differentiation"``, ``"propagation"``, ``"force"`` or ``"all"``.
        frame: ``"base"`` or ``"tool"``: the axes of J's rows.
        symbolic_params: DH lengths and offsets as symbols (the course's letters where the robot
            file names them).
        configuration: Name of the robot's configuration for the worked example (default:
            ``"home"``, else the middle of the joint ranges).
        rates: Joint rates q̇ (n,) [rad/s | m/s] for the example's v = J q̇.
        twist: A tool velocity [v; ω] (6,) [m/s; rad/s] for the example's q̇ = J⁻¹ v (task rows).
        timeout: Time budget [s] for the whole derivation; past it steps stay unsimplified (noted).
        progress: Called with short messages while the work goes on.
        words: The handout's language (:class:`.words.Words`: the app's Translator): its words, its
            decimal commas, the robot's texts in it (else English). Default: English.

    Raises:
        HandoutError: unknown format, method or configuration, wrong rates or twist.
        SymbolicError: bad frame or timeout, symbolic parameters for a robot without a DH table.
    """
    if fmt not in HANDOUT_FORMATS:
        raise HandoutError(f"format must be one of {', '.join(HANDOUT_FORMATS)}, got {fmt!r}")
    h = build_handout(
        robot,
        method,
        frame=frame,
        symbolic_params=symbolic_params,
        configuration=configuration,
        rates=rates,
        twist=twist,
        timeout=timeout,
        progress=progress,
        words=words,
    )
    return render_html(h) if fmt == "html" else render_tex(h)
