"""The room's questions: each kind's right answer against the kinematics, computed independently here."""

from __future__ import annotations

import math

import numpy as np
import pytest

import robots
from app.core import questions as Q
from app.core.actions import GoTo
from app.core.reducer import reduce
from app.core.snapshot import compute
from app.core.state import LabState
from kinematics.analysis import task_rows
from kinematics.numeric import fk, jacobian

SINGULAR = [(name, c.name) for name in robots.names() for c in robots.load(name).configurations if c.singular]


def _snap(name: str, conf: str):
    robot = robots.load(name)
    state = reduce(LabState.initial(name, robot), GoTo(conf))
    return robot, state, compute(state)


@pytest.mark.parametrize("name,conf", SINGULAR)
def test_kind_question_names_the_file_kind(name: str, conf: str) -> None:
    robot = robots.load(name)
    c = next(c for c in robot.configurations if c.name == conf)
    question = Q.kind_question(robot, c.q, conf)
    assert question.choices == Q.KIND_CHOICES
    assert "regular" not in question.right
    if c.singular in Q.KIND_CHOICES:
        assert c.singular in question.right


@pytest.mark.parametrize("name", robots.names())
def test_kind_question_at_a_random_regular_pose_is_regular(name: str) -> None:
    robot = robots.load(name)
    rng = np.random.default_rng(7)
    for _ in range(20):
        lo, hi = np.clip(robot.qlim, -math.pi, math.pi)
        q = rng.uniform(lo, hi)
        s = np.linalg.svd(jacobian(robot, q)[list(task_rows(robot))], compute_uv=False)
        if s[-1] > 1e-3 * s[0]:  # independently regular: κ < 1000
            assert Q.kind_question(robot, q).right == {"regular"}
            return
    pytest.skip("no regular pose drawn")  # pragma: no cover - every library robot has one


def _null_axis(columns: np.ndarray) -> np.ndarray:
    """The unit line orthogonal to every column (the rotation the wrist's three axes cannot give)."""
    _, _, vt = np.linalg.svd(columns.T)
    return vt[-1]


def test_lost_question_puma_wrist_is_the_axis_no_wrist_joint_turns_about() -> None:
    robot, state, snap = _snap("puma560", "wrist_singular")
    question = Q.lost_question(robot, state.q, snap.losses, seed=11)
    assert len(question.choices) == 4 and len(question.right) == 1
    z456 = jacobian(robot, np.array(state.q))[3:, 3:6]  # ω columns of the wrist joints: their axes
    want = _null_axis(z456)
    assert np.linalg.norm(z456.T @ want) < 1e-9
    (letter,) = question.right
    arrow = question.arrows[question.choices.index(letter)]
    assert arrow.part == "rotation"
    assert abs(abs(float(np.dot(arrow.direction, want))) - 1.0) < 1e-9
    assert Q.direction_is_right(question.lost, "rotation", want)
    tilted = math.cos(Q.LOST_ANGLE * 1.2) * want + math.sin(Q.LOST_ANGLE * 1.2) * np.cross(want, z456[:, 1])
    assert not Q.direction_is_right(question.lost, "rotation", tilted)
    for a in question.arrows:  # every other candidate is told from the answer
        if a is not arrow and a.part == arrow.part:
            assert (
                math.acos(min(1.0, abs(float(np.dot(a.direction, arrow.direction)))))
                >= math.radians(30) - 1e-9
            )


@pytest.mark.parametrize(
    "name,conf", [("planar2", "stretched"), ("planar3", "stretched"), ("trr", "stretched")]
)
def test_lost_question_boundary_is_a_translation_no_joint_gives(name: str, conf: str) -> None:
    """Stretched: the answer d is a tool velocity no joint's column has any part of (J_vᵀ d = 0)."""
    robot, state, snap = _snap(name, conf)
    question = Q.lost_question(robot, state.q, snap.losses, seed=2)
    (letter,) = question.right
    arrow = question.arrows[question.choices.index(letter)]
    Jv = jacobian(robot, np.array(state.q))[:3]
    assert arrow.part == "translation"
    assert np.linalg.norm(Jv.T @ np.array(arrow.direction)) < 1e-9 * np.linalg.norm(Jv)


def test_lost_question_order_is_the_seeds_and_every_seed_has_one_answer() -> None:
    robot, state, snap = _snap("puma560", "elbow_singular")
    seen = set()
    for seed in range(12):
        question = Q.lost_question(robot, state.q, snap.losses, seed=seed)
        assert len(question.right) == 1
        assert question == Q.lost_question(robot, state.q, snap.losses, seed=seed)
        seen |= question.right
    assert len(seen) > 1  # the answer is not always the same letter


def test_lost_question_refused_when_regular() -> None:
    robot, state, snap = _snap("puma560", "home")
    with pytest.raises(Q.QuestionError, match="regular"):
        Q.lost_question(robot, state.q, snap.losses)


def test_blowup_question_puma_wrist_is_q4_and_q6() -> None:
    robot = robots.load("puma560")
    preset = robots.motions("puma560")[0]
    question = Q.blowup_question(robot, preset.q, preset.twist, frame=preset.frame)
    assert question.right == {"q4", "q6"}
    assert question.choices == tuple(f"q{i}" for i in range(1, 7))


@pytest.mark.parametrize("name", [n for n in robots.names() if robots.motions(n)])
def test_blowup_answer_is_the_fastest_joint_of_an_independent_integration(name: str) -> None:
    """q̇ = J⁻¹ v integrated here with np.linalg.lstsq (not the library's step) until |q̇| grows 3×."""
    robot = robots.load(name)
    preset = robots.motions(name)[0]
    try:
        question = Q.blowup_question(robot, preset.q, preset.twist, frame=preset.frame)
    except Q.QuestionError:
        pytest.skip("this preset meets no singularity")
    rows = list(task_rows(robot))
    q = np.array(preset.q, dtype=float)
    v = np.asarray(preset.twist, dtype=float)
    first = None
    for _ in range(20000):
        J = jacobian(robot, q)
        if preset.frame == "tool":
            R = fk(robot, q)[:3, :3]
            vv = np.concatenate([R @ v[:3], R @ v[3:]])
        else:
            vv = v
        qd = np.linalg.lstsq(J[rows], vv[rows], rcond=None)[0]
        first = np.abs(qd).max() if first is None else first
        if (
            np.abs(qd).max() > 8 * first
            or np.any(q + 1e-3 * qd < robot.qlim[0])
            or np.any(q + 1e-3 * qd > robot.qlim[1])
        ):
            break
        q = q + 1e-3 * qd
    fastest = f"q{int(np.argmax(np.abs(qd))) + 1}"
    assert fastest in question.right


def test_number_question_det_and_kappa_against_numpy() -> None:
    robot = robots.load("planar2")
    rng = np.random.default_rng(3)
    for _ in range(10):
        q = rng.uniform(*robot.qlim)
        Jt = jacobian(robot, q)[list(task_rows(robot))]
        det = Q.number_question(robot, q, "det")
        assert robot.dh is not None
        a1, a2 = robot.dh[0].a, robot.dh[1].a
        assert det.value == pytest.approx(np.linalg.det(Jt), abs=1e-12)
        assert det.value == pytest.approx(a1 * a2 * math.sin(q[1]), abs=1e-12)  # the 2R's closed form
        s = np.linalg.svd(Jt, compute_uv=False)
        if s[-1] > 1e-6:
            kappa = Q.number_question(robot, q, "kappa")
            assert kappa.value == pytest.approx(s[0] / s[-1], rel=1e-12)
            assert kappa.tolerance == pytest.approx(max(0.05 * kappa.value, 0.5))


def test_number_question_refusals_say_why() -> None:
    robot = robots.load("panda")
    with pytest.raises(Q.QuestionError, match="κ instead"):
        Q.number_question(robot, robot.home, "det")
    stretched = robots.load("planar2")
    c = next(c for c in stretched.configurations if c.name == "stretched")
    with pytest.raises(Q.QuestionError, match="infinite"):
        Q.number_question(stretched, c.q, "kappa")
    with pytest.raises(Q.QuestionError):
        Q.number_question(stretched, c.q, "__import__('os')")


def test_custom_question_checks_what_the_teacher_typed() -> None:
    robot = robots.load("planar2")
    question = Q.custom_question(robot, robot.home, "  Which\u0000 is <b>right</b>?\n", ["yes", "no"], [1])
    assert question.prompt == "Which is <b>right</b>?"  # control characters dropped; HTML escaped by views
    assert question.right == {"no"}
    for prompt, choices, right, why in [
        ("", ["a", "b"], [0], "empty"),
        ("x" * 301, ["a", "b"], [0], "too long"),
        ("q", ["a"], [0], "2 to 6"),
        ("q", ["a", "a"], [0], "same"),
        ("q", ["a", "b"], [2], "one of the choices"),
        ("q", ["a", "b"], [True], "one of the choices"),
        ("q", ["a", 3], [0], "text"),
    ]:
        with pytest.raises(Q.QuestionError, match=why):
            Q.custom_question(robot, robot.home, prompt, choices, right)
