"""Recording what a tab does from the GUI ("Record a demo" in the View tab) and getting it back as a
demo folder (zip) that plays without a server: the frames, their resampling and the file's content."""

from __future__ import annotations

import io
import zipfile

import numpy as np
from fakes import FakeClock, poll
from test_record import _last, read_viser

import robots
from app.core.actions import SetJoint
from app.core.commands import ToggleRecording
from app.core.snapshot import compute
from app.core.state import LabState
from app.tab.recorder import FPS, TabRecorder
from kinematics import fk


def test_frames_are_resampled_at_a_steady_rate_keeping_the_last_robot():
    puma, panda = robots.load("puma560"), robots.load("panda")
    subscribers = []
    clock = FakeClock(50.0)
    recorder = TabRecorder(lambda fn: subscribers.append(fn) or (lambda: subscribers.remove(fn)), clock)
    first = LabState.initial("puma560", puma)
    recorder.start(first, compute(first))
    assert recorder.recording and len(subscribers) == 1
    states = [LabState.initial("panda", panda)]
    states.append(states[0].replace(q=np.array(states[0].q) + 0.1))
    clock.now += 0.5
    subscribers[0](states[0], compute(states[0]))  # a robot switch: the Puma's frames are dropped
    clock.now += 0.2
    subscribers[0](states[1], compute(states[1]))
    clock.now += 0.3
    frames = recorder.stop()
    assert not recorder.recording and not subscribers
    # From t = 0.5 to 0.7 s at 30 frames per second: 7 ticks, the first 6 show the first Panda state
    # (the 7th tick falls a hair before 0.7 s in floating point: the last state is then added).
    assert len(frames) in (int(0.2 * FPS) + 1, int(0.2 * FPS) + 2)
    assert all(s is states[0] for s, _ in frames[:6]) and frames[-1][0] is states[1]
    assert all(s.robot is panda for s, _ in frames)


def test_record_from_the_gui_downloads_a_demo_that_replays_what_was_done(session, monkeypatch):
    sent = []
    monkeypatch.setattr(
        session.client, "send_file_download", lambda name, data, **kw: sent.append((name, data))
    )
    button = session.panel.record
    button.value = True  # "Record a demo"
    session.settle()
    assert session.recorder.recording and button.label == "Stop and download the demo"
    for k in range(1, 6):
        session.dispatch(SetJoint(1, 0.1 * k))
        session.settle()
    final = session.state
    button.value = True  # "Stop and download the demo"
    session.settle()
    assert button.label == "Record a demo"
    poll(lambda: sent)
    name, data = sent[0]
    assert name == "jacobian-lab-demo.zip"
    files = zipfile.ZipFile(io.BytesIO(data))
    names = sorted(files.namelist())
    assert names == [
        "jacobian-lab-demo/index.html",
        "jacobian-lab-demo/joint_rates.csv",
        "jacobian-lab-demo/recording.viser",
        "jacobian-lab-demo/viser-client.html",
    ]
    # Moved by hand (no motion drives the joints): q per frame, the rate cells empty.
    rows = files.read("jacobian-lab-demo/joint_rates.csv").decode().splitlines()
    last = rows[-1].split(",")
    dof = final.robot.dof
    np.testing.assert_allclose(np.radians([float(c) for c in last[2 : 2 + dof]]), final.q, atol=1e-7)
    assert last[2 + dof :] == [""] * dof
    recording = read_viser(files.read("jacobian-lab-demo/recording.viser"))
    # The last frame: the ellipsoid on the tool where fk of the last state puts it.
    drawn = _last(recording["messages"], "/demo/lab/jacobian/velocity_ellipsoid", "position")
    np.testing.assert_allclose(drawn, fk(final.robot, final.q)[:3, 3], atol=1e-5)
    assert "playbackPath=recording.viser" in files.read("jacobian-lab-demo/index.html").decode()


def test_stopping_at_once_records_nothing(session, monkeypatch):
    sent = []
    monkeypatch.setattr(session.client, "send_file_download", lambda *a, **kw: sent.append(a))
    session.dispatch(ToggleRecording())
    session.dispatch(ToggleRecording())
    session.settle()
    assert not session.recorder.recording and not sent
