"""Keeping what matters in view: a frustum test, a framing, and a smooth camera move.

The scene says which points must stay visible (arm, tool, ellipsoids,
arrow tips). After a named configuration, a large move, a robot switch or a
change of the canvas's shape (a panel collapsed), the session asks
:func:`needs_framing`; if something left the view, :func:`framing` finds a
camera that keeps the user's viewing direction and fits everything, and a
:class:`CameraMove` glides there in a few frames (time lives in that object,
not in the session).
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = [
    "View",
    "in_view",
    "needs_framing",
    "framing",
    "facing",
    "across",
    "lost_axes",
    "ACROSS_DEGREES",
    "CameraMove",
    "TabCamera",
    "THREE_QUARTER",
    "FROM_ABOVE",
]

THREE_QUARTER = np.array([1.25, -1.45, 0.8])
"""Default viewing direction (from the target towards the camera) for spatial arms."""
FROM_ABOVE = np.array([0.25, -0.35, 1.6])
"""... and for planar arms, which move in the base x-y plane."""


@dataclass(frozen=True)
class View:
    """A pinhole camera: where it is, what it looks at, its vertical field of view and aspect.

    Attributes:
        position, look_at: (3,) [m] in base coordinates.
        up: (3,) up direction.
        fov: Vertical field of view [rad].
        aspect: Width / height of the canvas.
    """

    position: np.ndarray
    look_at: np.ndarray
    up: np.ndarray
    fov: float
    aspect: float


def _basis(view: View) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    forward = view.look_at - view.position
    forward = forward / max(np.linalg.norm(forward), 1e-12)
    right = np.cross(forward, view.up)
    if np.linalg.norm(right) < 1e-9:
        right = np.cross(forward, np.array([1.0, 0, 0]))
    right /= np.linalg.norm(right)
    return forward, right, np.cross(right, forward)


def in_view(view: View, points: np.ndarray, margin: float = 0.92) -> np.ndarray:
    """Which ``points`` (N, 3) lie inside ``margin`` of the view's half-angles (and in front of it)."""
    forward, right, up = _basis(view)
    d = np.asarray(points, float) - view.position
    z = d @ forward
    tan_v = np.tan(view.fov / 2) * margin
    tan_h = tan_v * view.aspect
    with np.errstate(divide="ignore", invalid="ignore"):
        ok = (z > 1e-6) & (np.abs(d @ up) <= tan_v * z) & (np.abs(d @ right) <= tan_h * z)
    return ok


def needs_framing(view: View, points: np.ndarray) -> bool:
    """True when some finite point is out of view, or everything fits in a small part of it."""
    pts = np.asarray(points, float)
    pts = pts[np.isfinite(pts).all(axis=1)]
    if not len(pts):
        return False
    if not in_view(view, pts).all():
        return True
    # Far too small (the arm a speck after a large move back): fits in a quarter of the view.
    return bool(in_view(view, pts, margin=0.2).all())


def framing(
    view: View, points: np.ndarray, direction: np.ndarray | None = None, pad: float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """Camera (position, look_at) that sees all ``points`` from ``direction`` (default: the view's own).

    The target is the centre of the points' bounding box; the distance fits their bounding
    sphere, grown by 10 % and by ``pad`` [m] (what is drawn around the points: link meshes,
    labels), in the narrower of the two fields of view.
    """
    pts = np.asarray(points, float)
    pts = pts[np.isfinite(pts).all(axis=1)]
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    center = (lo + hi) / 2
    radius = max(float(np.linalg.norm(pts - center, axis=1).max()), 0.05) * 1.1 + pad
    if direction is None:
        direction = view.position - view.look_at
    direction = np.asarray(direction, float)
    direction = direction / max(np.linalg.norm(direction), 1e-12)
    half = min(view.fov, 2 * np.arctan(np.tan(view.fov / 2) * view.aspect)) / 2
    return center + direction * radius / np.sin(half), center


def facing(points: np.ndarray) -> np.ndarray:
    """A viewing direction that shows ``points`` (N, 3) spread out: across their best-fit plane.

    The normal of the plane the arm and its glyphs lie closest to (smallest principal axis), turned
    a little towards the default three-quarter view and lifted at least 20° above the horizon, so
    arrows in that plane are seen side-on instead of end-on.
    """
    pts = np.asarray(points, float)
    pts = pts[np.isfinite(pts).all(axis=1)]
    if len(pts) < 3:
        return THREE_QUARTER / np.linalg.norm(THREE_QUARTER)
    _, vectors = np.linalg.eigh(np.cov((pts - pts.mean(axis=0)).T))
    normal = vectors[:, 0]
    tq = THREE_QUARTER / np.linalg.norm(THREE_QUARTER)
    if normal @ tq < 0:
        normal = -normal
    d = normal + 0.5 * tq
    d /= np.linalg.norm(d)
    horizontal = np.hypot(d[0], d[1])
    if d[2] < np.sin(np.radians(20)) or horizontal < 1e-6:
        h = d[:2] / horizontal if horizontal > 1e-6 else tq[:2] / np.linalg.norm(tq[:2])
        d = np.array([*(h * np.cos(np.radians(25))), np.sin(np.radians(25))])
    return d


ACROSS_DEGREES = 60.0
"""At a singularity the view makes at least this angle with every lost direction (when it can)."""


def lost_axes(losses) -> np.ndarray:
    """The directions (k, 3) a singular configuration's picture is about: every lost translation and
    lost rotation axis (the flattened axes of the ellipsoids that flatten lie along them)."""
    axes = [x.translation for x in losses if np.linalg.norm(x.translation) > 0.5]
    axes += [x.rotation for x in losses if np.linalg.norm(x.rotation) > 0.5]
    return np.array(axes).reshape(-1, 3)


def _sphere(count: int = 600) -> np.ndarray:
    """Nearly even directions over the upper half sphere (Fibonacci lattice), 10° above the horizon."""
    k = np.arange(count) + 0.5
    z = np.sin(np.radians(10)) + (1 - np.sin(np.radians(10))) * k / count
    phi = k * np.pi * (3 - np.sqrt(5))
    r = np.sqrt(1 - z * z)
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


_CANDIDATES = _sphere()


def across(direction: np.ndarray, axes: np.ndarray, degrees: float = ACROSS_DEGREES) -> np.ndarray:
    """A viewing direction (from the target to the camera) close to ``direction`` that sees every one of
    ``axes`` (k, 3) across the view: at least ``degrees`` from each (or as far as it can when no view
    does, e.g. three orthogonal axes allow 54.7° at most). ``direction`` itself when it already does."""
    d = np.asarray(direction, float)
    d = d / max(float(np.linalg.norm(d)), 1e-12)
    A = np.asarray(axes, float).reshape(-1, 3)
    if not len(A):
        return d
    limit = np.cos(np.radians(degrees))

    def worst(v: np.ndarray) -> np.ndarray:
        return np.abs(v @ A.T).max(axis=-1)  # cos of the smallest angle to an axis

    if worst(d) <= limit:
        return d
    w = worst(_CANDIDATES)
    ok = w <= max(limit, float(w.min()) + 1e-9)
    candidates = _CANDIDATES[ok]
    return candidates[int(np.argmax(candidates @ d))]


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

    def frame_across(self, points: np.ndarray, pad: float, axes: np.ndarray) -> None:
        """At a singular configuration: glide so that ``axes`` (k, 3), the lost directions, lie across
        the view (:func:`across`), or only re-frame if they already do."""
        view = self.view()
        current = view.position - view.look_at if view is not None else facing(points)
        current = current / max(float(np.linalg.norm(current)), 1e-12)
        direction = across(current, axes)
        if view is None or not np.allclose(direction, current):
            self.frame(points, pad, direction)
        else:
            self.frame_if_needed(points, pad)

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

    def close(self) -> None:
        """Stop any move (the tab has gone)."""
        self._closed = True
        self.mover.cancel()

    def _set(self, position: np.ndarray, look_at: np.ndarray) -> None:
        if self._closed:
            return
        cam = self.client.camera
        cam.up_direction = (0.0, 0.0, 1.0)
        cam.position = np.asarray(position, float)
        cam.look_at = np.asarray(look_at, float)  # after position: setting position moves look_at
