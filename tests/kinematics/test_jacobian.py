"""The geometric Jacobian, checked three independent ways for every library robot.

1. central finite differences of forward kinematics (position and orientation rows);
2. relations between frames: J_base = blockdiag(R, R) · J_tool;
3. batch results equal one-by-one results;
plus J̇ against finite differences of J along q̇, the analytic (Euler-rate)
Jacobian against finite differences of the Euler angles, the course's worked
numbers and closed forms.
"""

from __future__ import annotations

import gc
import math
import weakref

import mpmath
import numpy as np
import pytest
from fakes import random_q
from hypothesis import given
from hypothesis import strategies as st

import robots
from kinematics import (
    ConfigurationError,
    OptionError,
    RepresentationSingularityError,
    Robot,
    analytic_jacobian,
    euler_angles,
    fk,
    jacobian,
    jacobian_dot,
    joint_frames,
    link_frames,
)
from kinematics.transforms import rot_z, rotation_log, trans
from kinematics.urdf import robot_from_urdf_string, to_urdf

NAMES = robots.names()
ROBOTS = {name: robots.load(name) for name in NAMES}
seeds = st.integers(min_value=0, max_value=2**32 - 1)


def fd_jacobian(robot: Robot, q: np.ndarray, eps: float = 1e-6) -> np.ndarray:
    """Central differences of fk: linear rows from positions, angular rows from log(R+ R-ᵀ)."""
    J = np.empty((6, robot.dof))
    for i in range(robot.dof):
        dq = np.zeros(robot.dof)
        dq[i] = eps
        Tp, Tm = fk(robot, q + dq), fk(robot, q - dq)
        J[:3, i] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * eps)
        J[3:, i] = rotation_log(Tp[:3, :3] @ Tm[:3, :3].T) / (2 * eps)
    return J


def test_library_is_complete():
    expected = {
        "planar2",
        "planar3",
        "trr",
        "elbow3r",
        "scara",
        "stanford",
        "wrist",
        "puma560",
        "puma560_mdh",
        "ur5",
        "panda",
        "iiwa14",
    }
    assert expected <= set(NAMES)


@pytest.mark.parametrize("name", NAMES)
@given(seed=seeds)
def test_jacobian_matches_finite_differences(name, seed):
    robot = ROBOTS[name]
    q = random_q(robot, np.random.default_rng(seed))
    J = jacobian(robot, q)
    assert J.shape == (6, robot.dof)
    np.testing.assert_allclose(J, fd_jacobian(robot, q), atol=1e-6 * max(1.0, np.abs(J).max()))


@pytest.mark.parametrize("name", NAMES)
@given(seed=seeds)
def test_base_and_tool_frames_are_related_by_rotation(name, seed):
    robot = ROBOTS[name]
    q = random_q(robot, np.random.default_rng(seed))
    R = fk(robot, q)[:3, :3]
    J_tool = jacobian(robot, q, frame="tool")
    blockdiag = np.zeros((6, 6))
    blockdiag[:3, :3] = blockdiag[3:, 3:] = R
    np.testing.assert_allclose(jacobian(robot, q, frame="base"), blockdiag @ J_tool, atol=1e-12)


@pytest.mark.parametrize("name", NAMES)
def test_batch_equals_one_by_one(name):
    robot = ROBOTS[name]
    Q = random_q(robot, np.random.default_rng(7), size=5000)  # several chunks
    T, J, J_tool = fk(robot, Q), jacobian(robot, Q), jacobian(robot, Q, frame="tool")
    assert T.shape == (5000, 4, 4) and J.shape == (5000, 6, robot.dof)
    for i in (0, 1, 2047, 2048, 4999):
        np.testing.assert_allclose(T[i], fk(robot, Q[i]), atol=1e-12)
        np.testing.assert_allclose(J[i], jacobian(robot, Q[i]), atol=1e-12)
        np.testing.assert_allclose(J_tool[i], jacobian(robot, Q[i], frame="tool"), atol=1e-12)


@pytest.mark.parametrize("name", NAMES)
@given(seed=seeds)
def test_jacobian_dot_matches_finite_differences_along_qd(name, seed):
    robot = ROBOTS[name]
    rng = np.random.default_rng(seed)
    q, qd = random_q(robot, rng), rng.normal(size=robot.dof)
    eps = 1e-6
    expected = (jacobian(robot, q + eps * qd) - jacobian(robot, q - eps * qd)) / (2 * eps)
    np.testing.assert_allclose(
        jacobian_dot(robot, q, qd), expected, atol=2e-6 * max(1, np.abs(expected).max())
    )


@pytest.mark.parametrize("convention", ["zyx", "zyz"])
@pytest.mark.parametrize("name", ["puma560", "ur5", "panda", "stanford"])
@given(seed=seeds)
def test_analytic_jacobian_matches_euler_angle_differences(name, convention, seed):
    robot = ROBOTS[name]
    q = random_q(robot, np.random.default_rng(seed))
    try:
        JA = analytic_jacobian(robot, q, convention)
    except RepresentationSingularityError:
        return  # measure-zero set; covered by the dedicated test below
    eps = 1e-7
    for i in range(robot.dof):
        dq = np.zeros(robot.dof)
        dq[i] = eps
        dphi = euler_angles(fk(robot, q + dq)[:3, :3], convention) - euler_angles(
            fk(robot, q - dq)[:3, :3], convention
        )
        dphi = (dphi + np.pi) % (2 * np.pi) - np.pi  # unwrap across ±π
        np.testing.assert_allclose(JA[3:, i], dphi / (2 * eps), atol=1e-4 * max(1, np.abs(JA[3:]).max()))
    np.testing.assert_array_equal(JA[:3], jacobian(robot, q)[:3])


def test_analytic_jacobian_reports_representation_singularity():
    robot = ROBOTS["wrist"]
    # Find a configuration whose tool z axis is the base z axis: ZYZ θ = 0.
    q = np.zeros(robot.dof)
    R = fk(robot, q)[:3, :3]
    if abs(R[2, 2]) < 1 - 1e-9:
        pytest.skip("wrist home is not aligned with z")  # pragma: no cover - data dependent
    with pytest.raises(RepresentationSingularityError, match="ZYZ"):
        analytic_jacobian(robot, q, "zyz")
    # ZYX pitch = 90°: a planar arm in the base x-y plane never reaches it, a tilted tool does.
    tilt = Robot.from_dh(
        [dict(joint="revolute", a=0.0, alpha=0.0, d=0.0, theta=0.0)],
        tool=np.array([[0, 0, 1, 0], [0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1.0]]),
    )
    with pytest.raises(RepresentationSingularityError, match="pitch"):
        analytic_jacobian(tilt, [0.3], "zyx")


def test_trr_course_example():
    """The course's worked TRR example: q = [5 m, 60°, −15°], q̇ = [0.5 m/s, 90°/s, 45°/s]."""
    robot = ROBOTS["trr"]
    q = np.array([5.0, math.radians(60), math.radians(-15)])
    qd = np.array([0.5, math.pi / 2, math.pi / 4])
    J = jacobian(robot, q)
    np.testing.assert_allclose(J[:3], [[0, 8.157, 5.657], [0, -9.987, -5.657], [1, 0, 0]], atol=5e-4)
    np.testing.assert_allclose(J[:3] @ qd, [17.256, -20.13, 0.500], atol=5e-3)
    # The course's inverse: J⁻¹ = [[0, 0, 1], [−0.5464, −0.5464, 0], [0.9647, 0.7879, 0]].
    np.testing.assert_allclose(
        np.linalg.inv(J[:3]), [[0, 0, 1], [-0.5464, -0.5464, 0], [0.9647, 0.7879, 0]], atol=5e-4
    )


@given(q1=st.floats(-3, 3), q2=st.floats(-3, 3))
def test_planar_2r_closed_form_and_determinant(q1, q2):
    robot = ROBOTS["planar2"]
    a1, a2 = robot.dh[0].a, robot.dh[1].a
    J = jacobian(robot, [q1, q2])
    s1, c1, s12, c12 = math.sin(q1), math.cos(q1), math.sin(q1 + q2), math.cos(q1 + q2)
    expected = [[-a1 * s1 - a2 * s12, -a2 * s12], [a1 * c1 + a2 * c12, a2 * c12]]
    np.testing.assert_allclose(J[:2], expected, atol=1e-12)
    np.testing.assert_allclose(J[5], [1, 1], atol=1e-12)
    assert np.linalg.det(J[:2]) == pytest.approx(a1 * a2 * math.sin(q2), abs=1e-12)


@pytest.mark.parametrize("name", NAMES)
def test_urdf_written_from_dh_robot_agrees(name):
    robot = ROBOTS[name]
    again = robot_from_urdf_string(to_urdf(robot))
    assert again.joint_names == robot.joint_names and again.joint_types == robot.joint_types
    Q = random_q(robot, np.random.default_rng(3), size=20)
    np.testing.assert_allclose(fk(again, Q), fk(robot, Q), atol=1e-12)
    np.testing.assert_allclose(jacobian(again, Q), jacobian(robot, Q), atol=1e-12)


@pytest.mark.parametrize("name", NAMES)
def test_frames_are_consistent(name):
    robot = ROBOTS[name]
    q = random_q(robot, np.random.default_rng(11))
    W, L = joint_frames(robot, q), link_frames(robot, q)
    assert W.shape == (len(robot.axes), 4, 4) and L.shape == (len(robot.axes) + 2, 4, 4)
    np.testing.assert_allclose(L[-1], fk(robot, q), atol=1e-12)
    for k, ax in enumerate(robot.axes):
        # The joint frame is the previous link frame moved by T_parent_joint.
        np.testing.assert_allclose(W[k], L[k] @ ax.T_parent_joint, atol=1e-12)


def test_dh_frames_match_textbook_products():
    """Link frames of a DH robot are base · A1 ⋯ Ak with A from the textbook formulas."""
    from kinematics.transforms import rot_x, rot_z, trans

    rows = [
        dict(joint="revolute", a=0.3, alpha=0.5, d=0.2, theta=0.1),
        dict(joint="prismatic", a=0.1, alpha=-1.0, d=0.4, theta=0.7),
    ]
    q = np.array([0.8, 0.25])
    for convention in ("standard", "modified"):
        robot = Robot.from_dh(rows, convention)
        T = np.eye(4)
        for k, r in enumerate(rows):
            th = r["theta"] + (q[k] if r["joint"] == "revolute" else 0)
            d = r["d"] + (q[k] if r["joint"] == "prismatic" else 0)
            if convention == "standard":
                A = rot_z(th) @ trans(z=d) @ trans(x=r["a"]) @ rot_x(r["alpha"])
            else:
                A = rot_x(r["alpha"]) @ trans(x=r["a"]) @ rot_z(th) @ trans(z=d)
            T = T @ A
            np.testing.assert_allclose(link_frames(robot, q)[k + 1], T, atol=1e-12)
        np.testing.assert_allclose(fk(robot, q), T, atol=1e-12)


def test_limits_do_not_bound_the_maths():
    robot = ROBOTS["puma560"]
    q = robot.qlim[1] + 1.0  # beyond every upper limit
    assert np.isfinite(fk(robot, q)).all() and np.isfinite(jacobian(robot, q)).all()


def test_mimic_joint_sums_columns():
    """A URDF mimic joint drives an extra axis; its column contribution is scaled by the multiplier."""
    urdf = """<robot name="m">
      <link name="a"/><link name="b"/><link name="c"/>
      <joint name="j1" type="revolute"><parent link="a"/><child link="b"/>
        <origin xyz="0 0 0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
      <joint name="j2" type="revolute"><parent link="b"/><child link="c"/>
        <origin xyz="1 0 0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
        <mimic joint="j1" multiplier="2" offset="0.1"/></joint>
    </robot>"""
    robot = robot_from_urdf_string(urdf, tip_link="c")
    assert robot.dof == 1 and len(robot.axes) == 2
    q = np.array([0.3])
    np.testing.assert_allclose(jacobian(robot, q), fd_jacobian(robot, q), atol=1e-7)
    # Tool at the origin of c: p = (cos q, sin q) → ∂p/∂q = (−sin q, cos q) (the mimic axis passes through p).
    np.testing.assert_allclose(jacobian(robot, q)[:2, 0], [-math.sin(0.3), math.cos(0.3)], atol=1e-12)
    np.testing.assert_allclose(jacobian(robot, q)[5, 0], 3.0)
    again = robot_from_urdf_string(to_urdf(robot))
    np.testing.assert_allclose(jacobian(again, q), jacobian(robot, q), atol=1e-12)


# ------------------------------------------------------------- huge angles and hostile q
def exact_reduction(q: np.ndarray) -> np.ndarray:
    """q modulo 2π computed with 60 significant digits (mpmath), independent of NumPy's reduction."""
    mpmath.mp.dps = 60
    return np.array([float(mpmath.fmod(mpmath.mpf(float(v)), 2 * mpmath.pi)) for v in q])


@pytest.mark.parametrize("name", ["puma560", "panda", "stanford", "scara"])
@pytest.mark.parametrize("scale", [1e16, 3.7e17, -1e18])
def test_fk_stays_rigid_and_exact_at_huge_angles(name, scale):
    """|q| ~ 1e16: R stays a rotation (it reached ‖RᵀR − I‖ = 1.5 when sin was formed as cos(θ − π/2)),
    and it is the pose at q mod 2π, reduced exactly: single and batched kernels, J and link frames."""
    robot = ROBOTS[name]
    rng = np.random.default_rng(7)
    revolute = np.array([k == "revolute" for k in robot.joint_types])
    q = np.where(revolute, scale * rng.uniform(0.5, 1.0, robot.dof), 0.2)
    q_small = np.where(revolute, exact_reduction(q), q)
    for T in (fk(robot, q), fk(robot, q[None])[0], link_frames(robot, q)[-1]):
        R = T[:3, :3]
        assert np.abs(R.T @ R - np.eye(3)).max() < 1e-12
        np.testing.assert_allclose(T, fk(robot, q_small), atol=1e-12)
    np.testing.assert_allclose(jacobian(robot, q), jacobian(robot, q_small), atol=1e-12)
    np.testing.assert_allclose(jacobian(robot, q[None])[0], jacobian(robot, q_small), atol=1e-12)


ARM = Robot.from_dh(
    [
        dict(joint="revolute", a=1.0, alpha=0.0, d=0.0, theta=0.0, name="shoulder"),
        dict(joint="prismatic", a=0.0, alpha=0.0, d=0.0, theta=0.0, name="slide"),
    ],
    name="arm",
)


@pytest.mark.parametrize(
    ("q", "message"),
    [
        (["0.1", "0.2"], r"q must hold ints or floats, got strings: \['0.1', '0.2'\]"),
        ([b"1", b"2"], "q must hold ints or floats, got bytes"),
        ([0.1 + 1j, 0.2], "q must hold ints or floats, got complex numbers"),
        (np.array([0.1, 0.2], dtype=object), "q must hold ints or floats, got Python objects"),
        ([True, False], "q must hold ints or floats, got bools"),
        ([None, 0.2], "q must hold ints or floats, got Python objects"),
        ([10**400, 0.2], "q must hold ints or floats, got Python objects"),
        ([[0.1, 0.2], [0.3]], r"q must be an array of numbers, got \[\[0.1, 0.2\], \[0.3\]\]"),
        ({"shoulder": 0.1}, "q must hold ints or floats, got Python objects"),
        ([0.1, 0.2, 0.3], r"q has shape \(3,\); robot 'arm' expects \(2,\) or \(N, 2\)"),
        (0.1, r"q has shape \(\); robot 'arm' expects"),
        ([0.1, math.inf], r"q contains NaN or infinity \(joint 'slide': inf\)"),
        ([[0.0, 0.0], [math.nan, 0.0]], r"q contains NaN or infinity \(joint 'shoulder': nan\)"),
        ([0.0, 2e15], r"q: joint 'slide' value 2e\+15 m is out of range; expected \|value\| ≤ 1e\+15 m"),
        (
            [-2e18, 0.0],
            r"q: joint 'shoulder' value -2e\+18 rad is out of range; expected \|value\| ≤ 1e\+18 rad",
        ),
    ],
)
def test_hostile_q_is_refused_with_the_reason(q, message):
    for fn in (fk, jacobian, link_frames, joint_frames):
        with pytest.raises(ConfigurationError, match=message):
            fn(ARM, q)
    with pytest.raises(ConfigurationError, match=message.replace("q ", "qd ", 1).replace("q:", "qd:", 1)):
        jacobian_dot(ARM, [0.0, 0.0], q)


def test_values_just_inside_the_bounds_are_accepted():
    q = np.array([1e18, 1e15])
    T = fk(ARM, q)
    assert np.isfinite(T).all() and np.isfinite(jacobian(ARM, q)).all()
    assert T[2, 3] == pytest.approx(1e15)  # the slide moves along z by q2
    assert fk(ARM, np.zeros((0, 2))).shape == (0, 4, 4)  # an empty batch is a batch


@pytest.mark.parametrize("frame", ["world", "Base", "", None, 0, np.array(["base"])])
def test_unknown_frames_name_the_valid_ones(frame):
    for call in (
        lambda: jacobian(ARM, [0.0, 0.0], frame=frame),
        lambda: jacobian_dot(ARM, [0.0, 0.0], [1.0, 0.0], frame=frame),
    ):
        with pytest.raises(OptionError, match="frame must be one of 'base', 'tool'"):
            call()
    with pytest.raises(OptionError, match="frame='base' only"):
        jacobian_dot(ARM, [0.0, 0.0], [1.0, 0.0], frame="tool")


def test_fixed_transforms_compose_to_fk():
    """T_base_tool = F[0] · M_1(q) · F[1] ⋯ M_m(q) · F[m], with M an elementary z move (the model's formula)."""
    robot = ROBOTS["stanford"]
    q = random_q(robot, np.random.default_rng(3))
    F = robot.fixed_transforms()
    T = F[0]
    for k, ax in enumerate(robot.axes):
        v = ax.multiplier * q[ax.joint_index] + ax.offset
        T = T @ (rot_z(v) if ax.kind == "revolute" else trans(z=v)) @ F[k + 1]
    np.testing.assert_allclose(T, fk(robot, q), atol=1e-12)


def test_computing_with_a_robot_does_not_keep_it_alive():
    robot = Robot.from_dh([dict(joint="revolute", a=1.0, alpha=0.0, d=0.0, theta=0.0)])
    jacobian(robot, [0.3]), fk(robot, [[0.3]])
    ref = weakref.ref(robot)
    del robot
    gc.collect()
    assert ref() is None
