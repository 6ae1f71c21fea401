"""One pass over a batch (kinematics.batch): tool poses, J, J̇ and the measures against the
single-configuration functions, J̇ against finite differences of J, the measures against NumPy's
SVD, for every library robot and the URDF test files (mimic and prismatic joints, |q| ~ 1e16),
and the errors of bad input."""

from __future__ import annotations

import numpy as np
import pytest
from fakes import random_q
from kinematics_helpers import chains_under_test, generated_code_set_aside

import robots
from kinematics import (
    ConfigurationError,
    OptionError,
    Robot,
    analysis,
    batch,
    fk,
    jacobian,
    jacobian_dot,
    task_rows,
)
from kinematics.compiled import MAX_AXES
from kinematics.kernel import batch_scan_rates, kernel

ROBOTS: dict[str, Robot] = chains_under_test()
NAMES = list(ROBOTS)


def test_the_fixtures_hold_mimic_and_prismatic_joints_of_real_files():
    real = [r for r in ROBOTS.values() if r.urdf_path is not None]
    assert any(len(r.axes) > r.dof or any(a.multiplier != 1.0 for a in r.axes) for r in real)
    assert any("prismatic" in r.joint_types for r in real)
    assert any(len(r.axes) > r.dof for r in ROBOTS.values())


def _configurations(robot: Robot, size: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Random configurations (the first all zeros, often singular; the next three with revolute
    angles ~1e16) and joint rates."""
    rng = np.random.default_rng(seed)
    Q = random_q(robot, rng, size=size)
    Q[0] = 0.0
    Q[1:4] *= np.where([k == "revolute" for k in robot.joint_types], 1e16, 1.0)
    return Q, rng.normal(size=Q.shape)


@pytest.mark.parametrize("name", NAMES)
def test_batch_equals_the_single_configuration_functions(name):
    """T, J, J̇ and σ, w, κ, rank of every row equal fk, jacobian, jacobian_dot and
    analysis.measures of that row alone, across chunk boundaries (chunk 7 of 25)."""
    robot = ROBOTS[name]
    Q, U = _configurations(robot, 25, seed=11)
    b = batch(robot, Q, U, chunk=7)
    k = min(len(task_rows(robot)), robot.dof)
    assert b.T.shape == (25, 4, 4) and b.J.shape == b.Jdot.shape == (25, 6, robot.dof)
    assert b.sigma.shape == (25, k) and b.w.shape == b.kappa.shape == b.rank.shape == (25,)
    assert b.rows == task_rows(robot)
    for i in range(25):
        np.testing.assert_allclose(b.T[i], fk(robot, Q[i]), atol=1e-12)
        np.testing.assert_allclose(b.J[i], jacobian(robot, Q[i]), atol=1e-12)
        np.testing.assert_allclose(b.Jdot[i], jacobian_dot(robot, Q[i], U[i]), atol=1e-11)
        m = analysis.measures(jacobian(robot, Q[i]), b.rows)
        np.testing.assert_allclose(b.sigma[i], m.sigma, atol=1e-12)
        assert b.w[i] == pytest.approx(m.manipulability, rel=1e-9, abs=1e-12)
        assert b.rank[i] == m.rank
        assert b.kappa[i] == pytest.approx(m.condition, rel=1e-6)  # also inf == inf
        R = b.T[i, :3, :3]
        assert np.abs(R.T @ R - np.eye(3)).max() < 1e-12  # rigid at |q| ~ 1e16 too
    # The batched J̇ of jacobian_dot gives the same numbers; the chunk size changes nothing (to a
    # last bit: a vectorised tan may round a lane differently from the tail of a chunk).
    np.testing.assert_allclose(jacobian_dot(robot, Q, U), b.Jdot, atol=1e-14)
    whole = batch(robot, Q, U)
    for field in ("T", "J", "Jdot", "sigma", "w"):
        np.testing.assert_allclose(getattr(whole, field), getattr(b, field), atol=1e-14)


@pytest.mark.parametrize("name", NAMES)
def test_jdot_is_the_derivative_of_j_along_the_rates(name):
    """J̇(q, q̇) against the central difference (J(q + h q̇) − J(q − h q̇)) / 2h of the batched J; the
    generated code (batched and single) against the NumPy scan's J̇ (vectorised over the axes) and
    jacobian_dot's NumPy path (from the joint frames' velocities), also at |q| ~ 1e16."""
    robot = ROBOTS[name]
    rng = np.random.default_rng(4)
    Q, U = random_q(robot, rng, size=12), rng.normal(size=(12, robot.dof))
    h = 1e-6
    fd = (jacobian(robot, Q + h * U) - jacobian(robot, Q - h * U)) / (2 * h)
    found = batch(robot, Q, U).Jdot
    scale = max(1.0, np.abs(fd).max())
    np.testing.assert_allclose(found, fd, atol=1e-7 * scale)
    _, J, Jd = batch_scan_rates(kernel(robot), Q, U)
    np.testing.assert_allclose(found, Jd, atol=1e-12 * scale)
    Q[:3] *= np.where([k == "revolute" for k in robot.joint_types], 1e16, 1.0)
    with generated_code_set_aside(robot):  # jacobian_dot's NumPy path: a third derivation
        scan = [jacobian_dot(robot, Q[i], U[i]) for i in range(12)]
    for i in range(12):
        np.testing.assert_allclose(jacobian_dot(robot, Q[i], U[i]), scan[i], atol=1e-12 * scale)


def test_measures_against_numpy_svd_of_the_rows():
    """σ is NumPy's SVD of the chosen rows (largest first), w their product, κ σmax/σmin; with
    more rows than joints, w = 0 and κ = ∞; exactly singular configurations give κ = ∞, rank < k."""
    robot = robots.load("puma560")
    Q, _ = _configurations(robot, 40, seed=2)
    Q[5] = [0.3, -0.4, 0.2, 0.5, 0.0, 0.1]  # wrist singular: q5 = 0
    for rows in ("linear", "angular", "full", (0, 1, 5)):
        b = batch(robot, Q, rows=rows)
        selected = list(analysis.part_rows(rows))
        for i in range(40):
            s = np.linalg.svd(jacobian(robot, Q[i])[selected], compute_uv=False)
            np.testing.assert_allclose(b.sigma[i], s, atol=1e-12)
            assert b.w[i] == pytest.approx(np.prod(s), rel=1e-9, abs=1e-13)
            if s[-1] > 1e-6:
                assert b.kappa[i] == pytest.approx(s[0] / s[-1], rel=1e-8)
    full = batch(robot, Q, rows="full")
    assert np.isinf(full.kappa[5]) and full.rank[5] == 5 and full.w[5] < 1e-14
    three = robots.load("planar3")
    b = batch(three, np.zeros((2, 3)), rows="full")
    assert b.sigma.shape == (2, 3) and np.all(b.w == 0.0) and np.all(np.isinf(b.kappa))


def test_qd_of_one_row_serves_every_configuration():
    robot = robots.load("panda")
    Q, U = _configurations(robot, 9, seed=3)
    one = batch(robot, Q, U[0])
    assert one.Jdot is not None
    np.testing.assert_allclose(one.Jdot, batch(robot, Q, np.repeat(U[:1], 9, axis=0)).Jdot, atol=1e-14)
    np.testing.assert_allclose(jacobian_dot(robot, Q, U[0]), one.Jdot, atol=1e-14)
    assert batch(robot, Q).Jdot is None


def test_a_chain_beyond_the_generated_code_takes_the_numpy_scan():
    """A chain longer than MAX_AXES has no generated code: its batch (the NumPy scan) still equals
    the single-configuration functions."""
    rows = [
        dict(
            joint="prismatic" if k % 7 == 3 else "revolute",
            a=0.05,
            alpha=0.3 * (k % 5 - 2),
            d=0.01 * k,
            theta=0.1,
        )
        for k in range(MAX_AXES + 4)
    ]
    robot = Robot.from_dh(rows, name="snake")
    assert kernel(robot).compiled is None
    Q, U = _configurations(robot, 5, seed=9)
    b = batch(robot, Q, U, chunk=2)
    for i in range(5):
        np.testing.assert_allclose(b.J[i], jacobian(robot, Q[i]), atol=1e-12)
        np.testing.assert_allclose(b.Jdot[i], jacobian_dot(robot, Q[i], U[i]), atol=1e-10)


def test_memory_is_bounded_by_the_chunk_not_the_batch():
    """Beyond its results, the peak memory of a batch (tracemalloc sees NumPy's buffers) is that of
    one chunk: 16 times more configurations raise it by their results only."""
    import tracemalloc

    robot = robots.load("panda")

    def extra(n: int) -> int:
        Q, U = _configurations(robot, n, seed=0)
        batch(robot, Q[:64], U[:64], chunk=256)  # generated code compiled outside the measure
        tracemalloc.start()
        try:
            b = batch(robot, Q, U, chunk=256)
            _, peak = tracemalloc.get_traced_memory()
        finally:
            tracemalloc.stop()
        assert b.Jdot is not None
        arrays = (b.T, b.J, b.Jdot, b.sigma, b.w, b.kappa, b.rank)
        return peak - sum(a.nbytes for a in arrays)

    small, large = extra(1_000), extra(16_000)
    assert large < small + 64 * 1024
    assert large < 16_000 * 6 * 7 * 8 / 4  # a quarter of the batch's J alone


@pytest.mark.parametrize(
    ("q", "qd", "options", "error", "message"),
    [
        (
            np.empty((0, 7)),
            None,
            {},
            ConfigurationError,
            r"q is an empty batch \(0, 7\); batch expects at least one",
        ),
        (
            np.zeros(7),
            None,
            {},
            ConfigurationError,
            r"q has shape \(7,\); batch expects configurations \(N, 7\)",
        ),
        (np.zeros((3, 6)), None, {}, ConfigurationError, r"q has shape \(3, 6\); robot 'panda' expects"),
        (np.zeros((2, 3, 7)), None, {}, ConfigurationError, r"q has shape \(2, 3, 7\)"),
        (
            np.zeros((3, 7)),
            np.zeros((4, 7)),
            {},
            ConfigurationError,
            r"qd has shape \(4, 7\); expected one row",
        ),
        (np.zeros((3, 7)), np.zeros((3, 6)), {}, ConfigurationError, r"qd has shape \(3, 6\)"),
        (np.zeros((3, 7)), [[np.nan] * 7] * 3, {}, ConfigurationError, r"qd contains NaN or infinity"),
        ([["a"] * 7], None, {}, ConfigurationError, r"q must hold ints or floats"),
        (np.zeros((3, 7)), None, {"rows": "world"}, OptionError, r"part must be one of"),
        (np.zeros((3, 7)), None, {"rows": (0, 0)}, OptionError, r"distinct indices"),
        (np.zeros((3, 7)), None, {"rtol": 2.0}, OptionError, r"rtol must be a number in \[0, 1\)"),
        (np.zeros((3, 7)), None, {"chunk": 0}, OptionError, r"chunk must be an int ≥ 1, got 0"),
        (np.zeros((3, 7)), None, {"chunk": 2.5}, OptionError, r"chunk must be an int ≥ 1, got 2.5"),
    ],
)
def test_bad_input_is_refused_naming_what_is_wrong(q, qd, options, error, message):
    with pytest.raises(error, match=message):
        batch(robots.load("panda"), q, qd, **options)


def test_jacobian_dot_of_mismatched_batches_names_both_shapes():
    robot = robots.load("panda")
    with pytest.raises(ConfigurationError, match=r"got q \(3, 7\) and qd \(2, 7\)"):
        jacobian_dot(robot, np.zeros((3, 7)), np.zeros((2, 7)))
    with pytest.raises(ConfigurationError, match=r"got q \(7,\) and qd \(2, 7\)"):
        jacobian_dot(robot, np.zeros(7), np.zeros((2, 7)))
