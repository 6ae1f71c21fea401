"""Every camera the app chooses shows what the moment is about across the view (issue 28, stumble 5
and 6): at every named singular configuration of every robot the lost directions, with Whitney's step 1
open the step's vectors too (the Puma's shoulder singularity was seen straight down the lost
direction), with velocity propagation open every drawn vₖ and ωₖ (the TRR's v₃ was seen end-on), and
the arm itself readable: its long axis never end-on (the Stanford arm's upright boom was framed from
above, four joint labels in one spot), its joint labels apart on a 1280×720 canvas.

The camera is the tab's own (``client.camera``, polled after its glide); angles are measured from the
camera's line of sight, the joint labels projected through its pinhole (:func:`app.views.camera.project`,
checked here against a hand-made camera)."""

from __future__ import annotations

import numpy as np
import pytest
from app_helpers import labels_placed, scene_node
from fakes import poll

import robots
from app.core.actions import GoTo, SetOption
from app.core.commands import ChooseRobot
from app.views.camera import View, arm_axis, lost_axes, project, step_axes

LEAST = 30.0
"""Every chosen camera sees each lost direction and step vector at least this far from its line of
sight (|projection| ≥ sin 30° = half its length)."""
WIDTH, HEIGHT = 1280, 720


def singular(names=None):
    return [
        pytest.param(name, conf.name, id=f"{name}-{conf.name}")
        for name in names or robots.names()
        for conf in robots.load(name).configurations
        if conf.singular
    ]


def sight(session) -> np.ndarray:
    cam = session.client.camera
    d = np.asarray(cam.position, float) - np.asarray(cam.look_at, float)
    return d / np.linalg.norm(d)


def angles(session, axes: np.ndarray) -> np.ndarray:
    """The angles [°] between the camera's line of sight and each of ``axes`` (k, 3)."""
    return np.degrees(np.arccos(np.clip(np.abs(axes @ sight(session)), 0.0, 1.0)))


def settled(session, axes: np.ndarray) -> np.ndarray:
    """The angles once the camera has stopped gliding and sees every axis at ≥ LEAST (or the last)."""
    last = [angles(session, axes)]

    def done():
        now = angles(session, axes)
        ok = np.allclose(now, last[0], atol=0.01) and (now.min() >= LEAST if len(now) else True)
        last[0] = now
        return ok

    poll(done, what="the camera settled with every direction across the view")
    return last[0]


def joint_label_gap(session) -> float:
    """The smallest distance [px] between the labels of joints i and i + 1 on a 1280×720 canvas through
    the camera, of those apart in space (≥ 10 % of the arm's size: labels on one point, the Panda's shoulder, no camera
    can part; the screen-space placement does)."""
    cam = session.client.camera
    view = View(
        np.asarray(cam.position, float), np.asarray(cam.look_at, float), np.array([0.0, 0, 1]),
        float(cam.fov), WIDTH / HEIGHT,
    )  # fmt: skip
    robot = session.state.robot
    at = np.array(
        [scene_node(session, f"/lab/arm/label_{j}").position for j in range(len(robot.joint_names))]
    )
    px = project(view, at, WIDTH, HEIGHT)
    gaps = np.linalg.norm(px[1:] - px[:-1], axis=-1)
    apart = np.linalg.norm(at[1:] - at[:-1], axis=-1) >= 0.1 * session.scene.size
    return float(gaps[apart].min()) if apart.any() else np.inf


def test_projection_matches_a_hand_made_camera():
    view = View(np.array([0.0, -2.0, 0.0]), np.zeros(3), np.array([0.0, 0, 1]), np.radians(90), 2.0)
    px = project(view, np.array([[0, 0, 0], [1, 0, 0], [0, 0, 1], [0, -1, 0.5], [0, -3, 0]]), 200, 100)
    # f = 50 px per unit tangent: 1 m right at 2 m depth → 25 px; 0.5 m up at 1 m depth → 25 px.
    np.testing.assert_allclose(px[:4], [[100, 50], [125, 50], [100, 25], [100, 25]])
    assert np.isnan(px[4]).all()  # behind the camera


@pytest.mark.parametrize(("robot_name", "conf_name"), singular())
def test_a_jump_to_a_singularity_shows_the_loss_and_the_arm(session, robot_name, conf_name):
    session.dispatch(ChooseRobot(robot_name))
    session.dispatch(GoTo(conf_name))
    session.settle()
    snap = session.snapshot
    lost = lost_axes(snap.losses)
    arm = arm_axis(snap.link_frames[:, :3, 3])
    seen = settled(session, np.vstack([lost, arm]))
    assert seen.min() >= LEAST, seen
    labels_placed(session)  # the labels placed for the camera that stopped (a busy machine places them later)
    assert joint_label_gap(session) >= 14.0  # apart: a label is ~14 px high


@pytest.mark.parametrize(("robot_name", "conf_name"), singular(["puma560", "ur5", "stanford", "elbow3r"]))
def test_whitney_step_1_at_a_singularity_shows_the_loss_and_the_step(session, robot_name, conf_name):
    session.dispatch(ChooseRobot(robot_name))
    session.dispatch(SetOption("derive", "whitney"))
    session.dispatch(SetOption("derive_step", 0))
    session.dispatch(GoTo(conf_name))
    session.settle()
    snap = session.snapshot
    axes = np.vstack([lost_axes(snap.losses), step_axes(snap.derive)])
    seen = settled(session, axes)
    assert seen.min() >= LEAST, seen


def test_the_trr_velocity_propagation_sees_every_vector(session):
    session.dispatch(ChooseRobot("trr"))
    for i, q in enumerate((5.0, np.radians(60), np.radians(-15))):
        from app.core.actions import SetJoint

        session.dispatch(SetJoint(i, float(q)))
    session.dispatch(SetOption("derive", "propagation"))
    session.settle()
    for k in range(3):
        session.dispatch(SetOption("derive_step", k))
        session.settle()
        axes = step_axes(session.snapshot.derive)
        assert len(axes) >= 2 * (k + 1) - 1  # vₖ and ωₖ of every frame (ω₁ = 0: a slide)
        seen = settled(session, axes)
        assert seen.min() >= LEAST, (k, seen)
