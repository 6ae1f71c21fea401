"""What the panel modules share: binding inputs to actions, showing values, the widgets of the option
table, and the tab protocol (a tab is one module plus one entry in :data:`app.views.panel.TABS`)."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol

import viser

import robots
from kinematics import Robot

from ...core.actions import Action, SetOption
from ...core.commands import Message
from ...core.i18n import Translator, translations
from ...core.options import OPTION
from ...core.snapshot import Snapshot
from ...core.state import LabState
from ...viser_adapter import is_removed, on_event_loop

__all__ = [
    "sync_value",
    "bind",
    "bind_click",
    "Dispatch",
    "option_widget",
    "show_option",
    "Tab",
    "TabContext",
    "TabView",
]

Dispatch = Callable[[Message], None]


def bind(handle: viser.GuiInputHandle, dispatch: Dispatch, make: Callable[[Any], Message | None]) -> None:
    """When the user changes ``handle``, dispatch ``make(value)`` (nothing when it returns ``None``)."""

    def callback(event: viser.GuiEvent) -> None:
        if not is_removed(event.target):
            action = make(event.target.value)
            if action is not None:
                dispatch(action)

    handle.on_update(on_event_loop(callback))  # it only queues: no thread hand-over per change


def bind_click(button: viser.GuiButtonHandle, dispatch: Dispatch, make: Callable[[], Message]) -> None:
    """When ``button`` is clicked, dispatch ``make()``."""

    def callback(event: viser.GuiEvent) -> None:
        if not is_removed(event.target):
            dispatch(make())

    button.on_click(on_event_loop(callback))


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


def option_widget(
    gui: viser.GuiApi,
    dispatch: Dispatch,
    name: str,
    initial: Any = None,
    tr: Translator | None = None,
    **kwargs: Any,
) -> Any:
    """The widget of option ``name`` as its row of :data:`app.core.options.OPTION` describes it (a
    checkbox, a slider over its range, a dropdown of its choices' labels), bound to ``SetOption``.

    ``initial``: the value shown first (default: the row's default); ``tr``: the tab's language (its
    label, hint and choices' labels translated); ``kwargs`` go to viser (``order``, ``disabled`` …).
    """
    _ = (tr or translations()).gettext
    row = OPTION[name]
    value = row.default if initial is None else initial
    hint = _(row.hint) if row.hint else None
    if row.kind == "bool":
        box = gui.add_checkbox(_(row.label), initial_value=bool(value), hint=hint, **kwargs)
        bind(box, dispatch, lambda v: SetOption(name, bool(v)))
        return box
    if row.kind == "float":
        slider = gui.add_slider(
            _(row.label),
            min=row.lo,
            max=row.hi,
            step=row.step,
            initial_value=float(value),
            hint=hint,
            **kwargs,
        )
        bind(slider, dispatch, lambda v: SetOption(name, float(v)))
        return slider
    if row.kind == "choice":
        shown = tuple(_(label) for label in (row.labels or row.choices))
        menu = gui.add_dropdown(
            _(row.label), shown, initial_value=shown[row.choices.index(value)], hint=hint, **kwargs
        )

        def chosen(label: Any) -> Action | None:
            choice = row.choices[shown.index(label)] if label in shown else None
            return None if choice is None else SetOption(name, choice)

        bind(menu, dispatch, chosen)
        return menu
    raise ValueError(f"option {name!r} ({row.kind}) has no widget of its own kind: its tab builds it")


def show_option(handle: Any, name: str, value: Any, tr: Translator | None = None) -> None:
    """Show option ``name``'s ``value`` on its widget (a choice by its label, in ``tr``'s language)."""
    row = OPTION[name]
    if row.kind == "choice":
        sync_value(handle, (tr or translations()).gettext(row.label_of(value)))
    elif row.kind == "float":
        sync_value(handle, float(value))
    else:
        sync_value(handle, value)


@dataclass(frozen=True)
class TabContext:
    """What a tab's view is built from, once per robot.

    Attributes:
        gui: The tab's GUI (widgets added under the tab's handle).
        dispatch: Where its widgets send actions.
        robot: The robot shown; rows: its task rows; presets: its resolved-rate presets.
        joint_sliders: The ids of the joint sliders (always visible above the tabs).
        tr: The tab's language (every word a view shows, and its numbers).
    """

    gui: viser.GuiApi
    dispatch: Dispatch
    robot: Robot
    rows: tuple[int, ...]
    presets: Sequence[robots.MotionPreset]
    joint_sliders: Sequence[str]
    tr: Translator = field(default_factory=translations)


class TabView(Protocol):
    """One tab's widgets for one robot: drawn on every redraw, removed on a robot switch.

    A view may also list ``stepped``: its sliders whose step the page must honour (typed values).
    """

    def draw(self, state: LabState, snap: Snapshot) -> None: ...

    def remove(self) -> None: ...


@dataclass(frozen=True)
class Tab:
    """One entry of the panel's list of tabs (:data:`app.views.panel.TABS`).

    Attributes:
        name: The panel's attribute for its view (``panel.matrix``) and the tab's key.
        label: The tab's title; icon: its icon.
        build: Makes the view for a robot, inside the tab (``None``: the tab has no per-robot view).
    """

    name: str
    label: str
    icon: Any  # a viser.Icon (its type, IconName, is not public)
    build: Callable[[TabContext], TabView] | None
