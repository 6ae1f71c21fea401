"""The seams around the one-way flow: time (the ticker), the camera,
and the colours (contrast and distinctness), each tested without a browser."""

from __future__ import annotations

import math

import numpy as np
import pytest
from app_helpers import running_lab
from fakes import POLL_TIMEOUT, FakeClock, poll
from wsclient import ViserWsClient

import robots
from app.core.actions import Play, SetRate, Step
from app.core.reducer import reduce
from app.core.state import LabState
from app.tab.ticker import Ticker
from app.views.camera import THREE_QUARTER, View, facing, framing, in_view, needs_framing
from app.views.palette import (
    GLYPH_RGB,
    STATUS_RGB,
    STATUS_TEXT,
    contrast,
    delta_e,
    joint_color,
    joint_text_hex,
)


def test_ticker_dispatches_the_elapsed_time_as_steps():
    clock = FakeClock(100.0)
    got: list[float] = []
    ticker = Ticker(lambda action: got.append(action.dt), rate=30.0, clock=clock)
    ticker._last = clock()
    clock.now += 0.02
    assert ticker.tick() == pytest.approx(0.02)
    clock.now += 5.0  # a stall: one step is capped at four periods, the arm never jumps
    assert ticker.tick() == pytest.approx(4 / 30)
    assert got == pytest.approx([0.02, 4 / 30])


def test_playing_moves_the_joints_in_time_on_a_fake_clock():
    """The reducer integrates q̇ over the ticker's steps: q(t) = q0 + q̇ t, exactly."""
    puma = robots.load("puma560")
    state = reduce(reduce(LabState.initial("puma560", puma), SetRate(1, 0.2)), Play(True))
    clock = FakeClock(100.0)
    ticker = Ticker(lambda a: None, rate=30.0, clock=clock)
    ticker._last = clock()
    steps = []
    ticker.dispatch = steps.append
    for _ in range(45):
        clock.now += 1 / 30
        ticker.tick()
    for step in steps:
        state = reduce(state, step)
    assert all(isinstance(s, Step) for s in steps)
    assert state.time == pytest.approx(1.5)
    assert state.q[1] == pytest.approx(puma.home[1] + 0.2 * 1.5)


def test_a_tab_plays_on_its_own_ticker_and_stops_when_closed():
    with running_lab() as (lab, session, _):
        session.dispatch(SetRate(0, 0.5))
        session.dispatch(Play(True))
        session.settle()
        assert session.ticker.running
        q0 = session.state.q[0]
        poll(lambda: session.state.q[0] > q0 + 0.05)  # moving by itself
        assert session.panel.forward.play.label == "Pause"
        session.dispatch(Play(False))
        session.settle()
        assert not session.ticker.running
        session.dispatch(Play(True))
        session.settle()
        session.close()
        assert not session.ticker.running


def _view(aspect: float = 16 / 9) -> View:
    return View(np.array([3.0, -3.0, 2.0]), np.zeros(3), np.array([0.0, 0, 1]), math.radians(50), aspect)


def test_framing_fits_the_points_and_keeps_the_direction():
    rng = np.random.default_rng(3)
    points = rng.uniform(-1.0, 1.0, (50, 3)) + np.array([5.0, 2.0, 0.5])
    view = _view()
    assert needs_framing(view, points)  # they are off to the side
    position, look_at = framing(view, points)
    framed = View(position, look_at, view.up, view.fov, view.aspect)
    assert in_view(framed, points).all()
    assert not needs_framing(framed, points)
    old = view.position - view.look_at
    new = position - look_at
    assert np.dot(old, new) / np.linalg.norm(old) / np.linalg.norm(new) == pytest.approx(1.0)


def test_a_narrow_canvas_needs_reframing():
    points = np.array([[x, 0.0, 0.0] for x in np.linspace(-1.2, 1.2, 9)])
    wide = _view(2.0)
    position, look_at = framing(wide, points)
    narrow = View(position, look_at, wide.up, wide.fov, 0.6)  # a panel took most of the width
    assert not needs_framing(View(position, look_at, wide.up, wide.fov, 2.0), points)
    assert needs_framing(narrow, points)


def test_facing_looks_across_the_plane_of_the_points():
    """Points in the x-y plane are seen from above (arrows side-on), never edge-on."""
    rng = np.random.default_rng(4)
    flat = np.column_stack([rng.uniform(-5, 5, 40), rng.uniform(-5, 5, 40), np.zeros(40)])
    d = facing(flat)
    assert d[2] > 0.7
    vertical = np.column_stack([rng.uniform(-1, 1, 40), np.zeros(40), rng.uniform(0, 2, 40)])
    d = facing(vertical)
    assert abs(d[1]) > 0.6 and d[2] >= math.sin(math.radians(20)) - 1e-9
    assert np.linalg.norm(facing(np.zeros((1, 3))) - THREE_QUARTER / np.linalg.norm(THREE_QUARTER)) < 1e-12


def test_text_colours_are_legible_and_glyph_colours_distinct():
    white = (255, 255, 255)
    for i in range(9):
        text = joint_text_hex(i)
        rgb = tuple(int(text[k : k + 2], 16) for k in (1, 3, 5))
        assert contrast(rgb, white) >= 4.5, (i, text)
    for status, rgb in STATUS_RGB.items():
        text = STATUS_TEXT[status]
        fg = tuple(int(text[k : k + 2], 16) for k in (1, 3, 5))
        assert contrast(fg, rgb) >= 4.5, status
    for name, rgb in GLYPH_RGB.items():
        nearest = min(delta_e(rgb, joint_color(i)) for i in range(9))
        assert nearest >= 25, (name, nearest)


def test_contrast_and_delta_e_match_known_values():
    assert contrast((0, 0, 0), (255, 255, 255)) == pytest.approx(21.0)
    assert contrast((118, 118, 118), (255, 255, 255)) == pytest.approx(4.54, abs=0.01)
    assert delta_e((255, 0, 0), (255, 0, 0)) == 0.0
    assert delta_e((0, 0, 0), (255, 255, 255)) == pytest.approx(100.0, abs=0.1)


def test_a_tab_closed_while_its_session_is_built_is_forgotten(monkeypatch):
    """Closing a tab before its session is ready must not leave the session in the server's table."""
    import threading

    import app.server as server_module
    from app.server import Lab
    from app.tab.session import ClientSession

    building, release = threading.Event(), threading.Event()
    built: list[ClientSession] = []

    class SlowSession(ClientSession):
        def __init__(self, *args, **kwargs):
            building.set()
            assert release.wait(POLL_TIMEOUT)
            super().__init__(*args, **kwargs)
            built.append(self)

    monkeypatch.setattr(server_module, "ClientSession", SlowSession)
    lab = Lab(port=0)
    try:
        ws = ViserWsClient(f"ws://127.0.0.1:{lab.port}")
        ws.__enter__()
        poll(building.is_set)
        ws.__exit__(None, None, None)  # the tab closes while its session is being built
        poll(lambda: lab.server.get_clients() == {})
        release.set()
        poll(lambda: len(built) == 1)
        poll(lambda: built[0].closed)
        assert lab.sessions == {}
    finally:
        release.set()
        lab.stop()
