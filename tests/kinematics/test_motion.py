"""Resolved-rate motion (kinematics.motion.resolved_rate): q_{k+1} = q_k + Δt J⁻¹ v, its stops and measures."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fakes import random_q

import robots
from kinematics import (
    ArrayError,
    ConfigurationError,
    JacobianLabError,
    OptionError,
    condition_number,
    fk,
    jacobian,
    manipulability,
    singular_values,
)
from kinematics.motion.resolved_rate import resolved_rate, resolved_rate_step

DEG = math.pi / 180


def test_course_trr_inverse_velocity():
    """The course: at q = (5 m, 60°, −15°), v = (17.256, −20.13, 0.500) m/s needs
    q̇ = (0.5 m/s, 90°/s, 45°/s) (numbers rounded in the notes)."""
    trr = robots.load("trr")
    q = np.array([5, 60 * DEG, -15 * DEG])
    q_next, qd, stop = resolved_rate_step(trr, q, [17.256, -20.13, 0.500], dt=0.01)
    assert stop is None
    assert np.allclose(qd, [0.5, math.pi / 2, math.pi / 4], atol=2e-3)
    assert np.allclose(q_next, q + 0.01 * qd, atol=1e-15)
    # a full twist [v; ω] gives the same step (only the task rows are used)
    q6, qd6, _ = resolved_rate_step(trr, q, [17.256, -20.13, 0.500, 9.0, 9.0, 9.0], dt=0.01)
    assert np.array_equal(qd6, qd) and np.array_equal(q6, q_next)


@pytest.mark.parametrize("name", ["puma560", "panda", "iiwa14", "planar3", "trr"])
@pytest.mark.parametrize("frame", ["base", "tool"])
def test_every_step_realises_the_twist(name, frame):
    """J(q_k) q̇_k = v exactly (square or redundant J); the tool moves by ≈ v Δt per step."""
    robot = robots.load(name)
    rng = np.random.default_rng(11)
    q0 = random_q(robot, rng)
    twist = rng.normal(0, 0.05, 6)
    rows = {"planar3": [0, 1, 5], "trr": [0, 1, 2]}.get(name, list(range(6)))
    traj = resolved_rate(robot, q0, twist, dt=0.01, steps=20, frame=frame, rate_limit=1e3)
    k = len(traj.qd)
    assert k >= 3 and traj.q.shape == (k + 1, robot.dof) and traj.qd.shape == (k, robot.dof)
    assert (k == 20) == (traj.stopped is None)
    for q, qd in zip(traj.q[:-1], traj.qd, strict=True):
        assert np.allclose(jacobian(robot, q, frame)[rows] @ qd, twist[rows], atol=1e-9)
    # finite differences of fk over tiny steps: the tool point moves at v (to O(Δt))
    fine = resolved_rate(robot, q0, twist, dt=1e-6, steps=3, frame=frame, rate_limit=1e3)
    p = np.array([fk(robot, q)[:3, 3] for q in fine.q])
    v = np.diff(p, axis=0) / 1e-6
    lin = [r for r in rows if r < 3]
    for k, q in enumerate(fine.q[:-1]):
        R = fk(robot, q)[:3, :3] if frame == "tool" else np.eye(3)
        assert np.allclose(v[k][lin], (R @ twist[:3])[lin], atol=1e-4)


def test_measures_along_the_path_are_those_of_j():
    robot = robots.load("puma560")
    traj = resolved_rate(robot, robot.home + 0.2, [0.05, 0.0, 0.02, 0.0, 0.1, 0.0], dt=0.02, steps=10)
    assert traj.stopped is None and len(traj.q) == 11
    assert np.allclose(traj.time, 0.02 * np.arange(11))
    for k, q in enumerate(traj.q):
        J = jacobian(robot, q)
        s = singular_values(J)
        assert traj.sigma_min[k] == pytest.approx(s[-1], rel=1e-9)
        assert traj.kappa[k] == pytest.approx(condition_number(J), rel=1e-9)
        assert traj.inverse_kappa[k] == pytest.approx(s[-1] / s[0], rel=1e-9)
        assert traj.w[k] == pytest.approx(manipulability(J), rel=1e-9)


def test_joint_limit_stop_never_crosses():
    """TRR sliding up at 1 m/s from 5 m: the slide's upper limit (16 m) stops it."""
    trr = robots.load("trr")
    traj = resolved_rate(trr, [5, 60 * DEG, -15 * DEG], [0, 0, 1.0], dt=0.5, steps=100)
    stop = traj.stopped
    assert stop is not None and stop.kind == "joint limit" and stop.joint == 0
    assert "upper limit 16 m" in stop.message and "q1 slide" in stop.message
    assert traj.q[:, 0].max() <= 16.0
    assert len(traj.q) == stop.step + 1 == 23  # 5 + 0.5·22 = 16; step 22 would pass
    assert np.allclose(traj.q[-1], [16.0, 60 * DEG, -15 * DEG])


def test_a_motion_that_meets_a_limit_ends_exactly_at_it_along_the_same_step():
    """The Puma raising its tool at 0.2 m/s meets the elbow's upper limit (45°) inside a step: the motion
    takes that step's part up to the limit (the course's 002: a critical point), so q3 ends ON its bound,
    the step's direction is the one J⁻¹v gave (every joint scaled alike) and the time is where it got there."""
    puma = robots.load("puma560")
    q0 = np.zeros(6)
    q0[1], q0[2], q0[4] = puma.qlim[1, 1] - 0.3, 0.5, 0.6
    v, dt = np.array([0, 0, 0.2, 0, 0, 0]), 0.05
    traj = resolved_rate(puma, q0, v, dt=dt, steps=400)
    stop = traj.stopped
    assert (
        stop is not None
        and stop.kind == "joint limit"
        and stop.joint == 2
        and "upper limit 45°" in stop.message
    )
    before, end = traj.q[-2], traj.q[-1]
    assert end[2] == pytest.approx(puma.qlim[1, 2], abs=1e-12)  # at the limit, not a step before it
    assert (traj.q >= puma.qlim[0] - 1e-12).all() and (traj.q <= puma.qlim[1] + 1e-12).all()
    qd = np.linalg.solve(jacobian(puma, before), v)  # the full step from the last q inside
    assert before[2] + dt * qd[2] > puma.qlim[1, 2]  # would have passed it
    share = (puma.qlim[1, 2] - before[2]) / (dt * qd[2])
    assert 0 < share < 1 and stop.share == pytest.approx(share, rel=1e-12)
    assert np.allclose(end - before, share * dt * qd, atol=1e-12)  # the direction kept, every joint
    assert np.allclose(traj.qd[-1], qd, atol=1e-9)
    assert traj.time[-1] == pytest.approx(traj.time[-2] + share * dt, rel=1e-12)
    # one step alone from there: at the limit and still pushing out, it stays
    q_next, _, again = resolved_rate_step(puma, end, v, dt=dt)
    assert (
        again is not None and again.kind == "joint limit" and again.share == 0 and np.array_equal(q_next, end)
    )


def test_rate_bound_stop_names_the_joint():
    """Planar 2R arm pushed outward toward its stretched singularity: q̇ grows like 1/sin q2."""
    arm = robots.load("planar2")
    traj = resolved_rate(arm, [0.3, 0.2], [1.0, 0, 0, 0, 0, 0], dt=0.01, steps=300, rate_limit=10.0)
    stop = traj.stopped
    assert stop is not None and stop.kind == "rate bound"
    q = traj.q[-1]
    qd = np.linalg.solve(jacobian(arm, q)[:2], [1.0, 0.0])
    assert stop.joint == int(np.argmax(np.abs(qd))) and np.abs(qd).max() > 10.0
    assert np.abs(traj.qd).max() <= 10.0
    assert f"joint {stop.joint + 1}" in stop.message and "rad/s" in stop.message
    _, qd_step, again = resolved_rate_step(arm, q, [1.0, 0, 0, 0, 0, 0], dt=0.01, rate_limit=10.0)
    assert again is not None and again.kind == "rate bound" and np.allclose(qd_step, qd)


def test_singular_stop_without_damping_and_damped_motion_through_it():
    arm = robots.load("planar2")
    traj = resolved_rate(arm, [0.3, 0.0], [0.0, 0.1, 0, 0, 0, 0], dt=0.01, steps=10)
    assert traj.stopped is not None and traj.stopped.kind == "singular" and traj.stopped.step == 0
    assert traj.stopped.joint is None and len(traj.q) == 1
    assert traj.kappa[0] == math.inf and traj.inverse_kappa[0] == pytest.approx(0.0, abs=1e-12)
    damped = resolved_rate(arm, [0.3, 0.0], [0.0, 0.1, 0, 0, 0, 0], dt=0.01, steps=10, damping=0.1)
    assert damped.stopped is None and len(damped.q) == 11
    assert np.isfinite(damped.inverse_kappa).all()


def test_the_library_is_the_step_repeated():
    robot = robots.load("panda")
    twist = np.array([0.0, 0.05, -0.02, 0.1, 0.0, 0.0])
    traj = resolved_rate(robot, robot.home, twist, dt=0.02, steps=15, frame="tool", damping=0.01)
    q = robot.home
    for k in range(15):
        q, qd, stop = resolved_rate_step(robot, q, twist, dt=0.02, frame="tool", damping=0.01)
        assert stop is None
        assert np.array_equal(q, traj.q[k + 1]) and np.array_equal(qd, traj.qd[k])


@pytest.mark.parametrize(
    ("kwargs", "error", "word"),
    [
        (dict(twist=[1.0, 2.0]), ArrayError, "twist"),
        (dict(twist=[1.0, 0, 0, 0, 0, np.nan]), ArrayError, "twist"),
        (dict(q=[0.0]), ConfigurationError, "q"),
        (dict(dt=0.0), OptionError, "dt"),
        (dict(dt=-0.1), OptionError, "dt"),
        (dict(frame="world"), OptionError, "frame"),
        (dict(damping=-1.0), OptionError, "damping"),
        (dict(rate_limit=0.0), OptionError, "rate_limit"),
        (dict(rows=(0, 0)), OptionError, "rows"),
    ],
)
def test_bad_inputs(kwargs, error, word):
    robot = robots.load("puma560")
    args = dict(q=robot.home + 0.1, twist=np.zeros(6), dt=0.01)
    args.update(kwargs)
    q, twist = args.pop("q"), args.pop("twist")
    with pytest.raises(error, match=word) as info:
        resolved_rate_step(robot, q, twist, **args)
    assert isinstance(info.value, JacobianLabError)
    with pytest.raises(OptionError, match="steps"):
        resolved_rate(robot, robot.home, np.zeros(6), dt=0.01, steps=-1)
