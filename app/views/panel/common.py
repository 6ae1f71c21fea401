"""Small helpers shared by the panel modules: binding inputs to actions, showing values."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import viser

from ...core.commands import Message
from ...viser_adapter import is_removed

__all__ = ["sync_value", "bind", "bind_click", "Dispatch"]

Dispatch = Callable[[Message], None]


def bind(handle: viser.GuiInputHandle, dispatch: Dispatch, make: Callable[[Any], Message | None]) -> None:
    """When the user changes ``handle``, dispatch ``make(value)`` (nothing when it returns ``None``)."""

    def callback(event: viser.GuiEvent) -> None:
        if not is_removed(event.target):
            action = make(event.target.value)
            if action is not None:
                dispatch(action)

    handle.on_update(callback)


def bind_click(button: viser.GuiButtonHandle, dispatch: Dispatch, make: Callable[[], Message]) -> None:
    """When ``button`` is clicked, dispatch ``make()``."""

    def callback(event: viser.GuiEvent) -> None:
        if not is_removed(event.target):
            dispatch(make())

    button.on_click(callback)


def sync_value(handle: Any, value: float | str | bool) -> None:
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
