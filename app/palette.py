"""Colours: one per joint (shared by its slider, axis, column arrow and bars) and one per status.

Joint colours are saturated enough to read on a white projector screen and
avoid red, which is kept for singularities.
"""

from __future__ import annotations

__all__ = [
    "joint_color",
    "joint_hex",
    "STATUS_RGB",
    "status_hex",
    "LINK_RGB",
    "LOST_RGB",
    "LOST_ANGULAR_RGB",
    "TWIST_RGB",
    "FORCE_RGB",
    "ROTATION_RGB",
    "FORCE_ELLIPSOID_RGB",
    "hex_of",
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
    "regular": (66, 99, 235),  # calm blue
    "near singular": (245, 159, 0),  # amber
    "singular": (224, 49, 49),  # red
}
LINK_RGB = (150, 156, 166)
LOST_RGB = (201, 42, 42)
LOST_ANGULAR_RGB = (134, 46, 156)
TWIST_RGB = (33, 37, 41)
FORCE_RGB = (230, 73, 128)
ROTATION_RGB = (12, 166, 120)
FORCE_ELLIPSOID_RGB = (174, 62, 201)


def joint_color(i: int) -> tuple[int, int, int]:
    """RGB colour of joint ``i`` (0-based)."""
    return _JOINTS[i % len(_JOINTS)]


def hex_of(rgb: tuple[int, int, int]) -> str:
    """``#rrggbb`` of an RGB triple."""
    return "#{:02x}{:02x}{:02x}".format(*rgb)


def joint_hex(i: int) -> str:
    """``#rrggbb`` colour of joint ``i``."""
    return hex_of(joint_color(i))


def status_hex(status: str) -> str:
    """``#rrggbb`` colour of a singularity status."""
    return hex_of(STATUS_RGB.get(status, STATUS_RGB["regular"]))
