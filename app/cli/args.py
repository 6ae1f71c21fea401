"""Command-line numbers checked as argparse reads them: finite, and within bounds that keep every
command short (a recording of ``--fps 1e6`` or a ``--timeout`` of ``inf`` would run for ever)."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable

__all__ = ["bounded", "MAX_SECONDS", "MAX_FPS", "MAX_TIMEOUT"]

MAX_SECONDS = 600.0
"""Longest recording [s]."""
MAX_FPS = 120.0
"""Most frames per second of a recording."""
MAX_TIMEOUT = 3600.0
"""Longest time limit of a symbolic simplification [s]."""


def bounded(low: float, high: float, unit: str = "", open_low: bool = True) -> Callable[[str], float]:
    """An argparse ``type``: a finite number in ``(low, high]`` (``[low, high]`` unless ``open_low``)."""
    unit_text = f" {unit}" if unit else ""
    span = f"{'more than' if open_low else 'from'} {low:g} {'up ' if open_low else ''}to {high:g}{unit_text}"

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a number {span}, got {text[:40]!r}") from None
        below = value <= low if open_low else value < low
        if not math.isfinite(value) or below or value > high:
            raise argparse.ArgumentTypeError(f"expected a number {span}, got {text[:40]}")
        return value

    return parse
