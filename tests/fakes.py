"""What the tests share instead of copies: a fake clock, the one polling wait, random configurations
and an immediate in-process stand-in for the symbolic worker.

- :class:`FakeClock`: a time source the test moves by hand (rate limits, tickers, recorders).
- :func:`poll`: wait for a condition, never for a fixed time. The timeout is only a safety net
  (generous, so a loaded machine is slower but never red); the wait ends as soon as the condition holds.
- :func:`random_q`, :func:`random_configurations`: configurations for property tests over random q.
- :class:`FakeSymbolicService`: :class:`app.services.symbolic_service.SymbolicService` whose worker
  answers at once, in this process, with a placeholder that names what was asked. The app tests
  take it (``running_lab``'s default) unless they test the symbolic J itself.
"""

from __future__ import annotations

import html
import time
from collections.abc import Callable
from typing import Any, TypeVar

import numpy as np

from app.services import symbolic_requests as _sr
from app.services import symbolic_service as _ss

__all__ = [
    "FakeClock",
    "poll",
    "POLL_TIMEOUT",
    "random_q",
    "random_configurations",
    "FakeSymbolicService",
    "FakeWorkerPool",
]

T = TypeVar("T")

POLL_TIMEOUT = 120.0
"""Default safety net of :func:`poll` [s]: far above any wait seen on a quiet machine (a few seconds),
so a machine busy with other jobs only makes a test slower, never red."""


class FakeClock:
    """A monotonic clock moved by hand: ``clock.now += dt``."""

    def __init__(self, now: float = 100.0) -> None:
        self.now = now

    def __call__(self) -> float:
        return self.now


def poll(
    predicate: Callable[[], T], timeout: float = POLL_TIMEOUT, what: str = "condition", interval: float = 0.02
) -> T:
    """Call ``predicate`` every ``interval`` seconds until it returns something true (or an array,
    e.g. a capture: ``None`` means not yet); return that.

    Raises AssertionError naming ``what`` after ``timeout`` seconds (a safety net, not a time limit
    under test: the condition is checked once more at the end, so a slow machine cannot lose a race).
    """
    end = time.monotonic() + timeout
    while True:
        value = predicate()
        if _holds(value):
            return value
        if time.monotonic() > end:
            value = predicate()
            if _holds(value):
                return value
            raise AssertionError(f"{what} not reached within {timeout:g} s")
        time.sleep(interval)


def _holds(value: object) -> bool:
    return isinstance(value, np.ndarray) or bool(value)


def random_q(robot, rng: np.random.Generator, size: int | None = None) -> np.ndarray:
    """Configurations sampled inside the joint limits, clipped to ±π (revolute) / ±1 m (prismatic)."""
    lim = robot.qlim.copy()
    for i, kind in enumerate(robot.joint_types):
        span = np.pi if kind == "revolute" else 1.0
        lim[0, i] = max(lim[0, i], -span)
        lim[1, i] = min(lim[1, i], span)
    shape = (robot.dof,) if size is None else (size, robot.dof)
    return rng.uniform(lim[0], lim[1], size=shape)


def random_configurations(robot, count: int = 4, seed: int = 1) -> np.ndarray:
    """``count`` configurations (rows) inside the joint limits (±π where a joint has none), seeded."""
    rng = np.random.default_rng(seed)
    lim = robot.qlim
    lo = np.where(np.isfinite(lim[0]), lim[0], -np.pi)
    hi = np.where(np.isfinite(lim[1]), lim[1], np.pi)
    return rng.uniform(lo, hi, size=(count, robot.dof))


# ---------------------------------------------------------------- the symbolic worker's stand-in
def _math(text: str) -> str:
    """A placeholder formula; ``text`` is escaped, as the real worker escapes robot names."""
    return f'<math display="block"><mtext>{html.escape(text)}</mtext></math>'


def _fake_mathml(robot, frame: str, timeout: float, letters: bool = False) -> str:
    return _math(f"fake J of {robot.name} in {frame} axes{' (letters)' if letters else ''}")


def _fake_inverse(robot, letters: bool, timeout: float) -> str:
    return _math(f"fake J⁻¹ of {robot.name}{' (letters)' if letters else ''}")


def _fake_steps(robot, method: str, timeout: float, letters: bool = False) -> tuple:
    from app.views.methods import METHODS

    def keys(name: str) -> tuple[str, ...]:
        return METHODS[name].symbols if name in METHODS else ()

    steps: list[tuple[int | None, str, str, str]] = []
    # The tab asks for "whitney" on its DH view too: the A and ⁰T steps come with every method.
    for prefixes in dict.fromkeys((keys(method), keys("dh"))):
        for joint in range(robot.dof):
            for prefix in prefixes:
                steps.append((joint, f"{prefix}{joint + 1}", f"fake step {prefix}{joint + 1}", _math(prefix)))
    steps += [(None, "J", "fake J", _math("J")), (None, "detJ", "fake det J", _math("det J"))]
    return tuple(steps)


def _fake_export(robot, fmt: str, frame: str, timeout: float, name: str) -> tuple[str, bytes]:
    body = {"json": '{"fake": true}', "python": "FAKE = True\n", "latex": "% fake\n"}[fmt]
    return name, body.encode("utf-8")


_ANSWERS: dict[Callable[..., Any], Callable[..., Any]] = {
    _sr._mathml: _fake_mathml,
    _sr._inverse_mathml: _fake_inverse,
    _sr._steps_mathml: _fake_steps,
    _sr._export: _fake_export,
}


class FakeWorkerPool(_ss.WorkerPool):
    """A worker pool whose "worker" answers at once in this process with a placeholder
    (no process, no SymbolicFuture left pending). ``calls`` lists (function name, args) asked."""

    def __init__(self, on_restart: Callable[[str], None] | None = None) -> None:
        super().__init__(on_restart)
        self.calls: list[tuple[str, tuple]] = []

    def submit(self, fn: Callable[..., Any], *args: Any) -> _ss.SymbolicFuture:
        if self._closed:
            raise RuntimeError("the symbolic worker pool was closed")
        self.calls.append((fn.__name__, args))
        future = _ss.SymbolicFuture()
        try:
            future.set_result(_ANSWERS[fn](*args))
        except Exception as exc:
            future.set_exception(exc)
        return future

    def pids(self) -> list[int]:
        return []

    def close(self) -> None:
        self._closed = True


def _fake_pools(on_restart: Callable[[str], None]) -> _ss.LocalPools:
    pools = _ss.LocalPools(on_restart)
    pools.panel, pools.downloads = FakeWorkerPool(on_restart), FakeWorkerPool(on_restart)
    return pools


class FakeSymbolicService(_ss.SymbolicService):
    """The real service's bookkeeping (one request per key, release, cancel) over
    :class:`FakeWorkerPool` workers: deterministic, immediate, in process."""

    def __init__(self, timeout: float = 60.0) -> None:
        super().__init__(timeout, pools=_fake_pools)
        self._panel_worker = self._pools.panel  # type: ignore[attr-defined]
        self._export_worker = self._pools.downloads  # type: ignore[attr-defined]

    @property
    def calls(self) -> list[tuple[str, tuple]]:
        """Every computation asked of the fake workers (panel first, then exports)."""
        return self._panel_worker.calls + self._export_worker.calls  # type: ignore[attr-defined]


class MemberStub:
    """A tab as the classroom sees it (no session; the :class:`~app.services.member.Member` calls): the
    role it was told last, and every note it was told."""

    latest = (None, None)
    scene_messages = ()

    def __init__(self) -> None:
        self.role = None
        self.notes: list[str] = []

    def subscribe(self, fn):
        return lambda: None

    def mirror(self, state, snapshot, scene=(), shared=None):
        pass

    def mirror_camera(self, *pose):
        pass

    def mirror_labels(self, placed):
        pass

    def mirror_tab(self, label):
        pass

    def role_changed(self, role):
        self.role = role
        if role.note:
            self.notes.append(role.note)
