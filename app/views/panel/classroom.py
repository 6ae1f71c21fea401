"""The classroom controls of one tab (shown when the server runs with a presenter token).

A text input "Presenter token" (typing the token makes this tab the presenter: no other click), one
button that says what it does next ("Explore on my own", "Follow the presenter", "Stop presenting")
and a line saying what the tab is: presenting (and how many tabs follow), following (read-only),
or exploring alone.
"""

from __future__ import annotations

import viser

from ...core.commands import ClaimPresenter, Command, ExploreAlone, FollowPresenter, StopPresenting
from ...core.role import Role
from .common import Dispatch, bind, sync_value

__all__ = ["ClassroomPanel"]


class ClassroomPanel:
    """Presenter token, follow / explore alone, and the tab's role in words."""

    def __init__(self, gui: viser.GuiApi, dispatch: Dispatch, order: float) -> None:
        self.role = Role()
        self._shown: Role | None = None
        self.root = gui.add_folder("Classroom", order=order)
        with self.root:
            self.status = gui.add_html("")
            self.token = gui.add_text(
                "Presenter token",
                initial_value="",
                hint="The server's token: this tab then presents.",
            )
            bind(self.token, dispatch, lambda v: ClaimPresenter(str(v)) if str(v).strip() else None)
            self.button = gui.add_button("Explore on my own", visible=False)
            self.button.on_click(lambda _: dispatch(self._next()))

    def _next(self) -> Command:
        r = self.role
        if r.presenting:
            return StopPresenting()
        if r.following:
            return ExploreAlone()
        return FollowPresenter()

    def show(self, role: Role) -> None:
        """Put ``role`` on screen (only what changed)."""
        self.role = role
        if role == self._shown:
            return
        self._shown = role
        if role.presenting:
            n = role.followers
            text = f"<b>You are presenting</b>: {n} tab{'s' if n != 1 else ''} follow{'s' if n == 1 else ''}."
            label = "Stop presenting"
        elif role.following:
            text = "<b>Following the presenter</b>: your inputs are read-only."
            label = "Explore on my own"
        elif role.presenter:
            text = "<b>Exploring on your own</b>; a presenter is on."
            label = "Follow the presenter"
        else:
            text = "No presenter yet: tabs follow the presenter once one is on."
            label = ""
        self.status.content = f'<div class="jl-note" style="font-size:13.5px">{text}</div>'
        self.button.visible = bool(label)
        if label:
            self.button.label = label
        self.token.visible = not role.presenting
        if role.presenting:
            sync_value(self.token, "")

    def remove(self) -> None:
        self.root.remove()
