"""What one tab waits for from the symbolic worker: J(q), J⁻¹ and the Derive tab's steps.

Each is a :class:`Wanted` slot: it asks the shared
:class:`~app.services.symbolic_service.SymbolicService` once per
key (robot, frame, notation …), releases the request it replaces (so work no tab waits for any more
is dropped), and shows a note while the worker computes. A result comes back as an explicit message,
:class:`~app.core.commands.SymbolicResult`, dispatched into the tab's queue like any input: the
session's loop hands it to :meth:`TabSymbols.take`, which keeps it only if it is still the one
wanted, and the draw puts what is kept on the panel (:meth:`TabSymbols.draw`). No worker thread
touches a view. :class:`TabSymbols` derives the three keys from the tab's state
(:meth:`TabSymbols.update`, at every commit) and releases everything when the tab closes.
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Future
from typing import Any

from ..core.commands import Message, SymbolicResult
from ..core.i18n import N_, Translator, translations
from ..core.state import LabState
from ..services.symbolic_service import (
    WORKER_RESTARTED,
    SymbolicFuture,
    SymbolicNotAttempted,
    SymbolicService,
    SymbolicUnavailable,
)
from ..views.panel import PanelView
from .symbolic_words import TITLES, told

__all__ = ["Wanted", "TabSymbols"]

Shown = tuple[Any, str]
"""What a part of the panel shows: the content (None: only the note) and a note."""

Notify = Callable[[str, str], None]
"""Shows the tab a notice (title, body)."""


class Wanted:
    """One kind of symbolic result a tab waits for (at most one key at a time).

    Args:
        part: The panel part that shows it ("matrix", "inverse" or "derive").
        ask: Asks the service for a key (returns a future).
        release: Tells the service the key is no longer wanted.
        dispatch: The session's way in (the result comes back as a message).
        notify: Tells the tab in a notice when the server stopped the computation at a limit, or did
            not start it (:func:`~app.tab.symbolic_words.told`).

    Attributes:
        shown: What the part shows now (None: nothing asked yet).
    """

    def __init__(
        self,
        part: str,
        ask: Callable[..., SymbolicFuture],
        release: Callable[..., None],
        dispatch: Callable[[Message], None],
        notify: Notify | None = None,
        language: Callable[[], Translator] = translations,
    ) -> None:
        self.part, self._ask, self._release, self._dispatch = part, ask, release, dispatch
        self._notify, self._language = notify, language
        self.key: tuple | None = None
        self.shown: Shown | None = None

    def want(self, key: tuple | None, waiting: str, result: Callable[[Future], Shown]) -> bool:
        """Wait for ``ask(*key)`` (nothing for ``None``): the note ``waiting`` until it is ready, then
        ``result(future)``. Returns whether what the part shows changed."""
        if key == self.key:
            return False
        self.drop()
        self.key = key
        if key is None:
            self.shown = None  # nothing wanted: the part keeps what its own draw shows
            return False
        future = self._ask(*key)
        joints = key[0].dof
        if future.done():
            self.shown = self._limited(future, joints) or result(future)
            return True
        self.shown = (None, waiting)

        def ready(f: Future) -> None:  # in the worker's callback thread: only a message (and a notice)
            content, note = self._limited(f, joints, wanted=self.key == key) or result(f)
            self._dispatch(SymbolicResult(self.part, key, content, note))

        future.add_done_callback(ready)
        return True

    def _limited(self, future: Future, joints: int, wanted: bool = True) -> Shown | None:
        """What the part shows when the server stopped the computation or did not start it (the tab is
        told in a notice too if it still ``wanted`` it; "not attempted" by the matrix's slot
        only); None otherwise."""
        if future.cancelled() or future.exception() is None:
            return None
        exc = future.exception()
        words = told(self.part, exc, joints, tr=self._language())  # type: ignore[arg-type]
        if words is None:
            return None
        once = self.part == "matrix" or not isinstance(exc, SymbolicNotAttempted)
        if wanted and once and self._notify is not None:
            self._notify(*words)
        return None, words[1]

    def take(self, message: SymbolicResult) -> bool:
        """Keep ``message`` if it is the result still wanted; returns whether it was."""
        if message.key != self.key:
            return False
        self.shown = (message.content, message.note)
        return True

    def drop(self) -> None:
        """No longer wait (the service drops work that nobody waits for)."""
        if self.key is not None:
            self._release(*self.key)
            self.key = None


class TabSymbols:
    """The symbolic results one tab shows, kept in step with its state.

    Args:
        service: The shared symbolic service.
        dispatch: The session's way in.
        notify: Shows the tab a notice (a computation stopped at a limit; once per tab, an arm too large
            to be attempted: a Build table grown row by row past the rule is told once, its panel at
            every row).
        language: The tab's language now (the notices and the panel's lines are in it).
    """

    def __init__(
        self,
        service: SymbolicService,
        dispatch: Callable[[Message], None],
        notify: Notify | None = None,
        language: Callable[[], Translator] = translations,
    ) -> None:
        self._told: set[str] = set()
        self._language = language
        if notify is not None:
            notify = self._once_not_attempted(notify)
        self.jacobian = Wanted("matrix", service.mathml, service.release, dispatch, notify, language)
        self.inverse = Wanted("inverse", service.inverse, service.release_inverse, dispatch, notify, language)
        self.steps = Wanted("derive", service.steps, service.release_steps, dispatch, notify, language)
        self._changed: set[str] = set()

    def _once_not_attempted(self, notify: Notify) -> Notify:
        def told(title: str, body: str) -> None:
            if title == self._language().gettext(TITLES["not attempted"]):
                if title in self._told:
                    return
                self._told.add(title)
            notify(title, body)

        return told

    def take(self, message: SymbolicResult) -> bool:
        """A result arrived (in the session's loop): keep it if still wanted; returns whether it was."""
        slot = next((w for w in self._slots() if w.part == message.part), None)
        if slot is None or not slot.take(message):
            return False
        self._changed.add(slot.part)
        return True

    def draw(self, panel: PanelView, everything: bool) -> None:
        """Put what changed since the last draw on ``panel`` (``everything``: a rebuilt panel)."""
        for slot in self._slots():
            if slot.shown is None or not (everything or slot.part in self._changed):
                continue
            view = getattr(panel, slot.part)
            if view is None:
                continue
            if slot.part == "derive":
                view.show_formulas(*slot.shown)
            else:
                view.show_symbolic(*slot.shown)
        self._changed.clear()

    def _slots(self) -> tuple[Wanted, Wanted, Wanted]:
        return self.jacobian, self.inverse, self.steps

    def update(self, state: LabState, before: LabState | None) -> None:
        """Ask for what ``state`` shows that ``before`` (``None``: a rebuilt tab) did not."""
        o = state.options
        if before is None or (o.jacobian_frame, o.course_letters, o.symbolic_inverse) != (
            before.options.jacobian_frame,
            before.options.course_letters,
            before.options.symbolic_inverse,
        ):
            self._jacobian_and_inverse(state)
        if before is None or (o.derive, o.course_letters) != (
            before.options.derive,
            before.options.course_letters,
        ):
            self._steps(state)

    def _jacobian_and_inverse(self, state: LabState) -> None:
        robot, frame = state.robot, state.options.jacobian_frame
        letters = state.options.course_letters and robot.dh is not None
        # J⁻¹ in the course's letters whenever the robot file names them ([symbols]: the TRR's l1, l2, l3).
        inverse_letters = letters or bool(robot.param_names and robot.dh is not None)
        if self.inverse.want(
            (robot, inverse_letters) if state.options.symbolic_inverse else None,
            "computing J⁻¹ = adj J / det J …",
            _inverse_ready,
        ):
            self._changed.add("inverse")
        if self.jacobian.want(
            (robot, frame, letters),
            "computing the symbolic form… (the numeric J above is live)",
            lambda f: _jacobian_ready(f, frame, letters),
        ):
            self._changed.add("matrix")

    def _steps(self, state: LabState) -> None:
        derive = state.options.derive
        letters = state.options.course_letters and state.robot.dh is not None
        if self.steps.want(
            (state.robot, "whitney" if derive == "dh" else derive, letters) if derive else None,
            N_(
                "working out the step in symbols… (the numbers above are live)"
            ),  # the Derive tab translates it
            _steps_ready,
        ):
            self._changed.add("derive")

    def release(self) -> None:
        """The tab has gone: wait for nothing."""
        for slot in self._slots():
            slot.drop()


def _jacobian_ready(future: Future, frame: str, letters: bool) -> Shown:
    try:
        notation = " with the DH parameters as letters" if letters else ""
        mathml = future.result()
        note = f"J(q) in {frame} axes{notation}, from kinematics.symbolic."
        if getattr(future, "restarted", False):
            note += f" ({WORKER_RESTARTED}: this result was computed again.)"
    except SymbolicUnavailable as exc:
        mathml, note = None, str(exc)
    except Exception as exc:
        mathml, note = None, f"symbolic form not available: {type(exc).__name__}: {exc}"
    return mathml, note


def _inverse_ready(future: Future) -> Shown:
    try:
        return future.result(), "J⁻¹ = adj J / det J, base axes, task rows."
    except Exception as exc:
        return None, f"symbolic J⁻¹ not available: {exc}"


def _steps_ready(future: Future) -> Shown:
    try:
        return future.result(), ""
    except Exception as exc:
        return None, f"the step in symbols is not available: {exc}"
