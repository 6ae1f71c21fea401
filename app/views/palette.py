"""Colours: one per joint (its slider, axis, column arrow and bars), one per status, one per glyph.

Rules, each checked by a test:

* glyph colours (twist, force, lost direction, ellipsoids) are far from every
  joint colour (CIE76 ΔE ≥ 25), so "green" never means both ω and q3;
* text drawn in a colour (joint labels, table headers, the status banner)
  has a contrast of at least 4.5:1 (WCAG AA) against its background: joint
  text uses a darkened shade of the joint colour (:func:`joint_text_hex`).
"""

from __future__ import annotations

import functools

import numpy as np

__all__ = [
    "joint_color",
    "joint_hex",
    "joint_text_hex",
    "STATUS_RGB",
    "STATUS_TEXT",
    "status_hex",
    "LINK_RGB",
    "LOST_RGB",
    "TWIST_RGB",
    "TWIST_ANGULAR_RGB",
    "DESIRED_RGB",
    "FORCE_RGB",
    "ACCEL_RGB",
    "JQDD_RGB",
    "PATH_RGB",
    "PLANNED_RGB",
    "ROTATION_ELLIPSOID_RGB",
    "FORCE_ELLIPSOID_RGB",
    "GLYPH_RGB",
    "QUESTION_RGB",
    "hex_of",
    "contrast",
    "delta_e",
]

_JOINTS = (
    (31, 119, 180),  # blue
    (255, 127, 14),  # orange
    (44, 160, 44),  # green
    (148, 103, 189),  # purple
    (140, 86, 75),  # brown
    (227, 119, 194),  # pink
    (23, 190, 207),  # cyan
    (188, 189, 34),  # olive
    (127, 127, 127),  # grey
)

STATUS_RGB = {
    "regular": (59, 91, 219),  # blue
    "near singular": (245, 159, 0),  # amber (dark text on it)
    "singular": (201, 42, 42),  # red
}
STATUS_TEXT = {"regular": "#ffffff", "near singular": "#1f2328", "singular": "#ffffff"}
"""Text colour on each status colour (contrast ≥ 4.5:1)."""
LINK_RGB = (150, 156, 166)
LOST_RGB = (95, 0, 12)  # dark crimson: the lost direction (red family = singular)
TWIST_RGB = (20, 20, 20)  # v = J q̇: black
TWIST_ANGULAR_RGB = (95, 61, 0)  # ω = J q̇: dark umber
DESIRED_RGB = (200, 204, 212)  # the desired tool velocity: light grey (what J q̇ should reach)
FORCE_RGB = (0, 45, 98)  # the applied force and moment: navy
PATH_RGB = (0, 95, 115)  # the tool's traced path: dark teal (no joint, status or glyph uses it)
PLANNED_RGB = (0, 160, 135)  # the path y(t) to follow: sea green, wider, under the dark teal trace
ACCEL_RGB = (180, 0, 255)  # J̇ q̇, the tool's acceleration at constant joint rates: violet
QUESTION_RGB = (60, 60, 60)  # the room's candidate lost directions A–D: charcoal, until one is revealed
JQDD_RGB = (200, 0, 110)  # J q̈, the tool's acceleration from the joint accelerations: magenta
ROTATION_ELLIPSOID_RGB = (0, 120, 90)
FORCE_ELLIPSOID_RGB = (90, 20, 120)
GLYPH_RGB = {
    "lost direction": LOST_RGB,
    "twist v": TWIST_RGB,
    "twist ω": TWIST_ANGULAR_RGB,
    "desired v": DESIRED_RGB,
    "force": FORCE_RGB,
    "acceleration J̇ q̇": ACCEL_RGB,
    "acceleration J q̈": JQDD_RGB,
    "path y(t)": PLANNED_RGB,
}


def joint_color(i: int) -> tuple[int, int, int]:
    """RGB colour of joint ``i`` (0-based)."""
    return _JOINTS[i % len(_JOINTS)]


def hex_of(rgb: tuple[int, int, int] | np.ndarray) -> str:
    """``#rrggbb`` of an RGB triple."""
    r, g, b = (int(x) for x in rgb)
    return f"#{r:02x}{g:02x}{b:02x}"


def joint_hex(i: int) -> str:
    """``#rrggbb`` colour of joint ``i`` (bars, slider tracks, arrows)."""
    return hex_of(joint_color(i))


def _luminance(rgb: tuple[int, int, int] | np.ndarray) -> float:
    c = np.asarray(rgb, float) / 255.0
    lin = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return float(lin @ np.array([0.2126, 0.7152, 0.0722]))


def contrast(fg: tuple[int, int, int] | np.ndarray, bg: tuple[int, int, int] | np.ndarray) -> float:
    """WCAG contrast ratio of two colours (1 to 21)."""
    a, b = sorted((_luminance(fg), _luminance(bg)), reverse=True)
    return (a + 0.05) / (b + 0.05)


def _lab(rgb: tuple[int, int, int] | np.ndarray) -> np.ndarray:
    c = np.asarray(rgb, float) / 255.0
    lin = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    M = np.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]])
    xyz = M @ lin / np.array([0.95047, 1.0, 1.08883])
    f = np.where(xyz > 0.008856, np.cbrt(xyz), 7.787 * xyz + 16 / 116)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


def delta_e(a: tuple[int, int, int], b: tuple[int, int, int]) -> float:
    """CIE76 colour difference (≈ 2.3: just noticeable; ≥ 25: clearly different colours)."""
    return float(np.linalg.norm(_lab(a) - _lab(b)))


@functools.cache
def joint_text_hex(i: int, background: tuple[int, int, int] = (255, 255, 255)) -> str:
    """A shade of joint ``i``'s colour dark enough for text on ``background`` (contrast ≥ 4.5:1)."""
    rgb = np.array(joint_color(i), float)
    while contrast(rgb, background) < 4.6:
        rgb *= 0.92
    return hex_of(rgb.astype(int))


def status_hex(status: str) -> str:
    """``#rrggbb`` colour of a singularity status."""
    return hex_of(STATUS_RGB.get(status, STATUS_RGB["regular"]))
