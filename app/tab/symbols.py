"""What one tab waits for from the symbolic worker: J(q), J⁻¹ and the Derive tab's steps.

Each is a :class:`Wanted` slot: it asks the shared
:class:`~app.services.symbolic_service.SymbolicService` once per
key (robot, frame, notation …), releases the request it replaces (so work no tab waits for any more
is dropped), shows a note while the worker computes, and puts the result on the panel only if it is
still the one wanted when it arrives. :class:`TabSymbols` derives the three keys from the tab's state
(:meth:`TabSymbols.update`, after every commit) and releases everything when the tab closes.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from concurrent.futures import Future
from typing import Any

from ..core.state import LabState
from ..services.symbolic_service import WORKER_RESTARTED, SymbolicFuture, SymbolicService, SymbolicUnavailable
from ..views.panel import PanelView

__all__ = ["Wanted", "TabSymbols"]


class Wanted:
    """One kind of symbolic result a tab waits for (at most one key at a time)."""

    def __init__(
        self,
        lock: threading.RLock,
        closed: Callable[[], bool],
        ask: Callable[..., SymbolicFuture],
        release: Callable[..., None],
        report_error: Callable[[BaseException], None],
    ) -> None:
        self._lock, self._closed, self._ask, self._release = lock, closed, ask, release
        self._report_error = report_error
        self.key: tuple | None = None

    def want(self, key: tuple | None, waiting: Callable[[], None], show: Callable[[Future], None]) -> None:
        """Wait for ``ask(*key)`` (nothing for ``None``): ``waiting()`` now unless it is ready,
        ``show(future)`` under the tab's lock when it is done and still wanted."""
        if key == self.key:
            return
        self.drop()
        self.key = key
        if key is None:
            return
        future = self._ask(*key)
        if not future.done():
            waiting()

        def ready(f: Future) -> None:
            try:
                with self._lock:
                    if not self._closed() and self.key == key:
                        show(f)
            except Exception as exc:
                self._report_error(exc)

        future.add_done_callback(ready)

    def drop(self) -> None:
        """No longer wait (the service drops work that nobody waits for)."""
        if self.key is not None:
            self._release(*self.key)
            self.key = None


class TabSymbols:
    """The symbolic results one tab shows, kept in step with its state."""

    def __init__(
        self,
        service: SymbolicService,
        panel: Callable[[], PanelView],
        lock: threading.RLock,
        closed: Callable[[], bool],
        report_error: Callable[[BaseException], None],
    ) -> None:
        self._panel = panel

        def slot(ask: Callable[..., SymbolicFuture], release: Callable[..., None]) -> Wanted:
            return Wanted(lock, closed, ask, release, report_error)

        self.jacobian = slot(service.mathml, service.release)
        self.inverse = slot(service.inverse, service.release_inverse)
        self.steps = slot(service.steps, service.release_steps)

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
        self.inverse.want(
            (robot, inverse_letters) if state.options.symbolic_inverse else None,
            lambda: self._show("inverse", None, "computing J⁻¹ = adj J / det J …"),
            self._inverse_ready,
        )
        self.jacobian.want(
            (robot, frame, letters),
            lambda: self._show("matrix", None, "computing the symbolic form… (the numeric J above is live)"),
            lambda f: self._jacobian_ready(f, frame, letters),
        )

    def _steps(self, state: LabState) -> None:
        derive = state.options.derive
        letters = state.options.course_letters and state.robot.dh is not None
        self.steps.want(
            (state.robot, "whitney" if derive == "dh" else derive, letters) if derive else None,
            lambda: self._show(
                "derive", None, "working out the step in symbols… (the numbers above are live)"
            ),
            self._steps_ready,
        )

    def _show(self, part: str, content: Any, note: str) -> None:
        view = getattr(self._panel(), part)
        if view is None:
            return
        if part == "derive":
            view.show_formulas(content, note)
        else:
            view.show_symbolic(content, note)

    def _jacobian_ready(self, future: Future, frame: str, letters: bool) -> None:
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
        self._show("matrix", mathml, note)

    def _inverse_ready(self, future: Future) -> None:
        try:
            self._show("inverse", future.result(), "J⁻¹ = adj J / det J, base axes, task rows.")
        except Exception as exc:
            self._show("inverse", None, f"symbolic J⁻¹ not available: {exc}")

    def _steps_ready(self, future: Future) -> None:
        try:
            self._show("derive", future.result(), "")
        except Exception as exc:
            self._show("derive", None, f"the step in symbols is not available: {exc}")

    def release(self) -> None:
        """The tab has gone: wait for nothing."""
        for slot in (self.jacobian, self.inverse, self.steps):
            slot.drop()
