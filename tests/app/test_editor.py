"""The Build tab at server level: inputs set as a user would (``handle.value = x`` runs the callbacks),
the robot drawn from the table, rows added, removed and moved, bad values named, and downloads."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from app_helpers import assert_all_finite, scene_node

import robots
from app.core.build_table import BUILT_NAME
from app.views.panel.editor import DOWNLOADS, EMPTY, ROW_BUTTONS
from kinematics import Robot, robot_from_urdf
from kinematics.numeric import jacobian

ADD, REMOVE, UP, DOWN = ROW_BUTTONS
RNG = np.random.default_rng(7)


def _editor(session):
    editor = session.panel.editor
    editor.start.value = "planar2"  # then a fresh one-row table, whatever the previous test left
    editor.start.value = EMPTY
    session.settle()
    assert len(editor.table.rows) == 1 and session.state.robot_name == BUILT_NAME
    return editor


def _rows(*rows):
    """DH rows in radians from (kind, a, alpha°, d, theta°, lo, hi) with lo/hi in ° or m."""
    out = []
    for kind, a, alpha, d, theta, lo, hi in rows:
        rev = kind == "revolute"
        qlim = (math.radians(lo), math.radians(hi)) if rev else (lo, hi)
        out.append(
            dict(joint=kind, a=a, alpha=math.radians(alpha), d=d, theta=math.radians(theta), qlim=qlim)
        )
    return out


def _same_jacobian(a: Robot, b: Robot, samples: int = 5) -> None:
    assert a.dof == b.dof
    lo, hi = np.clip(a.qlim, -3, 3)
    for q in RNG.uniform(lo, hi, size=(samples, a.dof)):
        np.testing.assert_allclose(jacobian(a, q), jacobian(b, q), atol=1e-12)


def _downloads(session, monkeypatch) -> list[tuple[str, bytes]]:
    sent: list[tuple[str, bytes]] = []
    monkeypatch.setattr(
        session.client, "send_file_download", lambda name, data, **_: sent.append((name, data))
    )
    return sent


def _limits(editor, lo: float, hi: float) -> None:
    """Type the lower, then the upper limit."""
    editor.lower.value = str(lo)
    editor.upper.value = str(hi)


def test_an_edit_draws_the_robot_of_the_table_live(session):
    editor = _editor(session)
    handles = (editor.a, editor.alpha, editor.d, editor.theta, editor.lower, editor.upper, editor.row)
    editor.a.value = "0.7"
    editor.alpha.value = "90.0"
    editor.d.value = "0.25"
    editor.theta.value = "30.0"
    _limits(editor, -90.0, 120.0)
    session.settle()
    state = session.state
    assert state.robot_name == BUILT_NAME and state.robot is editor.built and editor.error == ""
    expected = Robot.from_dh(_rows(("revolute", 0.7, 90.0, 0.25, 30.0, -90.0, 120.0)))
    _same_jacobian(state.robot, expected)
    np.testing.assert_allclose(state.robot.qlim[:, 0], np.radians([-90.0, 120.0]))
    # The editor's own widgets were not rebuilt; the robot dropdown offers the built robot.
    assert (editor.a, editor.alpha, editor.d, editor.theta, editor.lower, editor.upper, editor.row) == handles
    assert BUILT_NAME in session.panel.robot.options and session.panel.robot.value == BUILT_NAME
    assert "0.7" in editor.summary.content and "drawn live" in editor.summary.content
    assert session.errors == 0
    assert_all_finite(session)


def test_rows_added_removed_and_moved_keep_the_joint_values_of_unchanged_rows(session):
    editor = _editor(session)
    editor.a.value = "0.4"
    editor.rows.value = ADD  # row 2 after row 1, selected
    editor.kind.value = "prismatic"
    _limits(editor, 0.0, 0.3)
    editor.theta.value = "90.0"
    editor.rows.value = ADD  # row 3
    editor.a.value = "0.2"
    session.settle()
    assert editor.row.options == ("1", "2", "3") and editor.row.value == "3"
    r1, r2, r3 = (
        ("revolute", 0.4, 0.0, 0.0, 0.0, -180.0, 180.0),
        ("prismatic", 0.3, 0.0, 0.0, 90.0, 0.0, 0.3),
        ("revolute", 0.2, 0.0, 0.0, 0.0, -180.0, 180.0),
    )
    _same_jacobian(session.state.robot, Robot.from_dh(_rows(r1, r2, r3)))

    session.panel.joints.sliders[0].value = 40.0  # q1 = 40°, q2 = 0.1 m
    session.panel.joints.sliders[1].value = 0.1
    session.settle()
    editor.row.value = "1"
    editor.rows.value = DOWN  # rows 2, 1, 3: the values follow their rows
    session.settle()
    _same_jacobian(session.state.robot, Robot.from_dh(_rows(r2, r1, r3)))
    np.testing.assert_allclose(session.state.q[:2], [0.1, math.radians(40.0)])
    assert editor.row.value == "2"

    editor.alpha.value = "-90.0"  # a number changed: every joint value stays
    session.settle()
    r1b = ("revolute", 0.4, -90.0, 0.0, 0.0, -180.0, 180.0)
    _same_jacobian(session.state.robot, Robot.from_dh(_rows(r2, r1b, r3)))
    np.testing.assert_allclose(session.state.q[:2], [0.1, math.radians(40.0)])

    editor.row.value = "1"
    editor.rows.value = REMOVE  # the prismatic row goes; q1 = 40° stays with its row
    session.settle()
    _same_jacobian(session.state.robot, Robot.from_dh(_rows(r1b, r3)))
    assert session.state.q[0] == pytest.approx(math.radians(40.0))
    editor.rows.value = UP  # already first: nothing changes
    editor.rows.value = REMOVE
    editor.rows.value = REMOVE  # the last row cannot go
    session.settle()
    assert len(editor.table.rows) == 1 and "at least one joint" in editor.error
    assert session.state.robot.dof == 1
    assert session.errors == 0


def test_starting_from_the_puma_gives_the_pumas_jacobian(session):
    editor = _editor(session)
    editor.start.value = "puma560"
    session.settle()
    assert editor.row.options == tuple("123456") and editor.convention.value == "standard"
    assert editor.alpha.value == "90"  # degrees on screen, shortest exact form
    puma = robots.load("puma560")
    _same_jacobian(session.state.robot, puma, samples=8)
    np.testing.assert_allclose(session.state.q, puma.home)  # at the Puma's home, not mid-limits
    assert session.state.configuration == "home"
    editor.start.value = "puma560_mdh"  # modified DH, with a tool transform
    session.settle()
    assert editor.convention.value == "modified"
    _same_jacobian(session.state.robot, robots.load("puma560_mdh"), samples=8)
    assert "puma560" in editor.start.options and "panda" in editor.start.options


@pytest.mark.parametrize(
    ("field", "value", "named"),
    [
        ("a", "nan", "Row 1, a [m]: “nan” is not a number"),
        ("alpha", "ninety", "Row 1, α [°]: “ninety” is not a number"),
        ("d", "1e400", "Row 1, d [m]: “1e400” is too large"),
        ("limits", (50.0, -50.0), "Row 1, lower limit: the lower limit 50 is above the upper limit -50"),
        ("a", "1e16", "Row 1, a [m]: 1e+16 is beyond ±100"),
        ("a", "0,3", "Row 1, a [m]: “0,3”: use a point for decimals (0.3)"),
        ("d", "1e-", "Row 1, d [m]: “1e-” is not a number"),
    ],
)
def test_a_bad_value_is_named_and_the_last_good_robot_stays(session, field, value, named):
    editor = _editor(session)
    editor.a.value = "0.6"
    if field == "limits":
        editor.upper.value = str(value[1])  # a good robot with the upper limit, then the bad lower one
    session.settle()
    good = session.state.robot
    if field == "limits":
        editor.lower.value = str(value[0])
    else:
        getattr(editor, field).value = value  # typed into the text box as it is
    session.settle()
    assert named in editor.error
    assert "⚠" in editor.summary.content and named.split(":")[0] in editor.summary.content
    # The value the error names is marked in the table; what is not a finite number shows as typed
    # (1e400 showed "inf" while the arm kept its last good d).
    cell = re.search(r'<td class="bad" title="[^"]*">([^<]*) ⚠</td>', editor.summary.content)
    assert cell is not None, editor.summary.content
    if isinstance(value, str) and value in ("nan", "ninety", "1e400", "0,3", "1e-"):
        assert cell.group(1) == value[:8]
    assert "inf" not in editor.summary.content.lower()
    assert session.state.robot is good and session.errors == 0
    assert_all_finite(session)
    editor.theta.value = "5.0"  # changing another field does not hide the bad one
    assert named.split(":")[0] in editor.error and session.state.robot is good
    editor.theta.value = "0.0"
    for name, mended in (("a", "0.55"), ("alpha", "0"), ("d", "0")):
        getattr(editor, name).value = mended
    _limits(editor, -170.0, 170.0)
    session.settle()
    assert editor.error == "" and session.state.robot is not good
    _same_jacobian(session.state.robot, Robot.from_dh(_rows(("revolute", 0.55, 0, 0, 0, -170, 170))))


def test_text_in_a_field_is_escaped_in_the_message(session):
    editor = _editor(session)
    editor.set_field("theta", "<img src=x onerror=alert(1)>")
    session.settle()
    assert "<img" not in editor.summary.content and "&lt;img" in editor.summary.content


def test_the_robot_file_download_loads_back_with_the_same_jacobian(session, monkeypatch, tmp_path):
    editor = _editor(session)
    sent = _downloads(session, monkeypatch)
    editor.start.value = "puma560_mdh"  # a tool transform, modified DH
    editor.row.value = "2"
    editor.d.value = "0.1234"
    editor.rows.value = ADD
    editor.kind.value = "prismatic"
    _limits(editor, -0.2, 0.4)
    session.settle()
    built = session.state.robot
    editor.download.value = "TOML"
    editor.download.value = "URDF"
    session.settle()
    (toml_name, toml), (urdf_name, urdf) = sent
    assert toml_name == "built_robot.toml" and urdf_name.endswith(".urdf")
    path = tmp_path / toml_name
    path.write_bytes(toml)
    loaded = robots.load(path)
    assert loaded.convention == "modified" and loaded.joint_types == built.joint_types
    np.testing.assert_allclose(loaded.qlim, built.qlim, atol=1e-12)
    _same_jacobian(loaded, built, samples=10)
    (tmp_path / "built.urdf").write_bytes(urdf)
    _same_jacobian(robot_from_urdf(str(tmp_path / "built.urdf")), built, samples=10)
    assert "alpha = 90.0" in toml.decode() or "alpha = -90.0" in toml.decode()  # degrees in the file
    assert loaded.configurations == ()  # a row was added: the original's home no longer fits


def test_a_robot_file_keeps_the_home_it_started_from(session, monkeypatch, tmp_path):
    editor = _editor(session)
    sent = _downloads(session, monkeypatch)
    editor.start.value = "puma560"
    editor.row.value = "3"
    editor.a.value = "0.05"
    editor.download.value = "TOML"
    session.settle()
    (tmp_path / sent[0][0]).write_bytes(sent[0][1])
    loaded = robots.load(tmp_path / sent[0][0])
    np.testing.assert_allclose(loaded.home, robots.load("puma560").home, atol=1e-12)
    _same_jacobian(loaded, session.state.robot, samples=10)


def test_the_symbolic_j_buttons_use_the_existing_export(session, monkeypatch):
    editor = _editor(session)
    editor.a.value = "0.5"
    session.settle()
    asked = []
    monkeypatch.setattr(
        session.commands, "_download", lambda state, label: asked.append((state.robot, label))
    )
    for button in DOWNLOADS:
        editor.download.value = button
    session.settle()
    assert [label for _, label in asked] == list(DOWNLOADS.values())
    assert {"LaTeX", "Python", "JSON"} <= {label for _, label in asked}
    assert all(robot is editor.built for robot, _ in asked)


def test_the_arm_is_drawn_from_the_table(session):
    """The scene follows the table: the tool point moves out with a, a prismatic row gets its box."""
    editor = _editor(session)
    editor.a.value = "0.8"
    session.settle()
    tool = session.snapshot.link_frames[-1][:3, 3]
    assert np.linalg.norm(tool) == pytest.approx(0.8)
    editor.a.value = "1.2"
    session.settle()
    assert np.linalg.norm(session.snapshot.link_frames[-1][:3, 3]) == pytest.approx(1.2)
    assert "/lab/arm/prismatic" not in _scene_names(session)
    editor.rows.value = ADD
    editor.kind.value = "prismatic"
    session.settle()
    assert session.state.robot.joint_types == ("revolute", "prismatic")
    assert "/lab/arm/prismatic" in _scene_names(session)
    assert len(scene_node(session, "/lab/arm/prismatic").batched_positions) == 1
    assert_all_finite(session)


def _scene_names(session) -> set[str]:
    from app.viser_adapter import scene_handles

    return set(scene_handles(session.client.scene))


def test_an_edit_keeps_the_users_view_a_new_robot_is_framed(session, monkeypatch):
    editor = _editor(session)
    framed: list[dict] = []
    real = session.camera.frame
    monkeypatch.setattr(session.camera, "frame", lambda *a, **k: framed.append(k) or real(*a, **k))
    editor.a.value = "0.52"  # the same built robot, edited: the camera is not re-aimed
    session.settle()
    assert session.state.robot.dh[0].a == pytest.approx(0.52)
    assert not [k for k in framed if k.get("glide") is False]
    session.panel.robot.value = "planar2"  # another robot: framed at once
    session.settle()
    assert [k for k in framed if k.get("glide") is False]


def test_a_planar_arm_built_in_the_browser_is_planar_not_singular_everywhere(session):
    """All axes along base z: the built robot takes the planar rows (vx, vy) as its task, as planar2 does,
    so a bent pose is regular (det J = a₁ a₂ sin q₂) instead of singular through an always-zero vz row."""
    editor = _editor(session)
    editor.a.value = 1.0
    editor.rows.value = ADD
    editor.a.value = 0.5
    session.settle()
    robot = session.state.robot
    assert robot.planar and session.snapshot.rows == (0, 1)
    session.panel.joints.sliders[1].value = 60.0
    session.settle()
    snap = session.snapshot
    assert snap.report.status == "regular"
    assert snap.det == pytest.approx(1.0 * 0.5 * math.sin(math.radians(60.0)), rel=1e-9)
    editor.row.value = "1"
    editor.alpha.value = 90.0  # standard DH: α₁ tilts axis 2 out of line with axis 1, no longer planar
    session.settle()
    assert not session.state.robot.planar
