"""Measures of J (singular values, manipulability, conditioning, ellipsoids), inverses and singularities."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fakes import random_q
from hypothesis import given
from hypothesis import strategies as st

import robots
from kinematics import (
    ArrayError,
    ConfigurationError,
    OptionError,
    analytic_jacobian,
    assess,
    condition_number,
    dls,
    euler_angles,
    euler_rate_matrix,
    fk,
    force_ellipsoid,
    jacobian,
    joint_frames,
    link_frames,
    manipulability,
    null_space,
    nullspace_projector,
    pinv,
    rank,
    select_rows,
    singular_values,
    solve_rates,
    task_rows,
    velocity_ellipsoid,
)

NAMES = robots.names()
ROBOTS = {name: robots.load(name) for name in NAMES}
seeds = st.integers(min_value=0, max_value=2**32 - 1)


@pytest.mark.parametrize("name", NAMES)
@given(seed=seeds)
def test_measures_agree_with_their_definitions(name, seed):
    robot = ROBOTS[name]
    J = jacobian(robot, random_q(robot, np.random.default_rng(seed)))
    for part in ("linear", "angular", "planar", "full", task_rows(robot)):
        Js = select_rows(J, part)
        s = singular_values(J, part)
        np.testing.assert_allclose(
            s, np.sqrt(np.clip(np.sort(np.linalg.eigvalsh(Js.T @ Js))[::-1][: len(s)], 0, None)), atol=1e-6
        )
        if Js.shape[0] <= Js.shape[1]:
            scale = max(1.0, np.abs(Js).max()) ** (2 * Js.shape[0])
            assert manipulability(J, part) ** 2 == pytest.approx(np.linalg.det(Js @ Js.T), abs=1e-12 * scale)
        else:
            assert manipulability(J, part) == 0.0
        c = condition_number(J, part)
        if rank(J, part) < min(Js.shape):
            assert c == math.inf
        elif Js.shape[0] <= Js.shape[1]:
            assert c == pytest.approx(np.linalg.cond(Js), rel=1e-9)


def test_planar_2r_singularity_measures():
    robot = ROBOTS["planar2"]
    J = jacobian(robot, [0.4, 0.0])  # stretched out: det J = a1 a2 sin q2 = 0
    assert condition_number(J, "planar") == math.inf
    assert rank(J, "linear") == 1
    assert manipulability(J, (0, 1)) == pytest.approx(0.0, abs=1e-12)
    a1, a2 = robot.dh[0].a, robot.dh[1].a
    J = jacobian(robot, [0.4, 1.0])
    assert manipulability(J, (0, 1)) == pytest.approx(a1 * a2 * math.sin(1.0), rel=1e-12)


@pytest.mark.parametrize("name", NAMES)
def test_velocity_ellipsoid_is_the_image_of_the_unit_ball(name):
    """Semi-axes σᵢ uᵢ are images of right singular vectors; random unit rates land inside."""
    robot = ROBOTS[name]
    rng = np.random.default_rng(5)
    J = jacobian(robot, random_q(robot, rng))
    E = velocity_ellipsoid(J, "linear")
    assert np.allclose(E.axes.T @ E.axes, np.eye(3)) and np.linalg.det(E.axes) == pytest.approx(1.0)
    assert np.all(np.diff(E.radii) <= 1e-12)
    for _ in range(200):
        qd = rng.normal(size=robot.dof)
        v = J[:3] @ (qd / np.linalg.norm(qd))
        coords = E.axes.T @ v  # components along the semi-axes
        with np.errstate(divide="ignore", invalid="ignore"):
            inside = np.sum(np.where(E.radii > 1e-12, (coords / E.radii) ** 2, 0.0))
        assert inside <= 1 + 1e-9
        assert np.all(np.abs(coords[E.radii <= 1e-12]) < 1e-9)  # nothing leaves a flat direction
    # The longest semi-axis is reached: ‖J v1‖ = σ1 along u1.
    _, s, Vt = np.linalg.svd(J[:3])
    assert np.linalg.norm(J[:3] @ Vt[0]) == pytest.approx(E.radii[0])
    assert abs(E.axes[:, 0] @ (J[:3] @ Vt[0])) == pytest.approx(s[0])


def test_ellipsoids_at_a_singularity_are_flat_not_nan():
    robot = ROBOTS["planar2"]
    J = jacobian(robot, [0.3, 0.0])
    E = velocity_ellipsoid(J, "linear")
    assert np.all(np.isfinite(E.radii)) and np.isfinite(E.axes).all()
    assert np.sum(E.radii > 1e-9) == 1  # a segment: only one direction of motion left
    F = force_ellipsoid(J, "linear")
    assert np.isinf(F.radii).sum() == 2 and np.all(F.capped(5.0).radii <= 5.0)
    # The velocity semi-axis that survives is perpendicular to the stretched arm (the x axis rotated by q1).
    u = E.axes[:, 0]
    assert abs(u @ [math.cos(0.3), math.sin(0.3), 0]) < 1e-9


def test_force_ellipsoid_is_dual_to_velocity():
    robot = ROBOTS["puma560"]
    J = jacobian(robot, random_q(robot, np.random.default_rng(1)))
    V, F = velocity_ellipsoid(J), force_ellipsoid(J)
    np.testing.assert_allclose(V.radii * F.radii, 1.0)
    np.testing.assert_allclose(np.abs(V.axes.T @ F.axes), np.eye(3), atol=1e-12)


@pytest.mark.parametrize("name", ["planar3", "panda", "iiwa14"])
def test_redundant_null_space_motion_leaves_the_tool_still(name):
    robot = ROBOTS[name]
    rng = np.random.default_rng(2)
    J = jacobian(robot, random_q(robot, rng))
    Jt = select_rows(J, task_rows(robot))
    N = null_space(J, task_rows(robot))
    assert N.shape == (robot.dof, robot.dof - Jt.shape[0])
    np.testing.assert_allclose(Jt @ N, 0, atol=1e-10)
    P = nullspace_projector(Jt)
    qd0 = rng.normal(size=robot.dof)
    np.testing.assert_allclose(Jt @ (P @ qd0), 0, atol=1e-10)
    np.testing.assert_allclose(P @ P, P, atol=1e-10)


@given(seed=seeds)
def test_pinv_and_dls(seed):
    rng = np.random.default_rng(seed)
    J = rng.normal(size=(6, 7))
    Jp = pinv(J)
    np.testing.assert_allclose(J @ Jp @ J, J, atol=1e-9)
    np.testing.assert_allclose(Jp, np.linalg.pinv(J), atol=1e-9)
    lam = 0.1
    np.testing.assert_allclose(dls(J, lam), J.T @ np.linalg.inv(J @ J.T + lam**2 * np.eye(6)), atol=1e-9)
    # DLS rates stay bounded at a singularity: ‖dls(J)‖ ≤ 1 / (2λ).
    Js = J.copy()
    Js[5] = Js[4]
    assert np.linalg.norm(dls(Js, lam), 2) <= 1 / (2 * lam) + 1e-9


def test_course_trr_inverse_is_pinv():
    robot = ROBOTS["trr"]
    J = jacobian(robot, [5.0, math.radians(60), math.radians(-15)])[:3]
    qd = pinv(J) @ np.array([17.256, -20.13, 0.5])
    np.testing.assert_allclose(qd, [0.5, math.pi / 2, math.pi / 4], atol=2e-3)


@pytest.mark.parametrize("name", NAMES)
def test_named_configurations_are_assessed_as_tagged(name):
    robot = ROBOTS[name]
    for cfg in robot.configurations:
        report = assess(robot, cfg.q)
        assert np.isfinite(report.sigma_min) and np.isfinite(report.lost_twist).all()
        if cfg.singular:
            assert report.status == "singular", (name, cfg.name, report)
            assert report.condition == math.inf
            J = jacobian(robot, cfg.q)
            rows = list(task_rows(robot))
            # The lost direction is (nearly) unreachable: no joint rate produces motion along it.
            assert np.abs(report.lost_twist[rows] @ J[rows]).max() < 1e-8
            if cfg.singular in ("wrist", "elbow", "shoulder"):
                assert cfg.singular in report.kinds, (name, cfg.name, report.kinds)
        else:
            assert report.status != "singular", (name, cfg.name)


def test_puma_singularity_kinds():
    robot = ROBOTS["puma560"]
    q = np.array([0.3, -0.4, 0.5, 0.7, 0.0, 0.2])  # q5 = 0: wrist axes 4 and 6 line up
    assert assess(robot, q).kinds == ("wrist",)
    assert assess(robot, q).text() == "singular: wrist"
    q = np.array([0.3, -0.4, 0.5, 0.7, 0.9, 0.2])
    assert assess(robot, q).status == "regular" and assess(robot, q).text() == "regular"


# ------------------------------------------------------------ bad arguments are named
J_PUMA = jacobian(ROBOTS["puma560"], [0.1, 0.2, 0.3, 0.4, 0.5, 0.6])
PARTS = "part must be one of 'full', 'linear', 'angular', 'planar'"


@pytest.mark.parametrize(
    ("call", "error", "message"),
    [
        (lambda: select_rows(J_PUMA, "position"), OptionError, f"{PARTS}, got 'position'"),
        (lambda: manipulability(J_PUMA, "Linear"), OptionError, f"{PARTS}, got 'Linear'"),
        (lambda: singular_values(J_PUMA, 3), OptionError, f"{PARTS} or row indices, got 3"),
        (
            lambda: rank(J_PUMA, (0, 6)),
            OptionError,
            r"rows of J must be distinct indices 0…5 .*, got \(0, 6\)",
        ),
        (lambda: rank(J_PUMA, (1, 1)), OptionError, r"distinct indices 0…5 .*, got \(1, 1\)"),
        (lambda: rank(J_PUMA, ()), OptionError, r"distinct indices 0…5 .*, got \(\)"),
        (lambda: rank(J_PUMA, (0, True)), OptionError, r"distinct indices 0…5 .*, got \(0, True\)"),
        (
            lambda: condition_number(J_PUMA, "linear", rtol=-1e-9),
            OptionError,
            r"rtol must be a number in \[0, 1\), got -1e-09",
        ),
        (lambda: rank(J_PUMA, rtol=math.nan), OptionError, r"rtol must be a number in \[0, 1\), got nan"),
        (
            lambda: force_ellipsoid(J_PUMA, rtol="0"),
            OptionError,
            r"rtol must be a number in \[0, 1\), got '0'",
        ),
        (
            lambda: velocity_ellipsoid(J_PUMA, "full"),
            OptionError,
            "ellipsoids need three rows of J .*, got 'full'",
        ),
        (
            lambda: velocity_ellipsoid(np.stack([J_PUMA] * 2)),
            ArrayError,
            r"one Jacobian \(6, n\), not a batch",
        ),
        (lambda: null_space(np.stack([J_PUMA] * 2)), ArrayError, "null_space takes one Jacobian"),
        (
            lambda: singular_values(J_PUMA[:5]),
            ArrayError,
            r"J should have shape \(6, n\) or \(N, 6, n\), got \(5, 6\)",
        ),
        (
            lambda: singular_values(np.where(np.eye(6, dtype=bool), np.nan, J_PUMA)),
            ArrayError,
            "J contains NaN or infinity",
        ),
        (
            lambda: singular_values(J_PUMA.astype(complex)),
            ArrayError,
            "J must hold ints or floats, got dtype complex128",
        ),
        (lambda: dls(J_PUMA, -0.1), OptionError, "damping must be a finite number ≥ 0, got -0.1"),
        (lambda: dls(J_PUMA, math.inf), OptionError, "damping must be a finite number ≥ 0, got inf"),
        (
            lambda: solve_rates(J_PUMA, np.ones(6), damping="0.1"),
            OptionError,
            "damping must be a finite number ≥ 0, got '0.1'",
        ),
        (lambda: solve_rates(J_PUMA, np.ones(3)), ArrayError, r"v must hold 6 numbers \(one per row of J\)"),
        (lambda: solve_rates(J_PUMA, [1, 2, 3, 4, 5, math.nan]), ArrayError, "v contains NaN or infinity"),
        (lambda: pinv([[1.0, "a"]]), ArrayError, "J must hold ints or floats, got dtype <U32"),
        (lambda: pinv(np.ones(3)), ArrayError, r"J should have shape \(m, n\) or \(N, m, n\), got \(3,\)"),
        (lambda: nullspace_projector(np.full((2, 2), np.inf)), ArrayError, "J contains NaN or infinity"),
        (
            lambda: analytic_jacobian(ROBOTS["puma560"], np.zeros(6), "xyz"),
            OptionError,
            "Euler convention must be one of 'zyx', 'zyz', got 'xyz'",
        ),
        (lambda: euler_angles(np.full((3, 3), np.nan)), ArrayError, "R contains NaN or infinity"),
        (lambda: euler_angles(np.eye(2)), ArrayError, r"R must be numbers of shape \(3, 3\) or \(4, 4\)"),
        (lambda: euler_rate_matrix([0.0, 0.0]), ArrayError, r"angles must be numbers of shape \(3,\)"),
        (
            lambda: assess(ROBOTS["puma560"], np.zeros(6), J=J_PUMA[:, :5]),
            ArrayError,
            r"J should have shape \(6, 6\) for robot 'puma560', got \(6, 5\)",
        ),
        (
            lambda: assess(ROBOTS["puma560"], np.zeros((2, 6))),
            ConfigurationError,
            r"assess takes one configuration \(6,\)",
        ),
        (
            lambda: assess(ROBOTS["puma560"], np.zeros(6), near_condition=0.5),
            OptionError,
            "near_condition must be a number > 1, got 0.5",
        ),
    ],
)
def test_bad_arguments_raise_project_errors_naming_them(call, error, message):
    with pytest.raises(error, match=message):
        call()


def test_rows_given_as_indices_select_those_rows():
    np.testing.assert_array_equal(select_rows(J_PUMA, (5, 0)), J_PUMA[[5, 0]])
    np.testing.assert_array_equal(select_rows(J_PUMA, np.array([3, 4, 5])), J_PUMA[3:])


@pytest.mark.parametrize("name", robots.names())
def test_measures_from_one_svd_equal_the_separate_measures(name):
    """measures() (one SVD) gives what singular_values, manipulability, rank and condition_number give,
    regular and singular; condition_of on a velocity ellipsoid's radii is condition_number of its rows."""
    from kinematics.analysis import condition_of, measures

    robot = robots.load(name)
    configurations = [c.q for c in robot.configurations] + list(
        np.random.default_rng(7).uniform(-2, 2, size=(4, robot.dof))
    )
    for q in configurations:
        J = jacobian(robot, q)
        for part in (task_rows(robot), "linear", "angular", "full"):
            m = measures(J, part)
            np.testing.assert_array_equal(m.sigma, singular_values(J, part))
            assert m.manipulability == pytest.approx(manipulability(J, part), rel=1e-12, abs=0)
            assert m.rank == rank(J, part)
            assert m.condition == pytest.approx(condition_number(J, part), rel=1e-12)
        assert condition_of(velocity_ellipsoid(J, "linear").radii) == pytest.approx(
            condition_number(J, "linear"), rel=1e-12
        )


@pytest.mark.parametrize("name", robots.names())
def test_frames_and_jacobian_is_the_three_calls(name):
    from kinematics.numeric import frames_and_jacobian

    robot = robots.load(name)
    for q in np.random.default_rng(8).uniform(-2, 2, size=(3, robot.dof)):
        L, W, J = frames_and_jacobian(robot, q)
        np.testing.assert_array_equal(L, link_frames(robot, q))
        np.testing.assert_array_equal(W, joint_frames(robot, q))
        np.testing.assert_array_equal(J, jacobian(robot, q))


@pytest.mark.parametrize("convention", ["zyx", "zyz"])
def test_euler_rotation_inverts_euler_angles(convention):
    from kinematics.analytic_jacobian import euler_rotation

    for R in (fk(ROBOTS["puma560"], q)[:3, :3] for q in np.random.default_rng(9).uniform(-2, 2, (8, 6))):
        np.testing.assert_allclose(euler_rotation(euler_angles(R, convention), convention), R, atol=1e-12)
