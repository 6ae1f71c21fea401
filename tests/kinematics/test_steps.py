"""The derivation steps (kinematics.symbolic.steps): every step against an independent quantity.

* exactly: each method's steps, assembled, are the library's simplified J (normal form modulo
  sin² + cos² = 1) for the small robots;
* numerically, for every library robot and a URDF arm: the transforms against ``link_frames``,
  Whitney's vectors against ``joint_frames``, the propagated link velocities against finite
  differences of ``link_frames``, the propagated wrench against the same wrench carried to each
  joint in the base frame, the ∂p/∂q and (∂R/∂q) Rᵀ against J's columns, and J against
  ``kinematics.jacobian``.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from locations import DATA

import kinematics
import robots
from kinematics.numeric import joint_frames, link_frames
from kinematics.symbolic import det_rows, is_zero, jacobian
from kinematics.symbolic.steps import METHODS, derivation_steps, dh_rows

URDF = DATA / "iiwa14_like.urdf"
SMALL = ["planar2", "trr", "elbow3r", "wrist"]
FAST = 0.3  # [s] simplification budget for the numeric checks: the steps are exact either way


def _robot(name: str) -> kinematics.Robot:
    return kinematics.robot_from_urdf(str(URDF)) if name == "urdf" else robots.load(name)


def _by_key(steps) -> dict:
    return {s.key: s for s in steps}


def _samples(robot: kinematics.Robot, count: int = 2, seed: int = 1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    lim = robot.qlim
    lo = np.where(np.isfinite(lim[0]), lim[0], -np.pi)
    hi = np.where(np.isfinite(lim[1]), lim[1], np.pi)
    return rng.uniform(lo, hi, size=(count, robot.dof))


def _tol(robot: kinematics.Robot) -> float:
    from kinematics.symbolic import build_model

    snaps = build_model(robot).snaps
    return 1e-9 if not snaps else 1e-9 + 20 * max(s.change for s in snaps)


def _skew(w: np.ndarray) -> np.ndarray:
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


# ------------------------------------------------------------------------------ exact


@pytest.mark.slow
@pytest.mark.parametrize("name", SMALL)
@pytest.mark.parametrize("method", METHODS)
def test_steps_assemble_the_library_jacobian_exactly(name, method):
    robot = robots.load(name)
    steps = derivation_steps(robot, method, timeout=None)
    S = _by_key(steps)
    J_ref = jacobian(robot, timeout=None)
    q = sp.symbols(f"q1:{robot.dof + 1}", real=True)
    assert all(is_zero(e, q) for e in S["J"].expr - J_ref)
    # … and J really is made of the method's own steps
    if method in ("whitney", "differentiation"):
        prefix = "whitney" if method == "whitney" else "diff"
        cols = sp.Matrix.hstack(*[S[f"{prefix}.col{j + 1}"].expr for j in range(robot.dof)])
        assert all(is_zero(e, q) for e in cols - J_ref)
    if method == "differentiation":
        for j in range(robot.dof):
            Sj = S[f"diff.S{j + 1}"].expr
            assert all(is_zero(e, q) for e in Sj + Sj.T)  # a skew matrix
    if method == "propagation":
        qd = S["prop.v_base"].inputs
        twist = sp.Matrix.vstack(S["prop.v_base"].expr, S["prop.w_base"].expr)
        assert all(is_zero(e, q) for e in twist - J_ref * sp.Matrix(qd))
    if method == "force":
        R = robot_tool_rotation(robot)
        JT_tool = S["force.JT"].expr
        J_tool = sp.Matrix.vstack(R.T * J_ref[:3, :], R.T * J_ref[3:, :])
        assert all(is_zero(e, q) for e in JT_tool - J_tool.T)
        taus = sp.Matrix([S[f"force.tau{j + 1}"].expr[0, 0] for j in range(robot.dof)])
        assert all(is_zero(e, q) for e in taus - J_tool.T * sp.Matrix(S["force.tau1"].inputs))


def robot_tool_rotation(robot: kinematics.Robot) -> sp.Matrix:
    from kinematics.symbolic import fk

    return fk(robot, timeout=None)[:3, :3]


@pytest.mark.slow
@pytest.mark.parametrize("name", ["planar2", "elbow3r"])
def test_tool_frame_steps(name):
    robot = robots.load(name)
    q = sp.symbols(f"q1:{robot.dof + 1}", real=True)
    J_tool = jacobian(robot, "tool", timeout=None)
    for method in METHODS:
        S = _by_key(derivation_steps(robot, method, "tool", timeout=None))
        assert S["J"].lhs == "J_{\\mathrm{tool}}"
        assert all(is_zero(e, q) for e in S["J"].expr - J_tool), method


def test_symbolic_dh_table_in_the_course_letters():
    rows = dh_rows(robots.load("trr"), symbolic_params=True)
    l1, l2, l3 = sp.symbols("l1 l2 l3", real=True)
    q1, q2, q3 = sp.symbols("q1 q2 q3", real=True)
    assert [r.joint for r in rows] == ["prismatic", "revolute", "revolute"]
    assert [(r.theta, r.d, r.a, r.alpha) for r in rows] == [
        (sp.pi / 2, q1, l1, sp.pi),
        (q2, 0, l2, 0),
        (q3, 0, l3, 0),
    ]
    mdh = dh_rows(robots.load("elbow3r"), symbolic_params=True)
    assert mdh[1].cells() == (sp.pi / 2, sp.Symbol("L1", real=True), 0, q2)  # Craig: α₁, a₁, d₂, θ₂
    assert dh_rows(_robot("urdf")) == ()


def test_a_urdf_chain_has_no_symbolic_parameters():
    with pytest.raises(kinematics.JacobianLabError, match="DH table"):
        derivation_steps(_robot("urdf"), "whitney", symbolic_params=True)


def test_bad_arguments_are_refused():
    robot = robots.load("planar2")
    for bad in (
        dict(method="newton"),
        dict(method="whitney", frame="world"),
        dict(method="whitney", timeout=-1),
    ):
        with pytest.raises(kinematics.JacobianLabError):
            derivation_steps(robot, **bad)  # type: ignore[arg-type]
    step = derivation_steps(robot, "propagation")[-3]
    with pytest.raises(ValueError, match="needs the values"):
        step.numeric([0.1, 0.2])


# ---------------------------------------------------------------------------- numeric

ALL = [*robots.names(), "urdf"]


@pytest.mark.slow
@pytest.mark.parametrize("name", ALL)
def test_transforms_and_whitney_vectors_numerically(name):
    robot = _robot(name)
    S = _by_key(derivation_steps(robot, "whitney", timeout=FAST))
    tol = _tol(robot)
    m = len(robot.axes)
    for q in _samples(robot):
        L, W = link_frames(robot, q), joint_frames(robot, q)
        p_n = kinematics.fk(robot, q)[:3, 3]
        for k in range(m):
            assert np.allclose(S[f"T0_{k + 1}"].numeric(q), L[k + 1], atol=tol)
            assert np.allclose(S[f"A{k + 1}"].numeric(q), np.linalg.inv(L[k]) @ L[k + 1], atol=tol)
            assert np.allclose(S[f"whitney.z{k}"].numeric(q)[:, 0], W[k][:3, 2], atol=tol)
            if robot.axes[k].kind == "revolute":
                assert np.allclose(S[f"whitney.p{k}"].numeric(q)[:, 0], W[k][:3, 3], atol=tol)
                assert np.allclose(S[f"whitney.r{k}"].numeric(q)[:, 0], p_n - W[k][:3, 3], atol=tol)
        J = kinematics.jacobian(robot, q)
        for j in range(robot.dof):
            assert np.allclose(S[f"whitney.col{j + 1}"].numeric(q)[:, 0], J[:, j], atol=tol)
        assert np.allclose(S["J"].numeric(q), J, atol=tol)
        if "detJ" in S:
            rows = list(det_rows(robot))
            Jr = J[rows]
            expected = (
                np.linalg.det(Jr)
                if len(rows) == robot.dof
                else np.linalg.det(Jr @ Jr.T if len(rows) < robot.dof else Jr.T @ Jr)
            )
            assert S["detJ"].numeric(q)[0, 0] == pytest.approx(expected, abs=1e-6)


@pytest.mark.slow
@pytest.mark.parametrize("name", ALL)
def test_differentiation_steps_numerically(name):
    robot = _robot(name)
    S = _by_key(derivation_steps(robot, "differentiation", timeout=FAST))
    tol = _tol(robot)
    for q in _samples(robot, 1):
        J = kinematics.jacobian(robot, q)
        for j in range(robot.dof):
            assert np.allclose(S[f"diff.dp{j + 1}"].numeric(q)[:, 0], J[:3, j], atol=tol)
            assert np.allclose(S[f"diff.S{j + 1}"].numeric(q), _skew(J[3:, j]), atol=tol)
        assert np.allclose(S["J"].numeric(q), J, atol=tol)


@pytest.mark.slow
@pytest.mark.parametrize("name", ALL)
def test_propagated_velocities_are_the_links_velocities(name):
    """ⁱωᵢ, ⁱvᵢ against central differences of the link frames along q̇; ⁰vₙ, ⁰ωₙ against J q̇."""
    robot = _robot(name)
    S = _by_key(derivation_steps(robot, "propagation", timeout=FAST))
    tol = _tol(robot)
    rng = np.random.default_rng(7)
    h = 1e-6
    for q in _samples(robot, 1):
        qd = rng.uniform(-1, 1, robot.dof)
        Lp, Lm, L = link_frames(robot, q + h * qd), link_frames(robot, q - h * qd), link_frames(robot, q)
        for k in range(len(robot.axes)):
            R = L[k + 1][:3, :3]
            v_base = (Lp[k + 1][:3, 3] - Lm[k + 1][:3, 3]) / (2 * h)
            Rdot = (Lp[k + 1][:3, :3] - Lm[k + 1][:3, :3]) / (2 * h)
            W = Rdot @ R.T
            w_base = np.array([W[2, 1], W[0, 2], W[1, 0]])
            assert np.allclose(S[f"prop.v{k + 1}"].numeric(q, qd)[:, 0], R.T @ v_base, atol=1e-6)
            assert np.allclose(S[f"prop.w{k + 1}"].numeric(q, qd)[:, 0], R.T @ w_base, atol=1e-6)
        J = kinematics.jacobian(robot, q)
        assert np.allclose(S["prop.v_base"].numeric(q, qd)[:, 0], J[:3] @ qd, atol=tol)
        assert np.allclose(S["prop.w_base"].numeric(q, qd)[:, 0], J[3:] @ qd, atol=tol)
        assert np.allclose(S["J"].numeric(q), J, atol=tol)


@pytest.mark.slow
@pytest.mark.parametrize("name", ALL)
def test_propagated_wrench_is_the_tool_wrench_at_each_joint(name):
    """fᵢ, nᵢ rotated to the base equal the tool wrench carried to joint i's frame; τ = J_toolᵀ F."""
    robot = _robot(name)
    S = _by_key(derivation_steps(robot, "force", timeout=FAST))
    tol = _tol(robot)
    rng = np.random.default_rng(3)
    for q in _samples(robot, 1):
        wrench = rng.uniform(-1, 1, 6)  # [f; n] in the tool axes
        T = kinematics.fk(robot, q)
        f_base, n_base = T[:3, :3] @ wrench[:3], T[:3, :3] @ wrench[3:]
        W = joint_frames(robot, q)
        for k, ax in enumerate(robot.axes):
            value = ax.multiplier * q[ax.joint_index] + ax.offset
            R, o = W[k][:3, :3], W[k][:3, 3]
            if ax.kind == "revolute":
                c, s = np.cos(value), np.sin(value)
                R = R @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
            else:
                o = o + value * W[k][:3, 2]
            assert np.allclose(R @ S[f"force.f{k + 1}"].numeric(q, wrench)[:, 0], f_base, atol=tol)
            n_expected = n_base + np.cross(T[:3, 3] - o, f_base)
            assert np.allclose(R @ S[f"force.n{k + 1}"].numeric(q, wrench)[:, 0], n_expected, atol=tol)
        J_tool = kinematics.jacobian(robot, q, "tool")
        tau = np.array([S[f"force.tau{j + 1}"].numeric(q, wrench)[0, 0] for j in range(robot.dof)])
        assert np.allclose(tau, J_tool.T @ wrench, atol=tol)
        assert np.allclose(S["J"].numeric(q), kinematics.jacobian(robot, q), atol=tol)


def test_modified_dh_link_transforms_are_craigs():
    """puma560_mdh: Aᵢ = Rx(α_{i−1}) Tx(a_{i−1}) Rz(θᵢ) Tz(dᵢ), from the table's own numbers."""
    from kinematics.transforms import rot_x, rot_z, trans

    robot = robots.load("puma560_mdh")
    S = _by_key(derivation_steps(robot, "whitney", timeout=FAST))
    q = _samples(robot, 1)[0]
    for i, row in enumerate(robot.dh):
        A = rot_x(row.alpha) @ trans(x=row.a) @ rot_z(row.theta + q[i]) @ trans(z=row.d)
        assert np.allclose(S[f"A{i + 1}"].numeric(q), A, atol=1e-9)


@pytest.mark.slow
def test_steps_print_in_latex_and_mathml():
    robot = robots.load("puma560")
    S = _by_key(derivation_steps(robot, "whitney"))
    assert S["T0_2"].latex().startswith("{}^{0}T_{2} = \\begin{bmatrix}")
    assert "c_{1}" in S["T0_2"].latex()
    mml = S["T0_6"].mathml(400)
    assert mml.count("<math") > 1 and "<mmultiscripts>" in mml  # split into groups of columns
    assert S["whitney.col2"].mathml(400).count("<math") == 1
    assert S["detJ"].latex().startswith("\\det J = ")
    assert {s.kind for s in S["detJ"].singular} == {"wrist", "elbow", "shoulder"}
    # The title leads to the sets, which are typeset in the joints' notation (not SymPy text in the title).
    assert S["detJ"].title.endswith("J is singular where a factor vanishes")
    assert not any(word in S["detJ"].title for word in ("sin(", "cos(", "pi", "q2"))
    from kinematics.symbolic.handout.parts import singular_texts

    texts = " ".join(singular_texts(S["detJ"].notation(), S["detJ"], latex=True))
    for kind in ("wrist", "elbow", "shoulder"):
        assert f"{kind} singularity" in texts
