"""``jacobian-lab record``: demos recorded as ``.viser`` files that play from a static web server.

The recording is read back with a small decoder of viser's file format (below): the tests check the
real values drawn (the tool where fk puts it, the readout, the camera), not only that bytes exist.
The Chromium test serves the folder with ``python -m http.server`` and watches the demo play; it is
marked like the app's browser tests (skipped locally without Chromium, failing under ``CI``).
"""

from __future__ import annotations

import html
import math
import os
import socket
import subprocess
import sys
import urllib.request
from pathlib import Path

import msgspec
import numpy as np
import pytest
import zstandard
from browser_helpers import ARGS, CHROMIUM, close_notifications, image, new_page, require_browser
from fakes import POLL_TIMEOUT, poll
from locations import ROOT

import robots
from app.cli.main import main
from app.core.actions import ApplyPreset, Play, Step
from app.core.reducer import reduce
from app.core.snapshot import compute
from app.core.state import LabState
from app.demo.rates import joint_rates, rates_csv, rates_readout
from app.demo.record import (
    CLIENT_PAGE,
    LEAD,
    RATES,
    RECORDING,
    plan,
    readout,
    record,
)
from app.views.fmt import number
from kinematics import jacobian
from kinematics.numeric import fk


# ------------------------------------------------------------------ reading a .viser file
def read_viser(data: bytes) -> dict:
    """The messages of a ``.viser`` file: ``{"duration": s, "messages": [(t, dict)], "buffers": [...]}``.

    viser 1.1's format: the inner size (8 bytes, little endian), then zstd of [msgpack length (8
    bytes), msgpack {durationSeconds, messages, binaryBufferLengths}, 8-byte aligned buffers].
    """
    inner = int.from_bytes(data[:8], "little")
    raw = zstandard.ZstdDecompressor().decompress(data[8:], max_output_size=inner)
    assert len(raw) == inner
    n = int.from_bytes(raw[:8], "little")
    doc = msgspec.msgpack.decode(raw[8 : 8 + n])
    buffers, offset = [], 8 + n
    for length in doc["binaryBufferLengths"]:
        offset += (8 - offset % 8) % 8
        buffers.append(raw[offset : offset + length])
        offset += length
    return {"duration": doc["durationSeconds"], "messages": doc["messages"], "buffers": buffers}


def _last(messages: list, name: str, key: str):
    """The last value of ``key`` sent for the node ``name`` (a prop update or a position)."""
    value = None
    for _, m in messages:
        if m.get("name") != name:
            continue
        if key in m:
            value = m[key]
        elif key in m.get("updates", {}):
            value = m["updates"][key]
        elif key in m.get("props", {}):
            value = m["props"][key]
    return value


def _camera(messages: list) -> dict:
    out = {}
    for t, m in messages:
        if m["type"] == "SetCameraPositionMessage":
            out["position"], out["t"] = np.array(m["position"]), t
        elif m["type"] == "SetCameraLookAtMessage":
            out["look_at"] = np.array(m["look_at"])
    return out


# ------------------------------------------------------------------ recordings
def test_a_preset_is_played_on_the_apps_reducer_until_it_stops():
    robot = robots.load("puma560")
    preset = robots.motions("puma560")[0]
    rec = record("puma560", robot, seconds=15.0, fps=30.0)

    # The same motion by hand: ApplyPreset → Play → Step(1/30) until it stops.
    state = LabState.initial("puma560", robot)
    state = reduce(
        state, ApplyPreset(preset.name, tuple(preset.q), tuple(preset.twist), preset.frame, preset.speed)
    )
    state = reduce(state, Play(True, "resolved_rate"))
    steps = 0
    while state.playing:
        state = reduce(state, Step(1 / 30))
        steps += 1
    # Paced near the wrist singularity (app.core.pacing): about 10 s of film instead of 3.
    assert 7 * 30 < steps < 15 * 30, "the puma's preset stops (q4 at its limit) after 7 s, before 15 s"
    assert rec.frames == steps + 1
    np.testing.assert_allclose(rec.states[-1].q, state.q, atol=1e-12)
    assert rec.states[-1].stopped == state.stopped and "q4" in state.stopped
    assert rec.title == f"{robot.title} — {preset.name}"

    f = read_viser(rec.data)
    assert f["duration"] == pytest.approx(LEAD + steps / 30)
    times = sorted({t for t, _ in f["messages"]})
    # The scene at t = 0 (as the last frame left it), then one batch of updates per frame from LEAD.
    assert times[0] == 0.0 and times[1] == pytest.approx(LEAD)
    assert len(times) == 1 + steps + 1
    np.testing.assert_allclose(np.diff(times[1:]), 1 / 30, atol=1e-9)
    # Frame 0 at LEAD brings the arm back to the preset's start, so every loop of the player starts there.
    first = [m for t, m in f["messages"] if t == times[1]]
    ellipsoid = [
        m for m in first if m.get("name") == "/demo/lab/jacobian/velocity_ellipsoid" and "position" in m
    ]
    np.testing.assert_allclose(ellipsoid[-1]["position"], fk(robot, preset.q)[:3, 3], atol=1e-5)

    # The arm drawn at the last frame: the ellipsoid sits on the tool where fk puts it (near the wrist
    # singularity the one drawn is the wrist block's, at the wrist centre: the Puma's tool point).
    tool = fk(robot, state.q)[:3, 3]
    name = "/demo/lab/jacobian/velocity_ellipsoid"
    if _last(f["messages"], name, "visible") is False:
        name = "/demo/lab/jacobian/wrist_ellipsoid"
        assert _last(f["messages"], name, "visible") is True
    drawn = _last(f["messages"], name, "position")
    np.testing.assert_allclose(drawn, tool, atol=1e-5)
    start_tool = fk(robot, preset.q)[:3, 3]
    assert np.linalg.norm(tool - start_tool) > 0.05, "the tool moved along the preset's line"

    # The readout says the last frame's status and κ, and why it stopped.
    snap = compute(state)
    text, rates = _last(f["messages"], "/demo/readout", "text").split("\n")
    assert text == readout(snap, state)
    assert text.startswith(f"{snap.report.text()}   κ = {number(snap.report.condition)}")
    assert snap.report.status == "near singular" and "wrist" in text and "q4" in text
    assert _last(f["messages"], "/demo/title", "text") == rec.title
    # Its second line: the joint rates of the last frame, J⁺ v of the preset's twist at the q it came from.
    assert rates == rates_readout(state)
    qd = joint_rates(state)
    np.testing.assert_allclose(qd, state.motion.trace.qd[-1])
    for j, x in zip(robot.joints, qd, strict=True):
        assert f"{j.name.split()[0]} {number(np.degrees(x), 3)} °/s" in rates

    # The initial camera (recorded) frames the motion: it looks at the arm from a few sizes away.
    cam = _camera(f["messages"])
    assert cam["t"] == 0.0  # before frame 0
    assert np.isfinite(cam["position"]).all() and np.isfinite(cam["look_at"]).all()
    distance = np.linalg.norm(cam["position"] - cam["look_at"])
    assert 0.5 < distance < 5.0
    assert np.linalg.norm(cam["look_at"] - (tool + start_tool) / 2) < 0.6


def test_the_recording_keeps_the_joint_rates_of_every_frame_with_their_units():
    """The TRR's preset (a prismatic joint and two revolute ones): joint_rates.csv holds each frame's
    q and q̇, in m, m/s, deg and deg/s, and q̇ is J⁺ v (J q̇ gives back the preset's twist)."""
    robot = robots.load("trr")
    rec = record("trr", robot, seconds=1.0, fps=10.0)
    lines = rates_csv(rec.states, rec.fps).splitlines()
    heads = lines[0].split(",")
    names = [j.name for j in robot.joints]
    assert heads[:2] == ["frame", "t [s]"]
    assert heads[2:5] == [f"{names[0]} [m]", f"{names[1]} [deg]", f"{names[2]} [deg]"]
    assert heads[5:] == [f"{names[0]} rate [m/s]", f"{names[1]} rate [deg/s]", f"{names[2]} rate [deg/s]"]
    assert len(lines) == 1 + rec.frames
    v = np.array(rec.states[0].v_desired)
    rows = [0, 1, 2]
    moving = 0
    for line, state in zip(lines[1:], rec.states, strict=True):
        cells = line.split(",")
        q = np.array([float(cells[2]), *np.radians([float(c) for c in cells[3:5]])])
        np.testing.assert_allclose(q, state.q, atol=1e-7)
        if cells[5] and state.time > 0:
            qd = np.array([float(cells[5]), *np.radians([float(c) for c in cells[6:8]])])
            # J q̇ = v at the q the step started from (the previous frame's): the rates are J⁺ v.
            before = rec.states[rec.states.index(state) - 1]
            np.testing.assert_allclose(jacobian(robot, before.q)[rows] @ qd, v[rows], atol=1e-6)
            moving += 1
    assert moving >= 5


def test_without_presets_the_arm_goes_smoothly_from_home_to_its_first_singular_configuration():
    robot = robots.load("ur5")
    first = next(c for c in robot.configurations if c.singular)
    rec = record("ur5", robot, seconds=1.0, fps=10.0)
    assert rec.frames == 11  # the path takes the whole recording
    np.testing.assert_allclose(rec.states[0].q, robot.home, atol=1e-12)
    np.testing.assert_allclose(rec.states[-1].q, first.q, atol=1e-12)
    steps = np.linalg.norm(np.diff([s.q for s in rec.states], axis=0), axis=1)
    assert steps[0] < steps[5] and steps[-1] < steps[5], "eased: slow start, slow arrival"
    f = read_viser(rec.data)
    assert f["duration"] == pytest.approx(LEAD + 1.0)
    drawn = _last(f["messages"], "/demo/lab/jacobian/velocity_ellipsoid", "position")
    np.testing.assert_allclose(drawn, fk(robot, first.q)[:3, 3], atol=1e-5)
    text = _last(f["messages"], "/demo/readout", "text")
    assert text.startswith("singular") and "κ = ∞" in text
    assert first.name in rec.title


def test_a_robot_without_presets_or_singular_configurations_goes_to_the_nearest_singularity(tmp_path):
    source = (robots.DATA_DIR / "planar2.toml").read_text()
    head = source[: source.index("[[configurations]]")]
    path = tmp_path / "planar2.toml"
    path.write_text(head + '[[configurations]]\nname = "home"\nq = [30, 60]\nsingular = ""\n')
    robot = robots.load(path)
    assert robots.motions(path) == () and not any(c.singular for c in robot.configurations)
    demo = plan(str(path), robot, frames=6)
    assert demo.kind == "nearest"
    rec = record(str(path), robot, seconds=0.5, fps=10.0)
    assert rec.frames == 6
    end = rec.states[-1]
    assert compute(end).report.status == "singular"
    assert abs(math.sin(end.q[1])) < 1e-3, "the 2R arm is singular at q2 = 0 or 180°"


def test_a_preset_is_chosen_by_name_and_an_unknown_one_is_refused():
    robot = robots.load("puma560")
    name = robots.motions("puma560")[0].name
    assert plan("puma560", robot, preset=name).start.motion.preset == name
    with pytest.raises(ValueError, match="no preset 'sideways'.*straight line into the wrist"):
        plan("puma560", robot, preset="sideways")


# ------------------------------------------------------------------ the command line
def test_record_writes_a_folder_that_plays_the_recording(tmp_path, capsys):
    out = tmp_path / "demo"
    assert main(["record", "planar2", "-o", str(out), "--seconds", "0.5", "--fps", "10"]) == 0
    assert sorted(p.name for p in out.iterdir()) == sorted(["index.html", CLIENT_PAGE, RECORDING, RATES])
    index = (out / "index.html").read_text()
    assert f"{CLIENT_PAGE}?playbackPath={RECORDING}" in index
    client = (out / CLIENT_PAGE).read_text()
    title = f"{robots.load('planar2').title} — {robots.motions('planar2')[0].name}"
    assert f"<title>{html.escape(title)}</title>" in client  # the tab says what the demo is
    f = read_viser((out / RECORDING).read_bytes())
    assert LEAD < f["duration"] <= LEAD + 0.5 + 1e-9
    assert "python -m http.server" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["puma56"], "unknown robot 'puma56'"),
        (["puma560", "--preset", "sideways"], "no preset 'sideways'; its presets: 'straight line"),
        (["ur5", "--preset", "x"], "its presets: none"),
        (["puma560", "--seconds", "0"], "--seconds: expected a number more than 0 up to 600 s, got 0"),
        (["puma560", "--seconds", "-2"], "--seconds: expected a number more than 0"),
        (["puma560", "--fps", "nan"], "--fps: expected a number more than 0 up to 120, got nan"),
        (["puma560", "--fps", "abc"], "--fps: expected a number more than 0 up to 120, got 'abc'"),
        (["puma560", "--seconds", "0.01", "--fps", "10"], "is not one frame"),
    ],
)
def test_record_mistakes_are_one_line_and_status_2(tmp_path, capsys, args, message):
    out = tmp_path / "demo"
    assert main(["record", *args, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert message in err
    assert not out.exists(), "nothing is written when the command is refused"


def test_record_into_a_folder_that_cannot_be_written_fails_clearly(tmp_path, capsys):
    blocker = tmp_path / "notes.txt"
    blocker.write_text("a file")
    assert main(["record", "planar2", "-o", str(blocker)]) == 2
    assert f"cannot write into {blocker}: it is a file" in capsys.readouterr().err
    assert main(["record", "planar2", "-o", str(blocker / "demo")]) == 2
    assert f"cannot create {blocker / 'demo'}: Not a directory" in capsys.readouterr().err
    assert blocker.read_text() == "a file"


# ------------------------------------------------------------------ in a real browser
def _free_port(lo: int = 8600, hi: int = 8699) -> int:
    for port in range(lo, hi + 1):
        with socket.socket() as s:
            try:
                s.bind(("127.0.0.1", port))
            except OSError:
                continue
            return port
    raise AssertionError(f"no free port in {lo}..{hi}")


def _answers(url: str) -> bool:
    try:
        with urllib.request.urlopen(url, timeout=1) as response:
            return response.status == 200
    except OSError:
        return False


@pytest.mark.slow
@pytest.mark.browser
def test_the_recorded_demo_plays_from_a_static_server_in_chromium(tmp_path):
    sync_playwright = require_browser()
    shots = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    shots.mkdir(parents=True, exist_ok=True)
    out = tmp_path / "demo"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run(
        [sys.executable, "-m", "app.cli.main", "record", "puma560", "-o", str(out)],
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    port = _free_port()
    server = subprocess.Popen(
        [sys.executable, "-m", "http.server", str(port), "--bind", "127.0.0.1", "-d", str(out)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    errors: list[str] = []
    try:
        poll(lambda: _answers(f"http://127.0.0.1:{port}/index.html"), what="http.server answering")
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=ARGS)
            try:
                page = new_page(browser)
                page.on("pageerror", lambda exc: errors.append(str(exc)))
                page.goto(f"http://127.0.0.1:{port}/")
                poll(lambda: CLIENT_PAGE in page.url, what="index.html sending the browser to the player")
                assert page.url.endswith(f"?playbackPath={RECORDING}")
                page.wait_for_selector("canvas")
                assert page.title().startswith(robots.load("puma560").title)
                close_notifications(page)
                canvas = page.locator("canvas").first

                def drawn():  # the recording loaded and drawn: the arm, its glyphs, the labels
                    shot = image(canvas.screenshot())
                    return shot if (np.abs(shot - shot[5, 5]).max(axis=-1) > 60).mean() > 0.01 else None

                first = poll(drawn, what="the scene drawn on the canvas")

                def moved() -> bool:
                    now = image(canvas.screenshot())
                    return bool((np.abs(now - first).max(axis=-1) > 40).mean() > 0.002)

                poll(moved, what="the arm moving while the demo plays")
                page.screenshot(path=str(shots / "record_demo_puma560.png"))
            finally:
                browser.close()
    finally:
        server.terminate()
        server.wait(POLL_TIMEOUT)
    assert not errors, errors
