"""Three of the course's ideas in the Motion tab: the null joint motion at a singularity (Ker J), said in
words and played; the Jacobian IK along a path y(t) (a line or a circle from the tool point); and the
several IK solutions of one pose (elbow up / down, wrist flip), found, listed and selectable.

At a singularity some joint rates move nothing at the tool (J q̇ = 0): the Puma's wrist at q₅ = 0
turns q₄ and q₆ against each other. The snapshot holds that motion (``snap.null``); this folder
says it and its button plays it back and forth (the arm moves, the tool stands still).
"""

from __future__ import annotations

import math

import numpy as np
import viser

from kinematics import fk
from kinematics.motion.ik import pose_error, target_rows

from ...core.actions import ChooseToolPath, FollowToolPath, PlayNullMotion, SelectIkSolution
from ...core.commands import FindIkSolutions
from ...core.i18n import N_, Translator
from ...core.self_motion import null_motion_text
from ...core.snapshot import Snapshot
from ...core.state import LabState
from ...core.tool_path import SHAPES
from .. import fmt
from .common import Dispatch, bind, sync_value

__all__ = ["NullMotionPanel", "PathPanel", "SolutionsPanel", "CourseMotion"]


class NullMotionPanel:
    """The null-motion folder: its words and its Play button (disabled where J has full rank)."""

    def __init__(self, gui: viser.GuiApi, dispatch: Dispatch, tr: Translator) -> None:
        self.tr = tr
        _ = tr.gettext
        with gui.add_folder(_("Null motion at a singularity (Ker J)"), expand_by_default=False):
            self.words = gui.add_html("")
            self.button = gui.add_button(
                _("Play the null motion"), icon=viser.Icon.PLAYER_PLAY, disabled=True
            )
            self.button.on_click(lambda _: dispatch(PlayNullMotion()))
        self._shown: str | None = None

    def draw(self, snap: Snapshot) -> None:
        html = self.html(snap)
        if html != self._shown:
            self._shown = html
            self.words.content = html
            self.button.disabled = snap.null is None

    def html(self, snap: Snapshot) -> str:
        """The folder's words for ``snap``."""
        _ = self.tr.gettext
        if snap.null is None:
            text = _(
                "J has full rank here: every joint motion moves the tool. At a singularity, some do not."
            )
            return f'<div class="jl"><div class="jl-note">{fmt.escape(text)}</div></div>'
        motion = null_motion_text(snap.null.direction, lambda c: fmt.number(c, 4, self.tr))
        text = _(
            "At this singularity the joint motion {motion} lies in Ker J: J q̇ = 0, "
            "the joints move and the tool stands still."
        ).format(motion=motion)
        return f'<div class="jl"><div class="jl-note">{fmt.escape(text)}</div></div>'


SHAPE_WORDS = {"": N_("no path"), "line": N_("a line"), "circle": N_("a circle")}
"""The path menu's entries, in English (shown in the tab's language); "" chooses none."""


class PathPanel:
    """The path folder: the course's method in words, a menu of paths (the one chosen is drawn in the 3-D
    view from the tool point) and a Follow button (disabled until a path is chosen)."""

    def __init__(self, gui: viser.GuiApi, dispatch: Dispatch, tr: Translator) -> None:
        _ = tr.gettext
        self._shapes = {_(SHAPE_WORDS[s]): s for s in ("", *SHAPES)}  # the menu's words → the shape
        with gui.add_folder(_("Follow a path y(t): the Jacobian method"), expand_by_default=False):
            text = _(
                "Newton finds q(t₀) with k(q(t₀)) = y(t₀); then q̇ = J⁻¹ẏ(t) (J⁺ẏ(t) + (I − J⁺J)ω(t) "
                "for a redundant arm, here ω = 0) carries the tool along the path, through the tool point. "
                "The rates chart shows q̇(t); near a singularity they blow up and the tool leaves the path."
            )
            gui.add_html(f'<div class="jl"><div class="jl-note">{fmt.escape(text)}</div></div>')
            self.shape = gui.add_dropdown(
                _("Path"), tuple(self._shapes), initial_value=next(iter(self._shapes))
            )
            bind(self.shape, dispatch, self._choose)
            self.button = gui.add_button(_("Follow the path"), icon=viser.Icon.ROUTE, disabled=True)
            self.button.on_click(lambda _: self._follow(dispatch))
        self._words = {s: w for w, s in self._shapes.items()}

    def _choose(self, value: object) -> ChooseToolPath | None:
        shape = self._shapes.get(str(value))  # a value the menu offers, else nothing
        return None if shape is None else ChooseToolPath(shape)

    def _follow(self, dispatch: Dispatch) -> None:
        shape = self._shapes.get(str(self.shape.value))  # a value the menu offers, else nothing
        if shape:
            dispatch(FollowToolPath(shape))

    def draw(self, state: LabState) -> None:
        """The menu shows the state's path (a follower's, a new robot's: none); Follow needs one."""
        sync_value(self.shape, self._words.get(state.tool_path, self._words[""]))
        if self.button.disabled != (not state.tool_path):
            self.button.disabled = not state.tool_path


class SolutionsPanel:
    """The IK solutions folder: Find, a menu of the solutions found, and how far apart they are."""

    def __init__(self, gui: viser.GuiApi, dispatch: Dispatch, tr: Translator) -> None:
        self.tr = tr
        _ = tr.gettext
        self._labels: dict[str, int] = {}  # the menu's entries → the solution's index
        with gui.add_folder(_("The IK solutions of this pose"), expand_by_default=False):
            self.find = gui.add_button(_("Find the IK solutions"), icon=viser.Icon.SEARCH)
            self.find.on_click(lambda _: dispatch(FindIkSolutions()))
            self.menu = gui.add_dropdown(_("Solution"), ("—",), initial_value="—", disabled=True)
            bind(self.menu, dispatch, self._select)
            self.words = gui.add_html("")
        self._shown: tuple | None = None

    def _select(self, value: object) -> SelectIkSolution | None:
        index = self._labels.get(str(value))  # an entry the menu offers, else nothing
        return None if index is None else SelectIkSolution(index)

    def draw(self, state: LabState) -> None:
        m = state.motion
        key = (id(m.solutions), tuple(np.round(state.q, 9)))
        if key == self._shown:
            return
        self._shown = key
        _ = self.tr.gettext
        if m.solutions is None or m.pose is None:
            self.words.content = self._note(
                _("One pose, several arms: press Find to see every IK solution of the tool's pose.")
            )
            return
        revolute = [j.kind == "revolute" for j in state.robot.joints]
        self._labels = {self._label(k, q, revolute): k for k, q in enumerate(m.solutions)}
        labels = tuple(self._labels) or ("—",)
        self.menu.options = labels
        self.menu.disabled = not self._labels
        here = next((k for k, q in enumerate(m.solutions) if np.abs(q - state.q).max() < 1e-6), None)
        if here is not None:
            sync_value(self.menu, labels[here])
        # the rows IK solves (a planar 2R's elbows reach one point with two tool orientations)
        rows = target_rows(state.robot, False, None)
        stale = float(np.abs(pose_error(fk(state.robot, np.array(state.q)), m.pose)[rows]).max()) > 1e-6
        gap = _nearest_gap(m.solutions, revolute)
        count = len(m.solutions)
        text = self.tr.ngettext(
            "{count} IK solution reaches this pose.", "{count} IK solutions reach this pose.", count
        ).format(count=count)
        if math.isfinite(gap):
            text += " " + _(
                "The nearest two are {gap} apart in joint space: they merge as the arm nears a singularity."
            ).format(gap=fmt.number(gap, 3, self.tr))
        if stale:
            text += " " + _("The arm has left that pose since: press Find again.")
        self.words.content = self._note(text)

    def _label(self, k: int, q: np.ndarray, revolute: list[bool]) -> str:
        values = ", ".join(
            f"{fmt.number(math.degrees(x), 4, self.tr)}°" if r else f"{fmt.number(x, 4, self.tr)} m"
            for x, r in zip(q, revolute, strict=True)
        )
        return f"{k + 1}: ({values})"

    @staticmethod
    def _note(text: str) -> str:
        return f'<div class="jl"><div class="jl-note">{fmt.escape(text)}</div></div>'


def _nearest_gap(solutions: np.ndarray, revolute: list[bool]) -> float:
    """The smallest distance between two solutions, revolute joints modulo 2π [rad | m] (inf: fewer)."""
    best = math.inf
    rev = np.array(revolute)
    for i in range(len(solutions)):
        for j in range(i + 1, len(solutions)):
            d = solutions[i] - solutions[j]
            d[rev] = (d[rev] + math.pi) % (2.0 * math.pi) - math.pi
            best = min(best, float(np.linalg.norm(d)))
    return best


class CourseMotion:
    """The null-motion, path and IK solutions folders of the Motion tab."""

    def __init__(self, gui: viser.GuiApi, dispatch: Dispatch, tr: Translator) -> None:
        self.null = NullMotionPanel(gui, dispatch, tr)
        self.path = PathPanel(gui, dispatch, tr)
        self.solutions = SolutionsPanel(gui, dispatch, tr)

    def draw(self, state: LabState, snap: Snapshot) -> None:
        self.null.draw(snap)
        self.path.draw(state)
        self.solutions.draw(state)
