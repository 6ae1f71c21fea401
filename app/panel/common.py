"""Small helpers shared by the panel modules."""

from __future__ import annotations

import math

import viser

__all__ = ["sync_value"]


def sync_value(handle: viser.GuiInputHandle, value: float | str | bool) -> None:
    """Show ``value`` on ``handle`` unless it already shows it (floats compared with a tolerance).

    A slider the user is dragging already holds the value the state was set from; writing back a
    value that differs only by a degree↔radian round-off would echo to the browser and fight the drag.
    """
    current = handle.value
    if isinstance(value, float) and isinstance(current, (int, float)) and not isinstance(current, bool):
        if math.isclose(current, value, rel_tol=1e-9, abs_tol=1e-9):
            return
    elif current == value:
        return
    handle.value = value
