"""Descent to a nearby singularity (kinematics.singularity.nearest)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fakes import random_q

import robots
from kinematics import ConfigurationError, JacobianLabError, OptionError, jacobian, singular_values, task_rows
from kinematics.singularity import nearest

DEG = math.pi / 180


def ratio(robot, q):
    s = singular_values(jacobian(robot, q), task_rows(robot))
    return s[-1] / s[0]


@pytest.mark.parametrize("q2", [20 * DEG, -35 * DEG, 160 * DEG])
def test_planar2_goes_to_the_nearest_of_stretched_or_folded(q2):
    arm = robots.load("planar2")
    res = nearest(arm, [0.3, q2])
    target = 0.0 if abs(q2) < math.pi / 2 else math.copysign(math.pi, q2)
    assert res.q[1] == pytest.approx(target, abs=1e-6)
    assert res.q[0] == pytest.approx(0.3, abs=1e-9)  # joint 1 plays no part in det J = sin q2
    assert res.converged and res.sigma_ratio < 1e-6 and ratio(arm, res.q) < 1e-6
    assert res.report.status == "singular" and res.report.kinds == ("elbow",)
    assert np.array_equal(res.path[0], [0.3, q2]) and np.array_equal(res.path[-1], res.q)
    assert len(res.path) <= 10  # Newton on σmin: quadratic once close
    # the path descends: σmin/σmax decreases along it
    assert np.all(np.diff([ratio(arm, q) for q in res.path]) < 0)


def test_puma_from_random_configurations_ends_singular_and_near():
    """Ten random regular Puma configurations: each ends singular with a named kind, and the
    distance travelled is on average no more than the distance to the wrist singularity reached
    by moving q5 alone (and never much more), far less than to random singular configurations."""
    puma = robots.load("puma560")
    rng = np.random.default_rng(12)
    travelled, wrist, random_singular = [], [], []
    for q0 in random_q(puma, rng, 10):
        res = nearest(puma, q0)
        assert res.converged and res.sigma_ratio < 1e-6 and ratio(puma, res.q) < 1e-6
        assert res.report.status == "singular" and res.report.kinds
        assert set(res.report.kinds) <= {"wrist", "elbow", "shoulder"}
        d_wrist = abs((q0[4] + math.pi / 2) % math.pi - math.pi / 2)
        d = np.linalg.norm(res.q - q0)
        assert d <= 2.0 * d_wrist + 0.05
        q_random = random_q(puma, rng)
        q_random[4] = 0.0  # a random wrist-singular configuration
        travelled.append(d)
        wrist.append(d_wrist)
        random_singular.append(np.linalg.norm(q_random - q0))
    assert np.mean(travelled) <= np.mean(wrist)
    assert np.mean(travelled) < 0.5 * np.mean(random_singular)


@pytest.mark.parametrize("name", ["trr", "ur5", "planar3", "stanford", "elbow3r"])
def test_other_robots_end_singular(name):
    """Including the TRR, whose smallest σ (the slide's, 1) never vanishes."""
    robot = robots.load(name)
    rng = np.random.default_rng(5)
    for q0 in random_q(robot, rng, 3):
        res = nearest(robot, q0)
        assert res.converged and ratio(robot, res.q) < 1e-6
        assert res.report.status == "singular"
        assert res.path.shape[1] == robot.dof and np.isfinite(res.path).all()


def test_already_singular_start_stays():
    puma = robots.load("puma560")
    q0 = np.array([0.1, 0.2, 0.3, 0.4, 0.0, 0.5])  # q5 = 0: wrist singular
    res = nearest(puma, q0)
    assert len(res.path) == 1 and np.array_equal(res.q, q0) and "wrist" in res.report.kinds


@pytest.mark.parametrize(
    ("kwargs", "error", "word"),
    [
        (dict(q0=[0.0]), ConfigurationError, "q0"),
        (dict(max_iterations=-1), OptionError, "max_iterations"),
        (dict(tol=0.0), OptionError, "tol"),
        (dict(tol=2.0), OptionError, "tol"),
    ],
)
def test_bad_inputs(kwargs, error, word):
    puma = robots.load("puma560")
    q0 = kwargs.pop("q0", puma.home)
    with pytest.raises(error, match=word) as info:
        nearest(puma, q0, **kwargs)
    assert isinstance(info.value, JacobianLabError)


def test_redundant_arm_descends_without_blowing_up():
    """Panda: the singular set has codimension 2; the descent lowers σmin/σmax a lot (it may not
    reach the tolerance: a documented limitation), and stays finite."""
    panda = robots.load("panda")
    for q0 in random_q(panda, np.random.default_rng(5), 3):
        res = nearest(panda, q0, max_iterations=60)
        assert np.isfinite(res.path).all()
        assert res.sigma_ratio < 1e-2 * ratio(panda, q0)
        assert res.sigma_ratio == pytest.approx(ratio(panda, res.q), rel=1e-6)
        assert res.converged == (res.sigma_ratio < 1e-6)
