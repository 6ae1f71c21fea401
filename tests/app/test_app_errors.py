"""Bad input from a page and failures in a redraw: shown to that tab only, never NaN on the page."""

from __future__ import annotations

import math

import numpy as np
import pytest
from app_helpers import assert_all_finite, nonfinite_paths
from fakes import poll
from wsclient import ViserWsClient

from app.core.actions import GoTo
from app.viser_adapter import handle_uuid


def test_an_error_is_shown_to_that_client_only(lab_client, session, monkeypatch):
    lab, _, ws = lab_client
    import app.tab.session as session_module

    def broken(state):
        raise RuntimeError("deliberate failure")

    monkeypatch.setattr(session_module, "compute", broken)
    mark = ws.mark()
    errors = session.errors
    session.panel.joints.sliders[0].value = 12.0
    session.settle()
    assert session.errors == errors + 1
    _, msg = ws.wait_for(lambda m: m["type"] == "NotificationShowMessage", after=mark)
    assert "deliberate failure" in msg["props"]["body"]
    monkeypatch.undo()
    session.panel.joints.sliders[0].value = 13.0  # the session carries on
    session.settle()
    assert session.errors == errors + 1
    assert session.state.q[0] == pytest.approx(math.radians(13.0))
    with ViserWsClient(f"ws://127.0.0.1:{lab.port}") as other:
        poll(lambda: len(lab.sessions) == 2)
        second = lab.session()
        assert second is not session and second.errors == 0
        second.panel.joints.sliders[0].value = -40.0
        second.settle()
        assert session.state.q[0] == pytest.approx(math.radians(13.0))
        assert second.state.q[0] == pytest.approx(math.radians(-40.0))
        assert other.wait_for(lambda m: m["type"] == "SceneNodeUpdateMessage")
    poll(lambda: len(lab.sessions) == 1)


def test_a_nonfinite_value_from_the_page_is_refused(lab_client, session):
    """Refused where it enters (app/viser_adapter/gate.py): the tab is told in words, which never
    echo "nan", and nothing else changes."""
    _, _, ws = lab_client
    q = session.state.q.copy()
    errors = session.errors
    mark = ws.mark()
    ws.set_value(handle_uuid(session.panel.joints.sliders[2]), math.nan)
    _, notice = ws.wait_for(lambda m: m["type"] == "NotificationShowMessage", after=mark)
    assert (
        "not a finite number" in notice["props"]["body"] and "Nothing was changed" in notice["props"]["body"]
    )
    assert not nonfinite_paths(notice)
    np.testing.assert_array_equal(session.state.q, q)
    session.panel.joints.sliders[0].value = 5.0  # the next event redraws as usual
    session.settle()
    assert session.errors == errors and session.state.q[0] == pytest.approx(math.radians(5.0))
    assert_all_finite(session)


def test_no_nonfinite_value_reached_the_client(lab_client):
    _, session, ws = lab_client
    session.settle()
    mark = ws.mark()
    session.dispatch(GoTo("wrist_singular"))
    ws.wait_for(lambda m: m["type"] == "SceneNodeUpdateMessage", after=mark)
    messages = [m for _, m in ws.messages]
    assert len(messages) > 100
    bad = nonfinite_paths(messages)
    assert not bad, bad[:10]
