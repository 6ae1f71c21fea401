"""The app with the real symbolic service (worker processes): the symbolic J and a download.

Every other app test takes tests/fakes.py's immediate fake (see tests/conftest.py); these are the
ones that check what the symbolic worker sends.
"""

from __future__ import annotations

import pytest
from fakes import poll

from app.core.commands import ChooseRobot, RequestDownload


@pytest.mark.slow
def test_symbolic_form_of_a_small_robot(symbolic_session):
    session = symbolic_session
    session.panel.robot.value = "planar2"  # small: a quick symbolic form
    session.settle()
    poll(lambda: "computing" not in session.panel.matrix.symbolic.content)
    content = session.panel.matrix.symbolic.content
    # J of the 2R arm in the shorthand s₁₂ = sin(θ₁ + θ₂): its first entry −s₁ − s₁₂
    assert "<math" in content and "<msub><mi>s</mi><mn>12</mn></msub>" in content, content[:300]


@pytest.mark.slow
def test_download_sends_the_file(symbolic_lab_client, symbolic_session):
    _, _, ws = symbolic_lab_client
    session = symbolic_session
    session.dispatch(ChooseRobot("planar2"))
    session.settle()
    mark = ws.mark()
    errors = session.errors
    session.dispatch(RequestDownload("JSON"))
    _, msg = ws.wait_for(lambda m: m["type"] == "FileTransferStartDownload", after=mark)
    assert msg["filename"] == "planar2_J_base.json"
    _, part = ws.wait_for(lambda m: m["type"] == "FileTransferPart", after=mark)
    assert bytes(part["content"]).lstrip().startswith(b"{")
    assert session.errors == errors
