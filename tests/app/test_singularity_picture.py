"""The picture of a singularity, at the server: at every named singular configuration of the library
robots the lost directions are drawn outside the links, each with its label clear of the joints' labels,
the ellipsoid that flattens is the one shown, the words say the same thing, and the camera framing puts
every lost direction across the view."""

from __future__ import annotations

import numpy as np
import pytest
from app_helpers import scene_node
from fakes import poll

import robots
from app.core.actions import GoTo
from app.core.commands import ChooseRobot
from app.views.camera import FROM_ABOVE, THREE_QUARTER, across, facing, lost_axes
from app.views.scene.overlays import MAX_LOSSES

ROOT = "/lab/jacobian"


def singular_configurations():
    return [
        pytest.param(name, conf.name, id=f"{name}-{conf.name}")
        for name in robots.names()
        for conf in robots.load(name).configurations
        if conf.singular
    ]


def _segment_distance(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance of each of ``points`` (N, 3) to the segment a–b."""
    ab = b - a
    t = np.clip(((points - a) @ ab) / max(float(ab @ ab), 1e-300), 0.0, 1.0)
    return np.linalg.norm(points - (a + t[:, None] * ab), axis=1)


def _distance_to_links(points: np.ndarray, links: np.ndarray) -> float:
    return min(
        float(_segment_distance(points, a, b).min()) for a, b in zip(links[:-1], links[1:], strict=True)
    )


def _go(session, robot_name, conf_name):
    session.dispatch(ChooseRobot(robot_name))
    session.dispatch(GoTo(conf_name))
    session.settle()
    assert session.state.configuration == conf_name
    return session.snapshot


@pytest.mark.parametrize(("robot_name", "conf_name"), singular_configurations())
def test_lost_directions_are_drawn_outside_the_arm_and_said_in_the_same_words(session, robot_name, conf_name):
    snap = _go(session, robot_name, conf_name)
    robot = session.state.robot
    size = session.scene.size
    links = snap.link_frames[:, :3, 3]
    status = session.panel.status.content
    assert 1 <= len(snap.losses) <= MAX_LOSSES

    # A spherical wrist is decoupled, and the parts agree with the kinds the geometry names.
    parts = {x.part for x in snap.losses}
    if snap.decoupling is not None:
        assert parts <= {"arm", "wrist"}
        assert ("wrist" in parts) == ("wrist" in snap.report.kinds)
        assert ("arm" in parts) == bool({"elbow", "shoulder"} & set(snap.report.kinds))
        assert ("Wrist singular" in status) == ("wrist" in parts)
        assert ("Arm singular" in status) == ("arm" in parts)
        assert "det J = det J<sub>11</sub> (arm) · det J<sub>22</sub> (wrist)" in status
        assert "Lost</b>:" not in status and "translation 9" not in status
        for x in snap.losses:
            np.testing.assert_allclose(x.point, snap.decoupling.centre)
    else:
        assert parts == {"tool"}
        assert status.count("Lost</b>:") == len(snap.losses) and "Measured at the tool point" in status

    # Each lost translation: an arrow along it, every point of it clear of the link polyline.
    moved = [
        x for x in snap.losses if x.translation_share >= 0.1 or (robot.planar and x.translation_share > 0)
    ]
    arrows = scene_node(session, f"{ROOT}/lost_translation")
    assert arrows.visible == bool(moved)
    if moved:
        for (start, end), loss in zip(np.asarray(arrows.points), moved, strict=True):
            u = (end - start) / np.linalg.norm(end - start)
            assert u @ loss.translation == pytest.approx(1.0, abs=1e-6)
            along = start + np.linspace(0, 1, 21)[:, None] * (end - start)
            assert _distance_to_links(along, links) > 0.04 * size, "the arrow lies on the arm"
    # Each lost rotation: an axis through its point.
    turned = [x for x in snap.losses if x.rotation_share >= 0.1 and not robot.planar]
    axis_node = scene_node(session, f"{ROOT}/lost_rotation")
    assert axis_node.visible == bool(turned)

    # A label per drawn direction, the same words once (the iiwa candle's two arm arrows: one
    # "arm: lost translation"), none on a joint's label.
    labels = [scene_node(session, f"{ROOT}/lost_label_{i}") for i in range(MAX_LOSSES)]
    shown = [label for label in labels if label.visible]
    assert bool(shown) == bool(moved or turned) and len(shown) <= len(moved) + len(turned)
    assert len({label.text for label in shown}) == len(shown)
    kinds = {"v" for _ in moved} | {"w" for _ in turned}
    assert {"v" if "translation" in label.text else "w" for label in shown} == kinds
    joint_labels = np.array(
        [scene_node(session, f"/lab/arm/label_{j}").position for j in range(len(robot.joint_names))]
    )
    for label in shown:
        gaps = np.linalg.norm(joint_labels - np.asarray(label.position), axis=1)
        assert gaps.min() > 0.05 * size, f"{label.text!r} sits on a joint label"
    texts = " ".join(label.text for label in shown)
    assert ("wrist: lost rotation axis" in texts) == ("wrist" in parts)

    # The ellipsoid that flattens is drawn, flat along the lost direction, and visibly thick.
    if snap.decoupling is not None:
        assert not scene_node(session, f"{ROOT}/velocity_ellipsoid").visible  # the tool's does not flatten
        for part, name in (("arm", "arm_ellipsoid"), ("wrist", "wrist_ellipsoid")):
            node = scene_node(session, f"{ROOT}/{name}")
            assert node.visible == (part in parts)
        block = snap.arm_ellipsoid if "arm" in parts else snap.wrist_ellipsoid
        flat = block.axes[:, int(np.argmin(block.radii))]
        lost = next(x for x in snap.losses if x.part == ("arm" if "arm" in parts else "wrist"))
        assert abs(flat @ (lost.translation + lost.rotation)) == pytest.approx(1.0, abs=1e-6)
    else:
        velocity = scene_node(session, f"{ROOT}/velocity_ellipsoid")
        node = velocity if velocity.visible else scene_node(session, f"{ROOT}/rotational_ellipsoid")
        assert node.visible and min(node.scale) >= 0.029 * size  # a collapsed ellipse stays visible


@pytest.mark.parametrize(("robot_name", "conf_name"), singular_configurations())
def test_the_camera_policy_puts_every_lost_direction_across_the_view(session, robot_name, conf_name):
    """From the views the app starts with (three-quarter, facing the arm, from above) and from looking
    straight down a lost direction, the framing at a singularity leaves ≥ 45° to every lost direction,
    and ≥ 75° to a single one (its flattened ellipsoid then shows at most a quarter of its width: it
    looks flat, not like a healthy ellipse seen from above)."""
    snap = _go(session, robot_name, conf_name)
    axes = lost_axes(snap.losses)
    assert len(axes)
    least = 75.0 if len(axes) == 1 else 45.0
    starts = [THREE_QUARTER, FROM_ABOVE, facing(session.scene.extent), *axes, *(-axes)]
    for start in starts:
        d = across(start, axes)
        assert np.linalg.norm(d) == pytest.approx(1.0)
        angles = np.degrees(np.arccos(np.clip(np.abs(axes @ d), 0.0, 1.0)))
        assert angles.min() >= least - 1e-6, (start, angles)
    # ... and the tab's camera ends there after the jump (its aim point is the arm's, not the loss's).
    poll(lambda: _camera_angles(session, axes).min() >= least - 5.0)


def test_puma_wrist_singularity_says_wrist_not_translation(session):
    snap = _go(session, "puma560", "wrist_singular")
    status = session.panel.status.content
    assert "<b>Wrist singular</b>: the wrist loses a rotation about (0.71, 0, 0.71)." in status
    assert "translation" not in status.split("Wrist singular")[1]
    assert snap.decoupling.det_wrist == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("robot_name", ["puma560", "stanford", "elbow3r"])
def test_derive_steps_are_framed_with_their_vectors_across_the_view(session, robot_name):
    """Whitney's walk: at every step the axis zᵢ₋₁, the lever pₙ − pᵢ₋₁ and the column Jᵢ are ≥ 45° from
    the view the camera policy picks (on the Puma at home, from the default view z₁, z₂ and J₁ were dots)."""
    from app.core.actions import SetOption
    from app.views.camera import step_axes

    session.dispatch(ChooseRobot(robot_name))
    session.dispatch(SetOption("derive", "whitney"))
    session.settle()
    for k in range(session.state.robot.dof):
        session.dispatch(SetOption("derive_step", k))
        session.settle()
        axes = step_axes(session.snapshot.derive)
        assert len(axes) >= 1  # zᵢ₋₁ (lever and column are zero for a wrist axis through the tool point)
        d = across(THREE_QUARTER, axes)
        angles = np.degrees(np.arccos(np.clip(np.abs(axes @ d), 0.0, 1.0)))
        assert angles.min() >= 45.0, (k, angles)
        # ... and the tab's camera goes there.
        poll(lambda axes=axes: _camera_angles(session, axes).min() >= 45.0)


def _camera_angles(session, axes: np.ndarray) -> np.ndarray:
    cam = session.client.camera
    d = np.asarray(cam.position, float) - np.asarray(cam.look_at, float)
    d /= np.linalg.norm(d)
    return np.degrees(np.arccos(np.clip(np.abs(axes @ d), 0.0, 1.0)))
