"""Maps of manipulability, ready to draw: a joint-space heat map and a workspace cloud.

The maths is :mod:`kinematics.maps` (batched, no Python loop over samples); here the colours, the
PNG the panel shows and the caches (a map is recomputed only when what it depends on changes: the
robot, the two joints, and the values of the *other* joints).
"""

from __future__ import annotations

import base64
import functools
import struct
import zlib
from dataclasses import dataclass

import numpy as np

from kinematics import Robot, fk, maps

from ..ranges import joint_ranges

__all__ = ["JointMap", "Cloud", "joint_map", "workspace_cloud", "colormap", "png_base64", "MAP_RESOLUTION"]

MAP_RESOLUTION = 48
"""Cells per side of the joint-space map."""
CLOUD_POINTS = 20_000
LIMIT_POINTS = 2_000
"""Extra cloud points with one joint at a limit (002's joint-limit critical points), drawn in LIMIT_RGB."""
LIMIT_RGB = (232, 89, 12)
"""The colour of the joint-limit points (orange)."""
SINGULAR_RGB = (230, 73, 128)
"""The colour of the (near-)singular points, σmin/σmax < SINGULAR_RATIO (pink)."""
SINGULAR_RATIO = 0.01
"""Tool points in the workspace cloud."""

# Viridis at five stops (perceptually ordered, readable by colour-blind viewers): low w dark blue.
_STOPS = np.array([[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]], dtype=float)


def colormap(x: np.ndarray) -> np.ndarray:
    """RGB uint8 (..., 3) of values ``x`` in [0, 1] (clipped; non-finite values as 0)."""
    x = np.clip(np.where(np.isfinite(x), x, 0.0), 0.0, 1.0) * (len(_STOPS) - 1)
    i = np.minimum(x.astype(int), len(_STOPS) - 2)
    f = (x - i)[..., None]
    return np.round(_STOPS[i] * (1 - f) + _STOPS[i + 1] * f).astype(np.uint8)


def png_base64(rgb: np.ndarray) -> str:
    """A PNG of the RGB uint8 image (H, W, 3), base64-encoded (for a data: URL)."""
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[r].tobytes() for r in range(h))

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b"")
    return base64.b64encode(png).decode("ascii")


@dataclass(frozen=True, eq=False)
class JointMap:
    """w over joints i (x, left to right) and j (y, bottom to top), the others held.

    Attributes:
        i, j: The two joints.
        lo, hi: Slider ranges of joints i and j in display units (degrees for revolute) (2,) each.
        w: The grid (resolution, resolution), rows along j, columns along i.
        w_max: Largest w of the grid (the colour scale's top).
        png: The coloured grid as a base64 PNG (row 0 at the top: j highest).
    """

    i: int
    j: int
    lo: tuple[float, float]
    hi: tuple[float, float]
    w: np.ndarray
    w_max: float
    png: str


@functools.lru_cache(maxsize=64)
def _joint_map(robot: Robot, i: int, j: int, key: tuple[float, ...]) -> JointMap:
    q = np.array(key)
    result = maps.joint_map(robot, q, i, j, resolution=MAP_RESOLUTION)
    grid = np.asarray(result.w, dtype=float).T  # w[a, b] is at (values_i[a], values_j[b]): rows along j
    grid = np.where(np.isfinite(grid), grid, 0.0)
    top = float(grid.max()) if grid.size else 0.0
    norm = grid / top if top > 0 else np.zeros_like(grid)
    ranges = joint_ranges(robot)
    vi, vj = np.asarray(result.values_i), np.asarray(result.values_j)
    shown_i = np.degrees(vi) if ranges[i].degrees else vi
    shown_j = np.degrees(vj) if ranges[j].degrees else vj
    lo = (float(shown_i[0]), float(shown_j[0]))
    hi = (float(shown_i[-1]), float(shown_j[-1]))
    return JointMap(i, j, lo, hi, grid, top, png_base64(colormap(norm[::-1])))


def joint_map(robot: Robot, q: np.ndarray, i: int, j: int) -> JointMap:
    """The map of w over joints ``i`` and ``j`` at ``q`` (cached on the values of the other joints:
    moving joint i or j, as on the map, never recomputes it)."""
    key = np.array(q, dtype=float)
    key[[i, j]] = 0.0
    return _joint_map(robot, i, j, tuple(float(x) for x in key))


@dataclass(frozen=True, eq=False)
class Cloud:
    """Tool points of random configurations within the sliders, coloured by w.

    Attributes:
        points: (N, 3) float32 [m].
        colors: (N, 3) uint8.
        w_max: Largest w (the colour scale's top).
        singular: How many of the first CLOUD_POINTS are drawn as (near-)singular (SINGULAR_RGB).
        limits: How many points at the end have a joint at a limit (LIMIT_RGB): the critical points of
            the joint-limit boundary.
    """

    points: np.ndarray
    colors: np.ndarray
    w_max: float
    singular: int = 0
    limits: int = 0


@functools.lru_cache(maxsize=8)
def workspace_cloud(robot: Robot, n: int = CLOUD_POINTS) -> Cloud:
    """The workspace cloud of ``robot`` (computed once per robot)."""
    result = maps.workspace(robot, n, seed=0)
    w = np.asarray(result.w, dtype=float)
    top = float(np.max(w)) if w.size and np.isfinite(w).all() else 0.0
    colors = colormap(w / top if top > 0 else np.zeros_like(w))
    near = np.asarray(result.inverse_kappa) < SINGULAR_RATIO
    colors[near] = SINGULAR_RGB
    # The joint-limit points: random configurations with one joint (at random) at one of its ends.
    rng = np.random.default_rng(1)
    lim = maps.sampling_range(robot)
    Q = rng.uniform(lim[0], lim[1], size=(LIMIT_POINTS, robot.dof))
    joint = rng.integers(0, robot.dof, LIMIT_POINTS)
    Q[np.arange(LIMIT_POINTS), joint] = np.where(rng.random(LIMIT_POINTS) < 0.5, lim[0, joint], lim[1, joint])
    edge = np.array([fk(robot, q)[:3, 3] for q in Q]).reshape(LIMIT_POINTS, 3)
    points = np.vstack([np.asarray(result.points, dtype=np.float32), edge.astype(np.float32)])
    colors = np.vstack([colors, np.tile(np.array(LIMIT_RGB, dtype=np.uint8), (LIMIT_POINTS, 1))])
    return Cloud(points, colors, top, int(near.sum()), LIMIT_POINTS)
