"""Keeping what matters in view: a frustum test, a framing and a viewing direction (pure geometry).

The scene says which points must stay visible (arm, tool, ellipsoids,
arrow tips). After a named configuration, a large move, a robot switch or a
change of the canvas's shape (a panel collapsed), the tab's camera
(:class:`app.tab.camera.TabCamera`) asks :func:`needs_framing`; if something left the view,
:func:`framing` finds a camera that keeps the user's viewing direction and fits everything.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "View",
    "in_view",
    "project",
    "needs_framing",
    "framing",
    "facing",
    "across",
    "lost_axes",
    "step_axes",
    "arm_axis",
    "label_pairs",
    "PAIR_DEGREES",
    "ACROSS_DEGREES",
    "STEP_DEGREES",
    "ARM_DEGREES",
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


def project(view: View, points: np.ndarray, width: float, height: float) -> np.ndarray:
    """Where ``points`` (N, 3) [m] fall on a ``width`` × ``height`` [px] canvas (N, 2) [px], from its
    top left corner, x to the right and y down (NaN behind the camera): the pinhole of three.js's
    perspective camera, whose ``fov`` is vertical."""
    forward, right, up = _basis(view)
    d = np.asarray(points, float).reshape(-1, 3) - view.position
    z = d @ forward
    f = height / 2 / np.tan(view.fov / 2)  # [px] per unit of tangent
    with np.errstate(divide="ignore", invalid="ignore"):
        x = width / 2 + f * (d @ right) / z
        y = height / 2 - f * (d @ up) / z
    out = np.stack([x, y], axis=1)
    out[z <= 1e-9] = np.nan
    return out


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


ACROSS_DEGREES = 75.0
"""At a singularity the view makes at least this angle with every lost direction (when it can): a
flattened ellipsoid then shows at most cos 75° ≈ 0.26 of its width as thickness, so it looks flat
(at 60° it still showed half its width: a healthy-looking ellipse seen from above)."""


def lost_axes(losses) -> np.ndarray:
    """The directions (k, 3) a singular configuration's picture is about: every lost translation and
    lost rotation axis (the flattened axes of the ellipsoids that flatten lie along them)."""
    axes = [x.translation for x in losses if np.linalg.norm(x.translation) > 0.5]
    axes += [x.rotation for x in losses if np.linalg.norm(x.rotation) > 0.5]
    return np.array(axes).reshape(-1, 3)


def step_axes(derivation) -> np.ndarray:
    """The directions (k, 3) a Derive step draws and must not be seen end-on: for Whitney's method the
    step's axis zᵢ₋₁, its lever pₙ − pᵢ₋₁ and its column Jᵢ; for velocity propagation every vₖ and ωₖ
    drawn up to the step's frame (none for the other methods)."""
    if derivation is None or not derivation.numbers:
        return np.zeros((0, 3))
    if derivation.method == "whitney":
        columns = derivation.numbers  # kinematics.steps.whitney: one column per axis
        vectors = [v for c in columns if c.joint == derivation.joint for v in (c.z, c.r, c.linear)]
    elif derivation.method == "propagation":  # kinematics.steps.propagation: one link per frame
        links = derivation.numbers[: derivation.axes[-1] + 1]
        vectors = [v for link in links for v in (link.v, link.omega)]
    else:
        return np.zeros((0, 3))
    out = [v / np.linalg.norm(v) for v in vectors if np.linalg.norm(v) > 1e-9]
    return np.array(out).reshape(-1, 3)


STEP_DEGREES = {"whitney": 75.0, "propagation": 45.0}
"""How far from the view a Derive step's directions are kept (:func:`step_axes`): Whitney's three
vectors like a lost direction; velocity propagation's many vₖ and ωₖ (ω along z, v across it on the
TRR) at 45°, which a view half-way up allows for both."""
ARM_DEGREES = 35.0
"""The arm's long axis (:func:`arm_axis`) is kept at least this far from the view: an upright boom
seen from above is a dot with its joint labels in one spot."""


PAIR_DEGREES = 20.0
"""Two joint labels apart in space are seen at least this far off the line of sight through both: not
one over the other (0.1 of a 500 px arm stays ≥ 17 px apart)."""


def label_pairs(points: np.ndarray, apart: float) -> np.ndarray:
    """The directions (k, 3) between the labels of joints i and i + 1 (N, 3) at least ``apart`` [m] from
    each other (next joints are the ones a view along a link stacks)."""
    pts = np.asarray(points, float).reshape(-1, 3)
    pts = pts[np.isfinite(pts).all(axis=1)]
    d = pts[1:] - pts[:-1]
    n = np.linalg.norm(d, axis=1)
    keep = n >= apart
    return (d[keep] / n[keep, None]).reshape(-1, 3)


def arm_axis(points: np.ndarray) -> np.ndarray:
    """The direction (1, 3) along which the arm's joint points (N, 3) spread most, when they spread
    along one (the largest spread at least twice the next); else none (0, 3)."""
    pts = np.asarray(points, float).reshape(-1, 3)
    pts = pts[np.isfinite(pts).all(axis=1)]
    if len(pts) < 2:
        return np.zeros((0, 3))
    values, vectors = np.linalg.eigh(np.cov((pts - pts.mean(axis=0)).T))
    spread = np.sqrt(np.clip(values, 0.0, None))
    if spread[2] <= 1e-9 or spread[2] < 2.0 * spread[1]:
        return np.zeros((0, 3))
    return vectors[:, 2].reshape(1, 3)


def _sphere(count: int = 600) -> np.ndarray:
    """Nearly even directions over the upper half sphere (Fibonacci lattice), 10° above the horizon."""
    k = np.arange(count) + 0.5
    z = np.sin(np.radians(10)) + (1 - np.sin(np.radians(10))) * k / count
    phi = k * np.pi * (3 - np.sqrt(5))
    r = np.sqrt(1 - z * z)
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)


_CANDIDATES = _sphere()


def across(
    direction: np.ndarray, axes: np.ndarray, degrees: float | np.ndarray = ACROSS_DEGREES
) -> np.ndarray:
    """A viewing direction (from the target to the camera) close to ``direction`` that sees every one of
    ``axes`` (k, 3) across the view: at least ``degrees`` (one angle, or one per axis) from each, or,
    when no view does (three orthogonal axes allow 54.7° at most), the one that falls least short of
    its angles. ``direction`` itself when it already does."""
    d = np.asarray(direction, float)
    d = d / max(float(np.linalg.norm(d)), 1e-12)
    A = np.asarray(axes, float).reshape(-1, 3)
    if not len(A):
        return d
    limit = np.cos(np.radians(np.broadcast_to(np.asarray(degrees, float), (len(A),))))

    def worst(v: np.ndarray) -> np.ndarray:
        return (np.abs(v @ A.T) - limit).max(axis=-1)  # > 0: some axis closer to the view than its angle

    if worst(d) <= 0:
        return d
    w = worst(_CANDIDATES)
    ok = w <= max(0.0, float(w.min()) + 1e-9)
    candidates = _CANDIDATES[ok]
    return candidates[int(np.argmax(candidates @ d))]
