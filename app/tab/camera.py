"""One tab's camera and its policy: when to re-frame what is drawn, and a smooth move there.

After each commit the session hands :meth:`TabCamera.after_commit` what changed: a new robot is
framed at once from a direction that shows it spread out (from above for a planar arm); a jump
(a named configuration, a large move, :func:`is_jump`) or an edit in the Build tab glides to a new
framing only when something drawn left the view; a reshaped canvas (a panel collapsed, the window
resized) is checked the same way. A follower's camera is the presenter's (:meth:`TabCamera.look`).
The geometry (frustum test, framing, facing) is :mod:`app.views.camera`.
"""

from __future__ import annotations

import contextlib
import threading
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from ..core.actions import Action, GoTo, ReplaceState, SetConfiguration, SetJoint
from ..core.build_table import BUILT_NAME
from ..core.state import LabState
from ..views.camera import (
    ACROSS_DEGREES,
    ARM_DEGREES,
    FROM_ABOVE,
    PAIR_DEGREES,
    STEP_DEGREES,
    View,
    across,
    arm_axis,
    facing,
    framing,
    label_pairs,
    lost_axes,
    needs_framing,
    step_axes,
)
from ..viser_adapter import set_camera

__all__ = ["CameraMove", "TabCamera", "is_jump", "JUMP"]

JUMP = 0.35
"""A joint moving more than this [rad | m] in one action is a jump: the camera may re-frame."""
PAD = 0.18
"""Margin around the points drawn, as a fraction of the scene's size (link meshes and labels)."""


def is_jump(before: LabState, after: LabState, action: Action) -> bool:
    """Whether ``action`` moved the arm far at once (the camera may need to follow)."""
    if isinstance(action, (GoTo, SetConfiguration, ReplaceState)):
        return True
    if isinstance(action, SetJoint) and before.robot is after.robot:
        return bool(np.max(np.abs(np.asarray(after.q) - np.asarray(before.q))) > JUMP)
    return False


def _new_step(state: LabState, old: LabState) -> bool:
    """The Derive tab moved to another method or step."""
    o, p = state.options, old.options
    return bool(o.derive) and (o.derive, o.derive_step) != (p.derive, p.derive_step)


def across_of(scene: Any, snap: Any) -> tuple[np.ndarray, np.ndarray, int, int]:
    """The directions (k, 3) the view must see across and each one's least angle (k,) [°]: the lost
    directions of a singular configuration, the open Derive step's vectors, the arm's long axis, the
    lines through two joint labels apart; then how many are lost directions and how many the step's."""
    none = np.zeros((0, 3))
    if snap is None:
        return none, np.zeros(0), 0, 0
    derive_open = getattr(scene, "open_tab", "") in ("", "derive")  # its glyphs are drawn
    steps = step_axes(snap.derive) if derive_open else none
    lost = lost_axes(snap.losses)
    arm = arm_axis(snap.link_frames[:, :3, 3])
    step_degrees = STEP_DEGREES.get(snap.derive.method, ACROSS_DEGREES) if len(steps) else 0.0
    arm_labels = getattr(getattr(scene, "arm", None), "label_points", none)
    pairs = label_pairs(arm_labels, 0.1 * scene.size)
    degrees = [ACROSS_DEGREES] * len(lost) + [step_degrees] * len(steps) + [ARM_DEGREES] * len(arm)
    degrees += [PAIR_DEGREES] * len(pairs)
    return np.vstack([lost, steps, arm, pairs]), np.array(degrees), len(lost), len(steps)


class CameraMove:
    """Glide a client's camera to a new pose in a few frames (a new move replaces a running one).

    Args:
        apply: Sets the camera to (position, look_at).
        duration: Length of the move [s].
        frames: Number of intermediate poses.
    """

    def __init__(self, apply, duration: float = 0.35, frames: int = 10) -> None:
        self.apply = apply
        self.duration = duration
        self.frames = frames
        self._generation = 0
        self._lock = threading.Lock()

    def to(self, start: tuple[np.ndarray, np.ndarray], end: tuple[np.ndarray, np.ndarray]) -> None:
        """Start gliding from ``start`` to ``end`` (each (position, look_at))."""
        with self._lock:
            self._generation += 1
            generation = self._generation
        threading.Thread(target=self._run, args=(generation, start, end), daemon=True).start()

    def cancel(self) -> None:
        """Stop a running move where it is."""
        with self._lock:
            self._generation += 1

    def _run(self, generation: int, start, end) -> None:
        (p0, t0), (p1, t1) = start, end
        for k in range(1, self.frames + 1):
            with self._lock:
                if generation != self._generation:
                    return
            s = k / self.frames
            s = s * s * (3 - 2 * s)  # ease in and out
            self.apply(p0 + (p1 - p0) * s, t0 + (t1 - t0) * s)
            if k < self.frames:
                time.sleep(self.duration / self.frames)


class TabCamera:
    """One tab's camera: reads the browser's view, frames what is drawn, glides there.

    Args:
        client: The tab's viser client (its ``camera``).
    """

    def __init__(self, client: Any) -> None:
        self.client = client
        self.mover = CameraMove(self._set)
        self._aspect = 0.0
        self._closed = False
        self.moved: Callable[[], None] = lambda: None
        """Called after each pose the tab sets (its labels are placed again)."""

    def view(self) -> View | None:
        """The browser's current view, or None before its first camera message."""
        cam = self.client.camera
        try:
            aspect, fov = float(cam.aspect), float(cam.fov)
        except Exception:
            return None
        if not (np.isfinite(aspect) and aspect > 0.05 and np.isfinite(fov) and fov > 0.05):
            return None
        return View(
            np.asarray(cam.position, float),
            np.asarray(cam.look_at, float),
            np.array([0.0, 0, 1]),
            fov,
            aspect,
        )

    def frame(
        self, points: np.ndarray, pad: float, direction: np.ndarray | None = None, glide: bool = True
    ) -> None:
        """Point the camera at ``points`` (+ ``pad`` [m]) from ``direction`` (default: the current one)."""
        view = self.view()
        if view is None:  # no camera message yet: assume a 16:9 canvas and viser's default fov
            view = View(np.array([1.3, -1.5, 0.9]), np.zeros(3), np.array([0.0, 0, 1]), 1.3, 1.4)
        end = framing(view, points, direction, pad=pad)
        if glide:
            self.mover.to((view.position, view.look_at), end)
        else:
            self.mover.cancel()
            self._set(*end)

    def frame_if_needed(self, points: np.ndarray, pad: float) -> None:
        """Glide to a framing only when something drawn left the view (or shrank to a speck)."""
        view = self.view()
        if view is not None and needs_framing(view, points):
            self.frame(points, pad)

    def canvas_changed(self, aspect: float) -> bool:
        """Record the canvas's aspect; True the first time and when it changed by more than 5 %."""
        changed = not self._aspect or abs(aspect - self._aspect) > 0.05 * self._aspect
        self._aspect = aspect
        return changed

    def after_commit(
        self, scene: Any, state: LabState, old: LabState, rebuild: bool, jump: bool, snap: Any = None
    ) -> None:
        """Re-frame ``scene`` (its ``extent`` and ``size``) after ``old`` became ``state`` if the policy
        says so: a new robot at once, a jump or a Build-tab edit only when something left the view, a
        jump to a singular configuration (``snap``: its losses) so the lost directions lie across the
        view, a new Derive step so its vectors do."""
        pad = PAD * scene.size
        edited = state.robot_name == old.robot_name == BUILT_NAME  # the Build tab: keep the user's view
        axes, degrees, lost, steps = across_of(scene, snap)
        if rebuild and not edited:
            direction = FROM_ABOVE if state.robot.planar else facing(scene.extent)
            self.frame(scene.extent, pad, across(direction, axes, degrees), glide=False)
        elif (jump and lost) or (steps and _new_step(state, old)):
            self.frame_across(scene.extent, pad, axes, degrees)
        elif jump or edited:
            self.frame_if_needed(scene.extent, pad)

    def reset(self, scene: Any, state: LabState) -> None:
        """Frame the whole of ``scene`` from the robot's default direction (the View tab's Reset view)."""
        if scene is not None:
            direction = FROM_ABOVE if state.robot.planar else facing(scene.extent)
            self.frame(scene.extent, PAD * scene.size, direction, glide=False)

    def frame_across(
        self, points: np.ndarray, pad: float, axes: np.ndarray, degrees: float | np.ndarray = ACROSS_DEGREES
    ) -> None:
        """At a singular configuration or a new Derive step: glide so that ``axes`` (k, 3), the lost
        directions and the step's vectors, lie across the view, at least ``degrees`` from it
        (:func:`~app.views.camera.across`), or only re-frame if they already do."""
        view = self.view()
        current = view.position - view.look_at if view is not None else facing(points)
        current = current / max(float(np.linalg.norm(current)), 1e-12)
        direction = across(current, axes, degrees)
        if view is None or not np.allclose(direction, current):
            self.frame(points, pad, direction)
        else:
            self.frame_if_needed(points, pad)

    def canvas_moved(self, aspect: float, scene: Any) -> None:
        """The canvas may have changed shape: keep everything in view."""
        if self.canvas_changed(aspect) and scene is not None:
            self.frame_if_needed(scene.extent, PAD * scene.size)

    def look(self, position: tuple, look_at: tuple, up: tuple) -> None:
        """Look where the presenter looks (a follower's camera); a scene the tab draws itself (a follower
        in another language) has its labels placed for that pose in the tab's own canvas, now: not on
        the browser's echo of the pose, which may come late or never (a bare client)."""
        if self._closed:
            return
        with contextlib.suppress(Exception), self.client.atomic():
            set_camera(self.client, position, look_at, up)
        self.moved()

    def close(self) -> None:
        """Stop any move (the tab has gone)."""
        self._closed = True
        self.mover.cancel()

    def _set(self, position: np.ndarray, look_at: np.ndarray) -> None:
        if self._closed:
            return
        set_camera(self.client, position, look_at, (0.0, 0.0, 1.0))
        self.moved()
