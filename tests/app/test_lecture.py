"""The demo the back row follows (issue 21, items 7–9), at server level: the pace of a preset near its
singularity (reduced on a fake clock), the first preset ready on a fresh tab, the motion's numbers at
the panel's top, the tool's path in the 3-D view, and the contrast of every text colour the page sets.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import robots
from app.core.actions import ApplyPreset, Play, Step
from app.core.commands import ChooseRobot
from app.core.pacing import RATE_GROWTH, rate_growth
from app.core.reducer import reduce
from app.core.state import LabState
from app.tab.ticker import Ticker
from app.views.palette import contrast, joint_text_hex
from app.views.panel.editor import _CSS as EDITOR_CSS
from app.views.panel.layout import LAYOUT_CSS, TEXT_COLOURS
from app.views.panel.live import live_html
from app.views.panel.motion import OWN_TWIST
from app.views.panel.style import BASE_CSS
from app.views.scene.path import MAX_POINTS, path_points
from kinematics import fk, jacobian
from kinematics.analysis import task_rows
from kinematics.motion.resolved_rate import resolved_rate


class FakeClock:
    """A clock the test advances: frames of 1/30 s, some late (a busy machine), as the ticker sees them."""

    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def play_on_a_fake_clock(name: str, seconds: float) -> tuple[list[LabState], list[float]]:
    """The robot's first preset played by a real :class:`Ticker` on a fake clock; the states after every
    step and the clock's Δt of each step."""
    p = robots.motions(name)[0]
    state = reduce(
        LabState.initial(name, robots.load(name)),
        ApplyPreset(p.name, tuple(p.q), tuple(p.twist), p.frame, p.speed),
    )
    states = [reduce(state, Play(True, "resolved_rate"))]
    dts: list[float] = []

    def dispatch(action: object) -> None:
        assert isinstance(action, Step)
        dts.append(action.dt)
        states.append(reduce(states[-1], action))

    clock = FakeClock()
    ticker = Ticker(dispatch, rate=30.0, clock=clock)
    rng = np.random.default_rng(3)
    while states[-1].playing and clock.now < seconds:
        clock.now += (1 / 30) * (1.0 if rng.random() < 0.8 else 2.5)
        ticker.tick()
    return states, dts


@pytest.mark.parametrize("name", ["puma560", "planar2"])
def test_the_joint_rates_grow_at_most_the_paced_rate_per_second_of_the_clock(name):
    states, dts = play_on_a_fake_clock(name, 120.0)
    end = states[-1]
    trace = end.motion.trace
    assert not end.playing and end.stopped.startswith("stopped:")
    # Sample k holds the rates of step k (taken at q_{k-1}); step k's Δt of the clock bounds their growth
    # to the rates of step k + 1.
    growth = [rate_growth(trace.qd[k], trace.qd[k + 1]) for k in range(1, len(trace) - 1)]
    bound = [RATE_GROWTH * dt for dt in dts[: len(growth)]]
    assert max(g - b for g, b in zip(growth, bound, strict=True)) <= 1e-9
    # It still runs into the blow-up: the rates at the stop are many times those at the start.
    norms = np.linalg.norm(trace.qd, axis=1)
    assert norms[-1] > 10 * norms[1]
    # The same law as unpaced: every step realises v with J(q_k) (the film is slowed, not the physics).
    rows = list(task_rows(end.robot))
    v = np.array(end.v_desired)[rows]
    for s, nxt in zip(states[:-2], states[1:-1], strict=True):
        qd = nxt.motion.trace.qd[-1]
        assert jacobian(end.robot, s.q)[rows] @ qd == pytest.approx(v, abs=1e-9)
    # Unpaced at real time the rates grow far faster than the bound, and it is over in a few seconds;
    # paced it lasts long enough to narrate.
    p = robots.motions(name)[0]
    raw = resolved_rate(
        end.robot, p.q, p.twist, dt=1 / 30, steps=900, rate_limit=4 * math.pi, rows=tuple(rows)
    )
    raw_growth = np.diff(np.log(np.linalg.norm(raw.qd, axis=1))) * 30
    assert raw_growth.max() > 5 * RATE_GROWTH
    assert sum(dts) > 2.5 * len(raw.qd) / 30 and sum(dts) > 8.0


def test_far_from_singularities_the_pace_is_the_speed_option():
    """The TRR example at speed 0.1: the first step is unslowed (q moves by q̇ Δt · 0.1)."""
    states, dts = play_on_a_fake_clock("trr", 0.05)
    first = states[1]
    assert first.motion.pace == pytest.approx(1.0)
    assert first.time == pytest.approx(dts[0] * 0.1)
    p = robots.motions("trr")[0]
    moved = np.array(first.q) - np.array(p.q)
    assert moved == pytest.approx(first.motion.trace.qd[-1] * dts[0] * 0.1, abs=1e-12)


def test_the_readout_shows_the_rates_kappa_and_the_slow_down_as_numbers():
    states, _ = play_on_a_fake_clock("puma560", 9.0)
    assert states[0].motion.trace is not None
    assert live_html(LabState.initial("puma560", robots.load("puma560"))) == ""  # nothing traced yet
    slowed = next(s for s in states if s.playing and s.motion.pace < 0.5)
    html = live_html(slowed)
    qd = slowed.motion.trace.qd[-1]
    for i in range(6):
        assert f"q̇{'₀₁₂₃₄₅₆'[i + 1]}" in html
        shown = f"{abs(math.degrees(qd[i])):.1f}"
        assert shown in html, (i, shown)
        assert joint_text_hex(i) in html
    shown_kappa = re.search(r"κ <b>([0-9.]+)</b>", html)
    assert shown_kappa is not None
    assert float(shown_kappa.group(1)) == pytest.approx(slowed.motion.trace.kappa[-1], rel=5e-3)
    assert "slowed ×" in html and "near the singularity" in html
    pace = re.search(r"slowed ×([0-9.]+)", html)
    assert pace is not None and float(pace.group(1)) == pytest.approx(slowed.motion.pace, rel=0.05)
    assert "nan" not in html.lower()


def test_the_tool_path_is_the_straight_line_of_the_preset():
    states, _ = play_on_a_fake_clock("puma560", 4.0)
    s = states[-1]
    trace = s.motion.trace
    assert trace.tool[-1] == pytest.approx(fk(s.robot, s.q)[:3, 3], abs=1e-12)
    p0, v = trace.tool[0], np.array(s.v_desired[:3])
    # On the line p0 + v t (to the Euler steps' first-order error), t the motion's own time.
    for t, p in zip(trace.t[:60], trace.tool[:60], strict=True):
        assert p == pytest.approx(p0 + v * t, abs=2e-3)
    points = path_points(np.vstack([trace.tool] * 10))
    assert len(points) <= MAX_POINTS + 1 and points[-1] == pytest.approx(trace.tool[-1])


def test_a_fresh_motion_tab_shows_the_first_preset_and_play_runs_it(session):
    for name in ("trr", "planar2", "puma560"):
        session.dispatch(ChooseRobot(name))
        session.settle()
        motion = session.panel.motion
        first = robots.motions(name)[0]
        assert motion.preset.value == first.name
        assert "Press <b>Play</b>" in motion.readout.content
        assert session.state.motion.preset == "" and not np.any(session.state.v_desired)
        motion.buttons.value = "Step"  # a click: the preset applied, then one step of it
        session.settle()
        state = session.state
        assert state.motion.preset == first.name and len(state.motion.trace) == 2
        assert np.array(state.v_desired) == pytest.approx(first.twist)
        assert session.panel.live.visible and "q̇₁" in session.panel.live.content
    # Choosing "your own v" keeps it (Play then asks for a v).
    session.panel.motion.preset.value = OWN_TWIST
    session.dispatch(ChooseRobot("planar3"))
    session.settle()
    assert session.panel.motion.preset.value == robots.motions("planar3")[0].name


def _hex(colour: str) -> tuple[int, int, int]:
    h = colour.lstrip("#")
    h = "".join(c * 2 for c in h) if len(h) == 3 else h
    return (int(h[0:2], 16), int(h[2:4], 16), int(h[4:6], 16))


_CONTAINERS = {".jl-live": "#f1f3f5", ".jl-close-x": "#f4f5f7"}
"""Backgrounds of our boxes whose text rules do not repeat them."""


@pytest.mark.parametrize("css", [BASE_CSS, LAYOUT_CSS, EDITOR_CSS], ids=["base", "layout", "editor"])
def test_every_text_colour_the_page_sets_reaches_4_5_to_1(css):
    rules = re.findall(r"([^{}]+)\{([^{}]*)\}", css.replace("{{", "{").replace("}}", "}"))
    checked = 0
    for selector, body in rules:
        text = re.search(r"(?<![-\w])color:\s*(#[0-9a-fA-F]{3,6})\b", body)
        if text is None:
            continue
        own = re.search(r"background(?:-color)?:\s*(#[0-9a-fA-F]{3,6})\b", body)
        box = next((bg for prefix, bg in _CONTAINERS.items() if selector.strip().startswith(prefix)), None)
        background = own.group(1) if own else box or "#ffffff"
        ratio = contrast(_hex(text.group(1)), _hex(background))
        assert ratio >= 4.5, f"{selector.strip()}: {text.group(1)} on {background} is {ratio:.2f}:1"
        checked += 1
    assert checked >= 3


def test_the_named_colours_reach_4_5_to_1_and_the_old_ones_did_not():
    for what, (fg, bg) in TEXT_COLOURS.items():
        assert contrast(_hex(fg), _hex(bg)) >= 4.5, what
        assert fg in LAYOUT_CSS
    # What the issue measured: Mantine's field labels (#868e96 → 3.32:1) and the selected tab in the
    # brand colour (#3b5bdb on its light tint → 3.86:1 was measured on screen).
    assert contrast(_hex("#868e96"), (255, 255, 255)) < 4.5
