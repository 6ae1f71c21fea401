"""Helpers for the app tests: a running lab with a headless websocket client, and finiteness scans."""

from __future__ import annotations

import contextlib
import math
import re
from collections.abc import Iterator
from typing import Any

import numpy as np
from fakes import FakeSymbolicService, poll
from wsclient import ViserWsClient

from app.server import Lab
from app.tab.session import ClientSession
from app.viser_adapter import node_props, scene_handles

_BAD_TEXT = re.compile(r"\b(nan|inf|infinity)\b", re.IGNORECASE)


@contextlib.contextmanager
def running_lab(
    size: tuple[int, int] = (800, 600), **kwargs: Any
) -> Iterator[tuple[Lab, ClientSession, ViserWsClient]]:
    """A Lab on a free port with one connected websocket client (its canvas ``size`` [px]); always stopped.

    Its symbolic service is :class:`fakes.FakeSymbolicService` (immediate placeholders, no worker
    process) unless ``symbolic=`` is given: pass ``SymbolicService()`` to test the symbolic J itself.
    """
    kwargs.setdefault("symbolic", FakeSymbolicService())
    lab = Lab(port=0, **kwargs)
    try:
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}", *size) as ws:
            session = lab.session()
            yield lab, session, ws
    finally:
        lab.stop()


def nonfinite_paths(obj: Any, path: str = "") -> list[str]:
    """Paths inside ``obj`` (message dicts, props, arrays) holding NaN/∞ numbers or "nan"/"inf" text."""
    bad: list[str] = []
    if isinstance(obj, dict):
        for k, v in obj.items():
            bad += nonfinite_paths(v, f"{path}.{k}")
    elif isinstance(obj, (list, tuple)):
        for i, v in enumerate(obj):
            bad += nonfinite_paths(v, f"{path}[{i}]")
    elif isinstance(obj, np.ndarray):
        if obj.dtype.kind == "f" and not np.isfinite(obj).all():
            bad.append(path)
    elif isinstance(obj, float):
        if not math.isfinite(obj):
            bad.append(path)
    elif isinstance(obj, str):
        text = re.sub(r"<[^>]*>", " ", obj)  # only the visible text, not tag or attribute names
        if _BAD_TEXT.search(text):
            bad.append(f"{path}: {text[:80]!r}")
    return bad


def scene_props(session: ClientSession) -> dict[str, Any]:
    """Every prop of every scene node of the session's client, by node name."""
    return {name: node_props(h) for name, h in scene_handles(session.client.scene).items()}


def scene_node(session: ClientSession, name: str) -> Any:
    """The scene handle called ``name`` of the session's client."""
    return scene_handles(session.client.scene)[name]


def gui_contents(session: ClientSession) -> list[str]:
    """The HTML shown by the session's readouts (status, measures, matrix, bars, twist)."""
    p = session.panel
    assert p.matrix and p.forward and p.inverse and p.force
    handles = [
        p.status,
        p.matrix.measures,
        p.matrix.numeric,
        p.matrix.symbolic,
        p.forward.twist,
        p.inverse.rates,
        p.inverse.result,
        p.force.torques,
        p.inverse.inverse,
        p.inverse.course,
        p.inverse.symbolic,
        p.matrix.analytic,
        p.forward.accel,
    ]
    if p.motion is not None and p.maps is not None:
        handles += [p.motion.readout, p.motion.ik, p.motion.about, p.maps.map]
    if p.derive is not None:
        handles += [p.derive.table, p.derive.body]
    return [h.content for h in handles]


def chart_data(session: ClientSession) -> list[Any]:
    """The data of every chart of the session's Motion tab."""
    m = session.panel.motion
    if m is None:
        return []
    charts = [m.measures, m.kappa, m.rates] + ([m.self_chart] if m.self_chart is not None else [])
    return [c.data for c in charts]


def assert_all_finite(session: ClientSession) -> None:
    """No NaN or ∞ (number or text) in the session's scene props, readouts and charts."""
    bad = nonfinite_paths(scene_props(session)) + nonfinite_paths(gui_contents(session))
    bad += nonfinite_paths(chart_data(session))
    assert not bad, bad


wait_until = poll
"""The name of :func:`fakes.poll` before tests/fakes.py (for tests written before it)."""


def derive_walk(session: ClientSession, method: str, step: int) -> None:
    """Open the Derive tab's ``method`` at ``step`` (0-based) as the user picks them, and check it took."""
    from app.core.snapshot.derive import METHODS

    session.panel.derive.method.value = METHODS[method]
    session.settle()
    session.panel.derive.step.value = step + 1
    session.settle()
    assert session.state.options.derive == method and session.state.options.derive_step == step


def scene_update_to(name: str, want: np.ndarray):
    """A predicate of websocket messages: ``name``'s batched positions updated to ``want`` (to 1e-6)."""

    def got(m: dict[str, Any]) -> bool:
        positions = m.get("updates", {}).get("batched_positions")
        return (
            m["type"] == "SceneNodeUpdateMessage"
            and m["name"] == name
            and positions is not None
            and np.allclose(np.asarray(positions, dtype=np.float32).ravel(), want, atol=1e-6)
        )

    return got


def labels_placed(session: ClientSession, still: int = 2, interval: float = 0.05) -> None:
    """Wait until the tab's camera has stood still for ``still`` polls ``interval`` s apart and its labels
    were placed for it (:class:`app.views.scene.labels.ScreenLabels`: its ``layout`` is recorded last)."""
    from fakes import poll

    labels, last, count = session.scene.labels, [None], [0]

    def done() -> bool:
        cam = session.client.camera
        now = (*np.round(cam.position, 9), *np.round(cam.look_at, 9))
        count[0] = count[0] + 1 if now == last[0] else 0
        last[0] = now
        lay = labels.layout
        return (
            lay is not None
            and count[0] >= still
            and np.allclose(lay.view.position, cam.position, atol=1e-9)
            and np.allclose(lay.view.look_at, cam.look_at, atol=1e-9)
            and not session.pending
        )

    poll(done, what="the camera stopped and the labels placed for it", interval=interval)
