"""URDF uploads (Build tab): private to the tab that uploaded them, size-capped, read from their bytes
only (no mesh is ever looked for), hostile files refused in words with the tab and the others intact."""

from __future__ import annotations

import math
import time
import uuid

import numpy as np
import pytest
from app_helpers import assert_all_finite, gui_contents, scene_props
from fakes import poll
from locations import DATA
from wsclient import ViserWsClient

import kinematics.urdf.mesh
from app.tab.robots import MAX_UPLOAD_BYTES, TabCatalog
from app.viser_adapter import UPLOAD_PART_BYTES, handle_uuid, message_class
from kinematics import robot_from_urdf
from kinematics.numeric import jacobian

ARM = """<?xml version="1.0"?>
<robot name="NAME">
  <link name="base"/><link name="upper">MESH</link><link name="fore"/><link name="tool"/>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="flange" type="fixed"><parent link="fore"/><child link="tool"/><origin xyz="0.2 0 0"/></joint>
</robot>
"""
LAUGHS = (
    '<?xml version="1.0"?>\n<!DOCTYPE robot [<!ENTITY lol "lol">'
    + "".join(f'<!ENTITY lol{i} "{f"&lol{i - 1};" * 10 if i > 1 else "&lol;" * 10}">' for i in range(1, 10))
    + ']>\n<robot name="&lol9;"><link name="a"/></robot>\n'
)


def _arm(name: str = "two_link", mesh: str = "") -> bytes:
    return ARM.replace("NAME", name).replace("MESH", mesh).encode()


def _notes(session, monkeypatch) -> list[tuple[str, str, dict]]:
    seen: list[tuple[str, str, dict]] = []
    real = session.client.add_notification

    def record(title, body="", **kwargs):
        seen.append((str(title), str(body), kwargs))
        return real(title, body, **kwargs)

    monkeypatch.setattr(session.client, "add_notification", record)
    return seen


def _upload(session, name: str, content: bytes) -> None:
    """Upload as the browser does: a start message, then parts of 512 KiB, over the tab's websocket."""
    ws = _SOCKETS[session.client.client_id]
    button, transfer = handle_uuid(session.panel.editor.upload), uuid.uuid4().hex
    parts = [content[i : i + UPLOAD_PART_BYTES] for i in range(0, len(content), UPLOAD_PART_BYTES)]
    before, errors = session.state, session.errors
    start = message_class("FileTransferStartUpload")
    ws.send(start(button, transfer, name, "application/xml", len(parts), len(content)))
    for i, part in enumerate(parts):
        ws.send(message_class("FileTransferPart")(button, transfer, i, part))
    poll(lambda: session.errors > errors or session.state is not before or session.pending)
    session.settle()
    poll(lambda: not session.commands.building)  # built away from the drawing thread
    session.settle()


_SOCKETS: dict[int, ViserWsClient] = {}


@pytest.fixture(autouse=True)
def _socket_of_the_tab(lab_client):
    lab, first, ws = lab_client
    _SOCKETS[first.client.client_id] = ws


@pytest.fixture
def other_tab(lab_client):
    """A second tab on the same server."""
    lab, first, _ = lab_client
    with ViserWsClient(f"ws://127.0.0.1:{lab.port}"):
        poll(lambda: len(lab.sessions) == 2)
        second = next(s for s in lab.sessions.values() if s is not first)
        second.settle()
        yield second


def test_a_small_urdf_loads_draws_and_stays_with_its_tab(session, other_tab, monkeypatch):
    notes, errors0 = _notes(session, monkeypatch), session.errors
    content = (DATA / "urdf" / "gripper_arm.urdf").read_bytes()
    _upload(session, "gripper_arm.urdf", content)
    state = session.state
    expected = robot_from_urdf(str(DATA / "urdf" / "gripper_arm.urdf"))
    assert state.robot_name.startswith(expected.name) and state.robot_name.endswith(" (uploaded)")
    assert state.robot.urdf_path is None
    for q in np.random.default_rng(3).uniform(-1, 1, size=(5, expected.dof)):
        np.testing.assert_allclose(jacobian(state.robot, q), jacobian(expected, q), atol=1e-12)
    session.panel.joints.sliders[0].value = 20.0
    session.settle()
    assert session.state.q[0] == pytest.approx(math.radians(20.0))
    assert session.panel.robot.options[0] == state.robot_name  # this tab lists it first…
    assert state.robot_name not in other_tab.panel.robot.options  # …no other tab does
    assert state.robot_name not in session.catalog.shared.names()
    assert other_tab.state.robot_name == "puma560" and other_tab.errors == 0
    assert session.errors == errors0 and not [n for n in notes if n[2].get("color") == "red"]
    assert_all_finite(session)
    # Going to a library robot and back through the dropdown.
    session.panel.robot.value = "planar2"
    session.settle()
    session.panel.robot.value = state.robot_name
    session.settle()
    assert session.state.robot is state.robot


def test_a_tab_robot_can_be_shared_with_every_tab(session, tmp_path):
    """The presenter's seam: TabCatalog.share lists a tab's robot in the shared catalogue."""
    tab = TabCatalog(session.catalog.shared)
    name = tab.add_upload("arm.urdf", _arm("shared_arm"))
    assert name not in TabCatalog(session.catalog.shared).names()
    shared = tab.share(name, tmp_path)
    assert shared in TabCatalog(session.catalog.shared).names()
    q = np.array([0.3, -0.4])
    np.testing.assert_allclose(
        jacobian(session.catalog.shared.load(shared), q), jacobian(tab.load(name), q), atol=1e-12
    )


@pytest.mark.parametrize(
    ("filename", "content", "said"),
    [
        ("notes.urdf", b"hello, I am not XML", "cannot parse URDF: line 1, column 1"),
        ("big.urdf", b" " * (50 * 1024 * 1024), "'big.urdf' is 52.4 MB; a URDF upload may be at most 2 MB"),
        ("latin1.urdf", _arm("caf\xe9").replace(b"caf\xc3\xa9", b"caf\xe9"), "not UTF-8"),
        ("arm\ufffd\x00\u202e.urdf", b"<robot", "upload 'arm\ufffd\ufffd\ufffd.urdf'"),
        ("laughs.urdf", LAUGHS.encode(), "must not contain a DOCTYPE or ENTITY declarations"),
        ("empty.urdf", b"", "upload 'empty.urdf': cannot parse URDF: line 1, column 1: Document is empty"),
    ],
    ids=["not-xml", "50MB", "not-utf8", "bad-filename", "billion-laughs", "empty"],
)
def test_a_hostile_upload_is_refused_in_words_and_every_tab_carries_on(
    session, other_tab, monkeypatch, filename, content, said
):
    notes = _notes(session, monkeypatch)
    before, other_before, errors0 = session.state, other_tab.state, session.errors
    options = session.panel.robot.options
    start = time.process_time()  # the server's threads' work (not the wall clock a busy machine stretches)
    _upload(session, filename, content)
    assert time.process_time() - start < 10.0
    errors = [n for n in notes if n[2].get("color") == "red"]
    assert len(errors) == 1 and said in errors[0][1], notes
    assert "\x00" not in errors[0][1] and "\u202e" not in errors[0][1]
    assert session.state is before and session.errors == errors0 + 1
    assert session.panel.robot.options == options
    session.panel.joints.sliders[1].value = 30.0  # the tab still works
    session.settle()
    assert session.state.q[1] == pytest.approx(math.radians(30.0))
    assert other_tab.state is other_before and other_tab.errors == 0
    assert_all_finite(session)


def test_a_name_that_is_not_utf8_is_shown_printable():
    """A name with lone surrogates (undecodable bytes) or control characters, straight to the catalogue."""
    from app.services.catalog import RobotCatalog
    from kinematics.errors import UrdfError

    tab = TabCatalog(RobotCatalog())
    with pytest.raises(UrdfError) as refused:
        tab.add_upload("arm\udcff\x07.urdf", b"<robot")
    assert str(refused.value).startswith("upload 'arm\ufffd\ufffd.urdf'")
    str(refused.value).encode("utf-8")  # loggable, sendable
    name = tab.add_upload("arm\udcff.urdf", _arm(""))  # no <robot name>: listed under the file's
    assert name == "arm\ufffd (uploaded)"


def test_a_name_with_html_is_escaped_wherever_shown(session):
    errors0 = session.errors
    hostile = "&lt;img src=x onerror=alert(1)&gt;&lt;script&gt;alert(2)&lt;/script&gt;"
    _upload(session, "<b>x</b>.urdf", _arm(hostile))
    robot = session.state.robot
    assert robot.name.startswith("<img src=x")
    shown = [*gui_contents(session), session.panel.source.content, session.panel.about.content]
    shown += [session.panel.editor.summary.content]
    assert not [s for s in shown if "<img" in s or "<script" in s]
    assert session.state.robot_name in session.panel.robot.options  # a dropdown shows text, not HTML
    assert session.errors == errors0


@pytest.mark.parametrize(
    "uri", ["/etc/passwd", "../../x.stl", "file:///etc/passwd", "package://tmp/x.stl", "meshes/a.stl"]
)
def test_an_uploaded_urdf_never_reads_a_mesh(session, monkeypatch, tmp_path, uri):
    (tmp_path / "x.stl").write_text("solid x\nendsolid x\n")
    errors0 = session.errors
    looked: list[str] = []
    real = kinematics.urdf.mesh.resolve_mesh
    monkeypatch.setattr(
        kinematics.urdf.mesh, "resolve_mesh", lambda *a, **k: looked.append(a) or real(*a, **k)
    )
    mesh = f'<visual><geometry><mesh filename="{uri}"/></geometry></visual>'
    _upload(session, "meshy.urdf", _arm("meshy", mesh))
    assert session.state.robot_name.startswith("meshy") and session.state.robot.urdf_path is None
    assert not looked
    assert not [n for n in scene_props(session) if n.startswith("/lab/arm/urdf")]
    assert session.errors == errors0


def test_uploads_are_capped_at_two_megabytes():
    from app.services.catalog import RobotCatalog
    from kinematics.errors import UrdfError

    tab = TabCatalog(RobotCatalog())
    assert MAX_UPLOAD_BYTES == 2 * 1024 * 1024
    with pytest.raises(UrdfError, match="at most 2 MB"):
        tab.add_upload("x.urdf", b"x" * (MAX_UPLOAD_BYTES + 1))
    assert tab.names() == tab.shared.names()


def test_an_upload_larger_than_one_message_arrives_in_parts(session):
    """The browser sends 512 KiB parts: beyond the 64 KiB message limit, yet the tab is not closed."""
    padded = _arm("padded_arm").replace(b"</robot>", b"<!--" + b"x" * 700_000 + b"--></robot>")
    assert len(padded) > UPLOAD_PART_BYTES
    _upload(session, "padded.urdf", padded)
    assert session.state.robot_name.startswith("padded_arm") and session.state.robot.dof == 2
    session.panel.joints.sliders[0].value = 10.0
    session.settle()
    assert session.state.q[0] == pytest.approx(math.radians(10.0))
