"""The generated straight-line chain code (kinematics.compiled) against the NumPy scan it replaced
(kernel.chain_scan / kernel.batch_scan, still the path of very long chains): every library robot,
the URDF test files, mimic and prismatic joints, a rotated base and tool, and |q| ~ 1e16."""

from __future__ import annotations

import io
import re
import tokenize

import numpy as np
import pytest
from fakes import random_q
from kinematics_helpers import MIMIC_URDF, chains_under_test

from kinematics import ConfigurationError, Robot, fk, jacobian, joint_frames, link_frames
from kinematics.compiled import MAX_AXES, Chain, Compiled, generate
from kinematics.kernel import (
    batch_scan,
    batched_jacobian,
    chain_scan,
    jacobian_from_frames,
    kernel,
)
from kinematics.numeric import chain_frames, frames_and_jacobian
from kinematics.transforms import rot_z, trans
from kinematics.urdf import robot_from_urdf_string

ROBOTS: dict[str, Robot] = chains_under_test()
NAMES = list(ROBOTS)


def test_the_fixtures_cover_what_the_generator_must_handle():
    """Mimic axes, prismatic joints, both DH conventions and URDF chains are all among ROBOTS."""
    assert any(len(r.axes) > r.dof for r in ROBOTS.values())
    assert any("prismatic" in r.joint_types for r in ROBOTS.values())
    assert {r.convention for r in ROBOTS.values()} >= {"standard", "modified", None}
    assert sum(r.urdf_path is not None for r in ROBOTS.values()) >= 3
    assert all(kernel(r).compiled is not None for r in ROBOTS.values())


def _reference(robot: Robot, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    c = kernel(robot)
    W, T = chain_scan(c, q)
    return W, T, jacobian_from_frames(c, W, T)


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("scale", [1.0, 1e16])
def test_single_configuration_matches_the_numpy_scan(name, scale):
    """fk, J (both frames), joint frames, link frames and frames_and_jacobian: 1e-12 from the scan
    at random configurations, and at revolute angles ~1e16 (both reduce exactly: still rigid)."""
    robot = ROBOTS[name]
    rng = np.random.default_rng(3)
    revolute = np.array([k == "revolute" for k in robot.joint_types])
    for _ in range(5):
        q = random_q(robot, rng)
        q = np.where(revolute, q * scale, q)
        W, T, J = _reference(robot, q)
        np.testing.assert_allclose(fk(robot, q), T, atol=1e-12)
        np.testing.assert_allclose(jacobian(robot, q), J, atol=1e-12)
        R = T[:3, :3]
        np.testing.assert_allclose(
            jacobian(robot, q, "tool"), np.vstack([R.T @ J[:3], R.T @ J[3:]]), atol=1e-12
        )
        np.testing.assert_allclose(joint_frames(robot, q), W, atol=1e-12)
        W2, T2 = chain_frames(robot, q)
        np.testing.assert_allclose(W2, W, atol=1e-12)
        np.testing.assert_allclose(T2, T, atol=1e-12)
        L, W3, J3 = frames_and_jacobian(robot, q)
        np.testing.assert_allclose(W3, W, atol=1e-12)
        np.testing.assert_allclose(J3, J, atol=1e-12)
        np.testing.assert_allclose(link_frames(robot, q), L, atol=0)
        # Link frames by their definition: base, W_k · M_k(q) · T_joint_child_k, tool.
        np.testing.assert_allclose(L[0], robot.base, atol=1e-12)
        np.testing.assert_allclose(L[-1], T, atol=1e-12)
        for k, ax in enumerate(robot.axes):
            value = ax.multiplier * q[ax.joint_index] + ax.offset
            M = rot_z(value) if ax.kind == "revolute" else trans(0.0, 0.0, value)
            np.testing.assert_allclose(L[k + 1], W[k] @ M @ ax.T_joint_child, atol=1e-12)
        assert np.abs(R.T @ R - np.eye(3)).max() < 1e-12


@pytest.mark.parametrize("name", NAMES)
def test_batch_matches_the_numpy_scan(name):
    """The generated batch code against the component-wise NumPy batch, and against one-by-one."""
    robot = ROBOTS[name]
    c = kernel(robot)
    Q = random_q(robot, np.random.default_rng(5), size=37)
    Q[:5] *= np.where([k == "revolute" for k in robot.joint_types], 1e16, 1.0)
    assert c.compiled is not None
    T, J = c.compiled.batch(Q, jacobian=True)
    T0, J0 = batch_scan(c, Q, want_jacobian=True)
    np.testing.assert_allclose(T, T0, atol=1e-12)
    np.testing.assert_allclose(J, J0, atol=1e-12)
    np.testing.assert_allclose(fk(robot, Q), T0, atol=1e-12)
    for i in (0, 7, 36):
        np.testing.assert_allclose(J[i], _reference(robot, Q[i])[2], atol=1e-12)


def test_batches_across_chunk_boundaries_equal_one_by_one():
    robot = ROBOTS["panda"]
    Q = random_q(robot, np.random.default_rng(1), size=2 * 4096 + 3)
    T, J = batched_jacobian(kernel(robot), Q)
    for i in (0, 4095, 4096, 8191, 8192, 8194):
        np.testing.assert_allclose(J[i], jacobian(robot, Q[i]), atol=1e-12)
        np.testing.assert_allclose(T[i], fk(robot, Q[i]), atol=1e-12)


def test_chains_beyond_max_axes_use_the_scan_and_agree():
    """A chain longer than MAX_AXES gets no generated code (the NumPy scan serves it); the
    generator still handles it, and both agree."""
    rows = [
        dict(joint="revolute", a=0.05, alpha=0.3 * (k % 5 - 2), d=0.01 * k, theta=0.0)
        for k in range(MAX_AXES + 6)
    ]
    robot = Robot.from_dh(rows, name="snake")
    c = kernel(robot)
    assert c.compiled is None
    other = Compiled(chain_of(robot))
    q = random_q(robot, np.random.default_rng(2))
    T, J = other.single(q, "TJ")
    np.testing.assert_allclose(fk(robot, q), T, atol=1e-12)
    np.testing.assert_allclose(jacobian(robot, q), J, atol=1e-12)


def chain_of(robot: Robot) -> Chain:
    """The Chain the kernel builds for a robot (written out here from the model's parts)."""
    return Chain(
        fixed=robot.fixed_transforms(),
        base=np.array(robot.base),
        child=np.array([ax.T_joint_child for ax in robot.axes]),
        index=tuple(ax.joint_index for ax in robot.axes),
        multiplier=tuple(ax.multiplier for ax in robot.axes),
        offset=tuple(ax.offset for ax in robot.axes),
        revolute=tuple(ax.kind == "revolute" for ax in robot.axes),
        dof=robot.dof,
    )


def test_generated_text_holds_only_fixed_identifiers_and_numbers():
    """Names from the model never reach the generated code: a robot whose name, joints and links
    are named like code gives a text of fixed identifiers, float literals and operators only."""
    evil = "&quot;);__import__(&quot;os&quot;).system(&quot;x&quot;);#"
    urdf = (
        MIMIC_URDF.replace('"j1"', f'"j1{evil}"')
        .replace('"e"', f'"e{evil}"')
        .replace('name="m"', f'name="{evil}"')
    )
    robot = robot_from_urdf_string(urdf)
    assert "import" in robot.joints[0].name and "import" in robot.name
    compiled = kernel(robot).compiled
    assert compiled is not None
    allowed = re.compile(
        r"(chain|cos|sin|tan|negative|multiply|out|return|def|pass|del|q|u|[qucstdvhg]\d+)\Z"
    )
    cases = (("T", False), ("TJ", False), ("TW", False), ("TWLJ", False), ("TJ", True), ("TJD", True))
    for parts, batch in cases:
        text, _ = generate(compiled.chain, "W" in parts, "L" in parts, "J" in parts, batch, "D" in parts)
        for token in tokenize.generate_tokens(io.StringIO(text).readline):
            assert token.type != tokenize.STRING, token
            if token.type == tokenize.NAME:
                assert allowed.match(token.string), token.string
    q = np.array([0.2, 0.3])
    np.testing.assert_allclose(jacobian(robot, q), _reference(robot, q)[2], atol=1e-12)


@pytest.mark.parametrize(
    ("q", "message"),
    [
        ([0.1, np.nan, 0.0, 0.0], r"q contains NaN or infinity \(joint 'q2 elbow': nan\)"),
        ([0.1, 0.0, 0.0, -np.inf], r"q contains NaN or infinity \(joint 'q4 tool roll': -inf\)"),
        ([0.1, 0.0, 2e15, 0.0], r"joint 'd3 quill' value 2e\+15 m is out of range"),
        ([-2e18, 0.0, 0.0, 0.0], r"joint 'q1 shoulder' value -2e\+18 rad is out of range"),
    ],
)
def test_float64_configurations_are_checked_like_any_other(q, message):
    """A float64 array of the right shape takes the one-configuration hot path of the input
    checks; NaN, ±inf and out-of-range values are still refused with the reason."""
    robot = ROBOTS["scara"]
    for fn in (fk, jacobian, joint_frames, link_frames, frames_and_jacobian):
        with pytest.raises(ConfigurationError, match=message):
            fn(robot, np.array(q, dtype=np.float64))
