"""The lab takes its symbolic service; the app tests' fake keeps the real service's bookkeeping and
answers at once, in process, with what was asked (escaped), so an app test never waits for SymPy."""

from __future__ import annotations

from app_helpers import running_lab
from fakes import FakeSymbolicService, poll
from wsclient import ViserWsClient

from app.core.commands import ChooseRobot


def test_the_lab_uses_the_service_it_is_given_and_closes_it():
    fake = FakeSymbolicService()
    with running_lab(symbolic=fake) as (lab, session, _):
        assert lab.symbolic is fake
        content = session.panel.matrix.symbolic.content
        # Answered while the tab was built: never a "computing" note, the robot and frame named.
        assert "computing" not in content and f"fake J of {lab.default_robot} in base axes" in content
        assert ("_mathml", "puma560") in [(name, args[0].name) for name, args in fake.calls]
    assert fake._panel_worker._closed and fake._export_worker._closed


def test_two_tabs_share_one_request_and_a_robot_nobody_shows_is_released():
    fake = FakeSymbolicService()
    with running_lab(symbolic=fake) as (lab, first, _):
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}"):
            poll(lambda: len(lab.sessions) == 2)
            asked = [c for c in fake.calls if c[0] == "_mathml"]
            assert len(asked) == 1  # the second tab took the first one's answer
            first.dispatch(ChooseRobot("planar2"))
            first.settle()
            assert "fake J of planar2" in first.panel.matrix.symbolic.content
            keys = set(fake._mathml)
            assert any(k[0] == lab.catalog.load("planar2").fingerprint() for k in keys)
            assert any(k[0] == lab.catalog.load(lab.default_robot).fingerprint() for k in keys)
