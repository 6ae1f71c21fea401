"""The course in the app (issue 21, items 12–15): its errors said where each item is shown, its
letters, its digits and one name per joint. Server level: handles set as a user sets them, actions
dispatched, snapshot and panel text read back."""

from __future__ import annotations

import pathlib
import re

import pytest
from app_helpers import assert_all_finite

from app.core.actions import ChooseRobot, SetRate, SetWrench
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
