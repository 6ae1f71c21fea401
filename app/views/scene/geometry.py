"""Drawing helpers: unit meshes, instance poses for segments, and the finite-number guard.

Nothing here is kinematics: these functions turn points and frames the
snapshot already holds into what viser's batched meshes take (positions,
quaternions, per-axis scales), and make sure no non-finite number reaches
the 3-D scene.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import trimesh
import viser.transforms as vtf

__all__ = [
    "set_if_changed",
    "finite",
    "finite_tuple",
    "wxyz",
    "wxyz_one",
    "segment_instances",
    "unit_cylinder",
    "unit_box",
    "TINY",
    "LABEL_SCALE",
    "LOST_LABEL_SCALE",
    "LABEL_CLEARANCE",
    "clear_of",
    "clear_start",
    "ring",
]

LABEL_SCALE = 1.6
"""Screen scale of the 3-D view's text labels (viser's 1.0 draws them about 11 px high: too small for the
back row of a lecture hall; 1.6 gives about 17 px)."""
LOST_LABEL_SCALE = 1.8
"""Screen scale of the words at a lost direction ("wrist: lost rotation axis"): what the room reads at a
singularity, about 20 px high (its capitals 34 mm on a 3 m wide image of 1280 px: 14 arcmin at 8 m)."""
LABEL_CLEARANCE = 0.08
"""Least distance of a glyph's label from a joint's label (and from the glyph's other labels), in robot
sizes: about 30 px at the default framing, more than a label's height."""


def clear_of(point: np.ndarray, taken: np.ndarray, gap: float, planar: bool = False) -> np.ndarray:
    """``point``, or, if it is within ``gap`` of one of ``taken`` (k, 3), moved to ``gap`` from it.

    The move is upward (+z: up on screen from every view the camera takes, so the two texts no longer
    overlap in the image, which a move along the line of sight would leave them doing); for a planar arm,
    seen from above, it is away from the nearer label in the plane. Moved again while another is close.
    """
    p = np.asarray(point, float).copy()
    taken = np.asarray(taken, float).reshape(-1, 3)
    for _ in range(len(taken)):
        d = p - taken
        dist = np.linalg.norm(d, axis=1)
        i = int(np.argmin(dist))
        if dist[i] >= gap * (1 - 1e-9):
            break
        flat = d[i] * np.array([1.0, 1.0, 0.0])
        if planar:
            n = float(np.linalg.norm(flat))
            away = flat / n if n > 1e-12 * gap else np.array([0.0, 1.0, 0.0])
            p = taken[i] + away * gap + np.array([0.0, 0.0, d[i][2]])
        else:  # straight above: the rise makes the distance exactly gap (more if p was higher already)
            rise = np.sqrt(max(gap * gap - float(flat @ flat), 0.0))
            p = taken[i] + flat + np.array([0.0, 0.0, max(rise, d[i][2])])
    return p


def ring(center: np.ndarray, axis: np.ndarray, radius: float, segments: int = 28) -> np.ndarray:
    """Line segments (segments, 2, 3) of a circle about ``axis`` through ``center``."""
    helper = np.array([1.0, 0, 0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1, 0])
    e1 = np.cross(axis, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(axis, e1)
    t = np.linspace(0.0, 2 * np.pi * 0.85, segments + 1)  # an open ring: it reads as a turn
    pts = center + radius * (np.cos(t)[:, None] * e1 + np.sin(t)[:, None] * e2)
    return np.stack([pts[:-1], pts[1:]], axis=1)


def clear_start(point: np.ndarray, u: np.ndarray, links: np.ndarray, gap: float, width: float) -> np.ndarray:
    """Where an arrow from ``point`` along ``u`` starts so that it is outside the arm: ``gap`` beyond
    ``point``, or beyond the last piece of the links (polyline ``links``) within ``width`` of its line."""
    t = np.linspace(0.0, 1.0, 9)
    samples = (links[:-1, None, :] * (1 - t)[None, :, None] + links[1:, None, :] * t[None, :, None]).reshape(
        -1, 3
    )
    d = samples - point
    along = d @ u
    lateral = np.linalg.norm(d - along[:, None] * u, axis=1)
    near = along[(lateral < width) & (along > 0)]
    return point + u * ((float(near.max()) if near.size else 0.0) + gap)


TINY = 1e-4
"""Smallest drawn extent [m]: degenerate shapes are drawn this thin instead of vanishing."""
_LIMIT = 1e3


def finite(a: object, limit: float = _LIMIT) -> np.ndarray:
    """``a`` as float32 with NaN → 0 and values clipped to ±``limit``: safe to send to the scene."""
    arr = np.asarray(a, dtype=np.float64)
    # One reduction decides: the largest |value| is NaN when any value is, so only finite, bounded
    # arrays take the fast path.
    if arr.size == 0 or float(abs(arr).max()) <= limit:
        return arr.astype(np.float32)
    arr = np.nan_to_num(arr, nan=0.0, posinf=limit, neginf=-limit)
    return np.clip(arr, -limit, limit).astype(np.float32)


def finite_tuple(v: object, limit: float = _LIMIT) -> tuple[float, ...]:
    """A short vector as a tuple of floats with NaN → 0 and values clipped to ±``limit`` (what viser's
    pose setters take, without NumPy's per-call cost)."""
    return tuple(min(max(x, -limit), limit) if x == x else 0.0 for x in np.asarray(v, float).tolist())


def wxyz(R: np.ndarray) -> np.ndarray:
    """Unit quaternions (…, 4) [w, x, y, z] of rotation matrices (…, 3, 3)."""
    q = vtf.SO3.from_matrix(np.asarray(R, dtype=np.float64)).wxyz
    norm = np.linalg.norm(q, axis=-1, keepdims=True)
    ok = np.isfinite(q).all(axis=-1, keepdims=True) & (norm > 0.5)
    identity = np.array([1.0, 0.0, 0.0, 0.0])
    return np.where(ok, q / np.where(ok, norm, 1.0), identity)


def wxyz_one(R: np.ndarray) -> tuple[float, float, float, float]:
    """The unit quaternion [w, x, y, z] of one rotation matrix (3, 3), as :func:`wxyz` gives it up to
    sign, in plain Python (a tenth of the cost for a single matrix); identity when not finite."""
    (a, b, c), (d, e, f), (g, h, i) = np.asarray(R, dtype=np.float64)[:3, :3].tolist()
    trace = a + e + i
    if trace > 0.0:  # Shepperd: divide by the largest of 4w², 4x², 4y², 4z²
        t = math.sqrt(trace + 1.0) * 2.0
        q = (0.25 * t, (h - f) / t, (c - g) / t, (d - b) / t)
    elif a > e and a > i:
        t = math.sqrt(max(1.0 + a - e - i, 1e-300)) * 2.0
        q = ((h - f) / t, 0.25 * t, (b + d) / t, (c + g) / t)
    elif e > i:
        t = math.sqrt(max(1.0 + e - a - i, 1e-300)) * 2.0
        q = ((c - g) / t, (b + d) / t, 0.25 * t, (f + h) / t)
    else:
        t = math.sqrt(max(1.0 + i - a - e, 1e-300)) * 2.0
        q = ((d - b) / t, (c + g) / t, (f + h) / t, 0.25 * t)
    norm = math.sqrt(sum(x * x for x in q))
    if not (math.isfinite(norm) and norm > 0.5):
        return (1.0, 0.0, 0.0, 0.0)
    w, x, y, z = (v / norm for v in q)
    return (w, x, y, z)


def segment_instances(p0: np.ndarray, p1: np.ndarray, radius: np.ndarray | float) -> tuple[np.ndarray, ...]:
    """Poses of unit cylinders (radius 1, height 1 along z, centred) spanning p0[i] → p1[i].

    Returns positions (N, 3), wxyzs (N, 4), scales (N, 3). The rotation is the shortest arc
    from z to the segment (quaternion [1 + z·d, z × d], normalised), so a cylinder never
    spins about its own axis as the arm moves. A zero-length segment gets height :data:`TINY`.
    """
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    d = p1 - p0
    length = np.sqrt(np.einsum("ij,ij->i", d, d))  # one call instead of np.linalg.norm's several
    short = length <= TINY
    u = d / np.where(short, 1.0, length)[:, None]
    if short.any():
        u[short] = (0.0, 0.0, 1.0)
    q = np.zeros((len(u), 4))
    q[:, 0] = 1.0 + u[:, 2]
    q[:, 1] = -u[:, 1]
    q[:, 2] = u[:, 0]
    norm = np.sqrt(np.einsum("ij,ij->i", q, q))
    flipped = norm < 1e-9  # pointing along -z: half a turn about x
    q /= np.where(flipped, 1.0, norm)[:, None]
    if flipped.any():
        q[flipped] = (0.0, 1.0, 0.0, 0.0)
    scales = np.empty((len(u), 3))
    scales[:, 0] = radius
    scales[:, 1] = radius
    scales[:, 2] = np.maximum(length, TINY)
    return (p0 + p1) * 0.5, q, scales


@functools.cache
def unit_cylinder() -> tuple[np.ndarray, np.ndarray]:
    """Vertices and faces of a cylinder of radius 1 and height 1 along z, centred at the origin."""
    mesh = trimesh.creation.cylinder(radius=1.0, height=1.0, sections=24)
    return np.asarray(mesh.vertices, np.float32), np.asarray(mesh.faces, np.uint32)


@functools.cache
def unit_box() -> tuple[np.ndarray, np.ndarray]:
    """Vertices and faces of a unit cube centred at the origin."""
    mesh = trimesh.creation.box(extents=(1.0, 1.0, 1.0))
    return np.asarray(mesh.vertices, np.float32), np.asarray(mesh.faces, np.uint32)


_UNSET = object()


def set_if_changed(handle: object, name: str, value: object) -> None:
    """Assign a scalar prop (``visible``, a length, a colour) only when it differs from what we last set.

    viser compares every assignment with the stored value, at a cost; a plain dict lookup is cheaper.
    """
    cache = handle.__dict__.setdefault("_jl_last", {})
    if cache.get(name, _UNSET) == value:
        return
    setattr(handle, name, value)
    cache[name] = value
