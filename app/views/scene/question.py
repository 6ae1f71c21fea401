"""The room's "which direction is lost?" in the 3-D view: the candidate lines A, B, C, D at the loss's point.

While the question is open every candidate is drawn as a line through the point (a lost direction has no
sense), each with its letter and what it is ("A: translation", "B: rotation axis"); once revealed, only
the right one stays, in the lost direction's colour, with its words, and the arm's own lost-direction
glyph (hidden while the room answers: :class:`app.views.scene.SceneView`) comes back. Nothing is drawn
for the other questions.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import viser

from ...core.i18n import N_, Translator
from ...core.poll import Seen
from ...core.snapshot import Snapshot
from ...core.state import LabState
from ..camera import View, project
from ..palette import LOST_RGB, QUESTION_RGB
from .geometry import LOST_LABEL_SCALE, finite, finite_tuple, set_if_changed
from .labels import anchor_label

__all__ = ["QuestionScene", "MAX_CANDIDATES", "candidate_segments", "label_points", "hide_lost"]

MAX_CANDIDATES = 6
_WORDS = {"translation": N_("{letter}: translation"), "rotation": N_("{letter}: rotation axis")}


def candidate_segments(seen: Seen, half: float) -> tuple[np.ndarray, list[int]]:
    """The lines (k, 2, 3) drawn for ``seen``'s candidates, ``half`` [m] each way, and which candidates
    they are (all while the question is open; the right ones once revealed)."""
    q = seen.question
    keep = [
        i
        for i, letter in enumerate(q.choices[: len(q.arrows)])
        if seen.phase != "revealed" or letter in q.right
    ]
    lines = [
        [np.array(q.arrows[i].point) - half * np.array(q.arrows[i].direction),
         np.array(q.arrows[i].point) + half * np.array(q.arrows[i].direction)]
        for i in keep
    ]  # fmt: skip
    return (np.array(lines, dtype=float) if lines else np.zeros((0, 2, 3))), keep


def hide_lost(overlays: Any) -> None:
    """Hide the arm's lost-direction glyph (its arrow, its axis and ring, its words) until the reveal; the
    ellipsoids and everything else stay as they are."""
    overlays.lost_v.hide()
    set_if_changed(overlays.lost_w, "visible", False)
    for label in overlays.lost_labels:
        set_if_changed(label, "visible", False)
    overlays.lost_tips = np.zeros((0, 3))


def label_points(
    segments: np.ndarray, taken: np.ndarray, view: View | None, width: float = 1280.0, height: float = 720.0
) -> np.ndarray:
    """Where each candidate's letter goes (k, 3): on its line, at whichever of a few points along it
    (either end, or three quarters out) lies farthest on screen from the letters already placed and from
    ``taken`` (the joints' labels), so two candidates' words never sit on each other whatever the camera.
    Without a view (a recording), the lines' far ends."""
    if view is None or not len(segments):
        return segments[:, 1] if len(segments) else np.zeros((0, 3))
    centre = 0.5 * (segments[:, 0] + segments[:, 1])
    placed: list[np.ndarray] = [project(view, taken, width, height)] if len(taken) else []
    out = []
    for k in range(len(segments)):
        tries = np.array([segments[k, 1], segments[k, 0]] + [centre[k] + f * (segments[k, e] - centre[k])
                         for e in (1, 0) for f in (0.75, 0.55)])  # fmt: skip
        screen = project(view, tries, width, height)
        others = np.concatenate(placed) if placed else np.zeros((0, 2))
        gap = (
            np.min(np.linalg.norm(screen[:, None, :] - others[None, :, :], axis=2), axis=1)
            if len(others)
            else np.zeros(len(tries))
        )
        best = int(np.argmax(np.where(np.isfinite(gap), gap, -1.0)))
        out.append(tries[best])
        placed.append(screen[best : best + 1])
    return np.array(out)


class QuestionScene:
    """The candidate lines of a "lost" question for one tab's scene."""

    def __init__(
        self,
        scene: viser.SceneApi,
        size: float,
        root: str,
        tr: Translator,
        seen: Callable[[], Seen | None],
        view: Callable[[], View | None] = lambda: None,
        joint_labels: Callable[[], np.ndarray] = lambda: np.zeros((0, 3)),
    ) -> None:
        self._seen, self._tr, self._half = seen, tr, 0.45 * size
        self._view, self._joint_labels = view, joint_labels
        self.lines = scene.add_line_segments(
            f"{root}/question_lines",
            points=np.zeros((1, 2, 3), dtype=np.float32),
            colors=np.array(QUESTION_RGB, dtype=np.uint8),
            thickness=5.0,
            thickness_units="screen",
            visible=False,
        )
        self.labels = [
            scene.add_label(
                f"{root}/question_label_{i}", "", visible=False, anchor="bottom-left",
                font_screen_scale=LOST_LABEL_SCALE,
            )
            for i in range(MAX_CANDIDATES)
        ]  # fmt: skip
        self.extent: np.ndarray = np.zeros((0, 3))

    def update(self, snap: Snapshot, state: LabState) -> None:
        seen = self._seen()
        shown = seen is not None and seen.question.kind == "lost" and seen.question.robot == state.robot.name
        segments, keep = candidate_segments(seen, self._half) if shown and seen is not None else (None, [])
        set_if_changed(self.lines, "visible", bool(keep))
        if segments is not None and keep and seen is not None:
            revealed = seen.phase == "revealed"
            self.lines.points = finite(segments)
            self.lines.colors = np.array(LOST_RGB if revealed else QUESTION_RGB, dtype=np.uint8)
            self.extent = segments.reshape(-1, 3)
        else:
            self.extent = np.zeros((0, 3))
        at = label_points(segments, self._joint_labels(), self._view()) if segments is not None else None
        for j, label in enumerate(self.labels):
            visible = j < len(keep)
            set_if_changed(label, "visible", visible)
            if visible and seen is not None and segments is not None:
                i = keep[j]
                arrow = seen.question.arrows[i]
                text = self._tr.gettext(_WORDS[arrow.part]).format(letter=seen.question.choices[i])
                if label.text != text:
                    label.text = text
                anchor_label(label, finite_tuple(at[j] if at is not None else segments[j][1]))

    def remove(self) -> None:
        self.lines.remove()
        for label in self.labels:
            label.remove()
