"""The course in the app (issue 21, items 12–15): its errors said where each item is shown, its
letters, its digits and one name per joint. Server level: handles set as a user sets them, actions
dispatched, snapshot and panel text read back."""

from __future__ import annotations

import pathlib
import re

import numpy as np
import pytest
from app_helpers import assert_all_finite, derive_walk, scene_node, wait_until
from fakes import poll

from app.core.actions import GoTo, SetRate, SetWrench
from app.core.commands import ChooseRobot, UploadRobot
from app.core.numbers import NumberError, parse_number
from app.views.camera import in_view
from app.views.panel.errata import ERRATA

COURSE = next(
    (
        d / "shared" / "course"
        for d in pathlib.Path(__file__).resolve().parents
        if (d / "shared" / "course").is_dir()
    ),
    pathlib.Path("/nonexistent"),
)  # ../shared/course of the worktree or of the main checkout


def choose(session, name: str) -> None:
    session.dispatch(ChooseRobot(name))
    session.settle()


def _text(html: str) -> str:
    return re.sub(r"<[^>]*>", "", html)


@pytest.mark.skipif(not COURSE.is_dir(), reason="the course notes are not next to the repository")
@pytest.mark.parametrize(
    ("key", "quoted"),
    [("M", "ctg θ"), ("gradient", "grad"), ("forces", "infinitos en articulaciones"), ("jdot", "apenas")],
)
def test_each_erratum_cites_lines_that_hold_what_it_quotes(key, quoted):
    """The note's file and line range point at the course's own words (so the citation can be checked)."""
    where = ERRATA[key].where
    number = re.search(r"course (\d{3})", where).group(1)
    first, *last = re.search(r"lines? (\d+)(?:–(\d+))?", where).groups()
    end = int(last[0]) if last and last[0] else int(first)
    (path,) = COURSE.glob(f"{number}_*.txt")
    lines = path.read_text(encoding="utf-8").splitlines()[int(first) - 1 : end]
    assert quoted in "\n".join(lines)


def test_the_four_course_errors_are_said_where_each_item_is_shown(session):
    p = session.panel
    # 004's M(y): the J(q) tab's analytic J.
    assert "The course is wrong" not in p.matrix.analytic.content
    p.matrix.representation.value = next(v for v in p.matrix.representation.options if "ZYZ" in v)
    session.settle()
    assert "course 004, slide 12" in _text(p.matrix.analytic.content)
    assert "M⁻¹" in _text(p.matrix.analytic.content)
    # 000's J̇ᵢ: the v = J q̇ tab's J̇ q̇.
    session.dispatch(SetRate(1, 1.0))
    session.settle()
    assert "course 000, §7" in _text(p.forward.accel.content)
    # 002's forces: the τ = Jᵀ F tab.
    session.dispatch(SetWrench(0, 5.0))
    session.settle()
    assert "course 002" in _text(p.force.torques.content)
    assert "no torque" in _text(p.force.torques.content)
    assert_all_finite(session)


def test_the_gradient_sign_is_said_beside_the_climb(session):
    choose(session, "iiwa14")
    motion = session.panel.motion
    assert motion is not None and motion.redundant
    shown = [_text(h.content) for h in motion.notes]
    assert any("course 004, slide 17" in t and "(I − J⁺J) ∇w" in t for t in shown)
    choose(session, "puma560")  # not redundant: no climb, no note
    assert not session.panel.motion.notes


# ---------------------------------------------------------------------- item 11: typed numbers
def _editor(session):
    session.panel.robot.value = session.panel.robot.options[0]
    editor = session.panel.editor
    editor.start.value = "empty table (one joint)"
    session.settle()
    return editor


@pytest.mark.parametrize(
    ("typed", "value"),
    [("1e-3", 1e-3), ("0.15005", 0.15005), (" −0.25 ", -0.25), ("+.5", 0.5), ("2.5E1", 25.0), (3, 3.0)],
)
def test_parse_number_keeps_what_is_typed(typed, value):
    assert parse_number(typed) == value


@pytest.mark.parametrize(
    ("typed", "words"),
    [
        ("0,3", "use a point for decimals (0.3)"),
        ("1e400", "too large"),
        ("1e-", "is not a number"),
        ("1_000", "is not a number"),
        ("nan", "is not a number"),
        ("inf", "is not a number"),
        ("", "empty"),
        ("0x10", "is not a number"),
        (True, "expected a number"),
        (float("nan"), "NaN"),
    ],
)
def test_parse_number_refuses_in_words(typed, words):
    with pytest.raises(NumberError, match=re.escape(words)):
        parse_number(typed)
    with pytest.raises(NumberError, match="beyond ±100 m"):
        parse_number("1400", 100.0, "m")


def test_the_build_tab_keeps_1e_minus_3_and_refuses_a_decimal_comma_and_1e400(session):
    editor = _editor(session)
    editor.a.value = "1e-3"
    session.settle()
    assert editor.error == "" and editor.a.value == "1e-3"  # the box keeps what was typed
    assert session.state.robot.dh[0].a == 1e-3  # and the arm is 1 mm long, not −13 m
    good = session.state.robot
    for typed, words in (("0,3", "use a point for decimals (0.3)"), ("1e400", "too large")):
        editor.a.value = typed
        session.settle()
        assert words in editor.error and words in _text(editor.problem.content)
        assert editor.a.value == typed and session.state.robot is good  # nothing silently built
    assert_all_finite(session)


def test_reset_view_brings_the_camera_back_after_a_long_arm(session):
    editor = _editor(session)
    cam = session.client.camera

    def distance() -> float:
        return float(np.linalg.norm(np.asarray(cam.position) - np.asarray(cam.look_at)))

    editor.a.value = "90"  # a 90 m arm: the camera glides out to see it
    session.settle()
    wait_until(lambda: distance() > 50)
    editor.a.value = "0.3"  # the arm is 0.3 m again, the camera stays out there (the user's view)
    session.settle()
    assert distance() > 50
    session.panel.reset_view.value = True  # the View tab's button
    session.settle()
    wait_until(lambda: distance() < 3.0)
    extent = session.scene.extent
    view = session.camera.view()
    assert in_view(view, extent).all()  # the whole arm in the picture


def test_the_course_velocity_typed_keeps_its_digits(session):
    choose(session, "trr")
    inverse = session.panel.inverse
    vx = inverse.sliders[0]
    assert vx.precision >= 3  # the box keeps 17.256, not 17.2
    vx.value = 17.256
    inverse.sliders[1].value = -20.13
    inverse.sliders[2].value = 0.5
    session.settle()
    assert session.state.v_desired[:3].tolist() == [17.256, -20.13, 0.5]
    rates = session.snapshot.rates  # the course's (0.5 m/s, 90°/s, 45°/s), to its rounding of v
    assert abs(rates[0] - 0.5) < 1e-3 and abs(np.degrees(rates[1]) - 90) < 0.05
    bars = _text(inverse.rates.content)
    assert "90°/s" in bars and "45°/s" in bars and "90.8" not in bars
    readout = _text(session.panel.motion.readout.content)
    assert "17.256" in readout and "−20.13" in readout


# ---------------------------------------------------------------------- item 14: one name per joint
_OTHER_SYMBOL = re.compile(r"\b(?!q\d\b)[A-Za-zθ]{1,6}_?\d+\b")  # d3, A1, joint4: a second name
_MIXED = """<?xml version="1.0"?>
<robot name="mixed">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="l4"/>
  JOINTS
</robot>
"""


def _mixed_urdf() -> bytes:
    """The issue's upload: joints named q1, q2, elbow_joint, q4."""
    joints = []
    for k, name in enumerate(("q1", "q2", "elbow_joint", "q4")):
        axis = "0 0 1" if k % 2 == 0 else "0 1 0"
        joints.append(
            f'<joint name="{name}" type="revolute"><parent link="{"base" if k == 0 else f"l{k}"}"/>'
            f'<child link="l{k + 1}"/><origin xyz="0.2 0 0.1"/><axis xyz="{axis}"/>'
            '<limit lower="-2" upper="2" effort="1" velocity="1"/></joint>'
        )
    return _MIXED.replace("JOINTS", "\n  ".join(joints)).encode()


@pytest.mark.parametrize("name", ["stanford", "iiwa14", "ur5", "trr", "puma560", "uploaded"])
def test_every_joint_has_one_name_on_screen(session, name):
    if name == "uploaded":
        session.dispatch(UploadRobot("mixed.urdf", _mixed_urdf()))
        session.settle()
        poll(lambda: not session.commands.building)  # built away from the drawing thread
        session.settle()
        assert session.state.robot.dof == 4 and session.errors == 0
    else:
        choose(session, name)
    robot, p = session.state.robot, session.panel
    labels = [s.label for s in p.joints.sliders]
    for i, label in enumerate(labels):
        assert label.startswith(f"q{i + 1}") and not label[len(f"q{i + 1}")].isdigit(), label
        assert not _OTHER_SYMBOL.search(label), label  # no d3, A1 or elbow_joint beside q3
    arm_labels = [scene_node(session, f"/lab/arm/label_{j}").text for j in range(robot.dof)]
    assert arm_labels == [f"q{j + 1}" for j in range(robot.dof)]
    rates = [s.label for s in p.forward.sliders]
    assert all(r.startswith(f"q̇{i + 1} ") for i, r in enumerate(rates))
    if name == "stanford":
        assert labels[2] == "q3 boom [m]"
    if name == "uploaded":
        assert labels[2] == "q3 elbow [°]"


def test_the_course_word_for_a_boundary_singularity(session):
    """002 calls the TRR's stretched arm a boundary singularity (the robot file's word); the banner
    says so, with what the geometry finds."""
    choose(session, "trr")
    session.dispatch(GoTo("stretched"))
    session.settle()
    banner = _text(session.panel.status.content)
    assert "singular: boundary (elbow)" in banner
    choose(session, "puma560")
    session.dispatch(GoTo("elbow_singular"))
    session.settle()
    assert "singular: elbow" in _text(session.panel.status.content)
    assert "singular: boundary" not in _text(session.panel.status.content)


def test_the_dh_table_shows_the_files_numbers(session):
    choose(session, "puma560")
    table = _text(session.panel.derive.table.content)
    assert "0.15005" in table and "0.4318" in table


# ---------------------------------------------------------------------- item 12: the Derive tab


def test_trr_velocity_propagation_draws_every_links_velocity_readably(session):
    """On the TRR's 24 m arm at the course's rates (0.5 m/s, 90°/s, 45°/s), v₁ = 0.5 m/s and
    v₃ ≈ 26.5 m/s: each vₖ is drawn along its true direction and long enough to see (issue 28: ≥ 15 % of
    the arm, v₂ was a stub at 8.5 %), each labelled with its size (the scale stated)."""
    choose(session, "trr")
    for i, rate in enumerate((0.5, np.pi / 2, np.pi / 4)):
        session.dispatch(SetRate(i, rate))
    derive_walk(session, "propagation", 2)
    d, size = session.snapshot.derive, session.scene.size
    thin = scene_node(session, "/lab/derive/thin_arrows").points
    thick = scene_node(session, "/lab/derive/arrows").points
    drawn = np.concatenate([thin, thick])
    vectors = drawn[:, 1] - drawn[:, 0]
    for k, link in enumerate(d.numbers[:3]):
        v = np.asarray(link.v, float)
        if np.linalg.norm(v) < 1e-9:
            continue
        unit = v / np.linalg.norm(v)  # an arrow from this link's origin along vₖ, at least 15 % of the arm
        match = [
            w
            for s, w in zip(drawn[:, 0], vectors, strict=True)
            if np.allclose(s, link.origin, atol=1e-5) and np.allclose(w / np.linalg.norm(w), unit, atol=1e-5)
        ]
        assert match and np.linalg.norm(match[0]) >= 0.15 * size - 1e-6, k
    texts = {scene_node(session, f"/lab/derive/label_{k}").text for k in range(6)}
    # The course's worked example: the tool's v = (17.256, −20.13, 0.5) m/s, so |v₃| = 26.5 m/s; the
    # slide's v₁ = 0.5 m/s; ω₃ = q̇₂ + q̇₃ = 135°/s = 2.36 rad/s.
    assert f"v₃ = {np.hypot(np.hypot(17.256, -20.13), 0.5):.3g}\u2009m/s" in texts, texts
    assert "v₁ = 0.5\u2009m/s" in texts and "ω₃ = 2.36\u2009rad/s" in texts, texts


def test_a_new_robot_starts_its_walk_at_joint_1(session):
    choose(session, "puma560")
    derive_walk(session, "propagation", 5)
    choose(session, "trr")
    assert session.state.options.derive_step == 0 and session.panel.derive.step.value == 1
    assert "Step 1 of 3" in _text(session.panel.derive.body.content)


@pytest.mark.slow
def test_course_letters_reach_the_derive_tabs_steps(symbolic_session):
    """With "Course letters", the Derive tab's ⁰Tᵢ and every step use the file's letters (the TRR's
    l₁, l₂, l₃), not its numbers; without, the numbers (typeset by the real symbolic worker)."""
    session = symbolic_session
    choose(session, "trr")
    derive_walk(session, "dh", 1)
    formula = session.panel.derive.formula
    wait_until(lambda: "⁰T₂" in formula.content and "<math" in formula.content, timeout=120)
    assert "<msub><mi>l</mi><mn>2</mn></msub>" not in formula.content
    session.panel.matrix.letters.value = True
    session.settle()
    wait_until(lambda: "<msub><mi>l</mi><mn>2</mn></msub>" in formula.content, timeout=120)
    assert "⁰T₂" in formula.content
