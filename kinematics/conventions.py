"""The project's conventions as data: frames, tasks and the names of the rows of J.

Every module that names a frame, a task or a row of J takes it from here, so the
six rows ``[vx, vy, vz, ωx, ωy, ωz]`` are spelled once per medium (plain text,
ASCII for file formats, HTML, LaTeX and MathML).

* **Twists** are ordered ``[v; ω]``: ``v`` is the linear velocity of the tool-frame
  origin [m/s], ``ω`` the angular velocity [rad/s]; row ``r`` of J is row ``r`` of the twist.
* **Frames**: the rows of J are expressed in the base frame (``"base"``, the default) or
  in the tool frame (``"tool"``). Transforms carry both frames in their names:
  ``T_base_tool`` maps tool coordinates to base coordinates.
* **Tasks**: the rows of J a robot is meant to control (:data:`PART_ROWS`); ``"auto"``
  lets :func:`kinematics.analysis.task_rows` choose from the robot's shape.

This module imports nothing from the rest of the package (only NumPy), so anything may import it.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "FloatArray",
    "Frame",
    "FRAMES",
    "Task",
    "TASKS",
    "Part",
    "PART_ROWS",
    "ROW_TEXT",
    "ROW_ASCII",
    "ROW_HTML",
    "ROW_LATEX",
    "ROW_MATHML",
    "WRENCH_TEXT",
]

FloatArray = NDArray[np.float64]
"""What the numeric functions return: float arrays (shapes in each docstring: (n,) for one
configuration, (4, 4) transforms, (6, n) Jacobians, with a leading (N, …) for batches). They take
anything :data:`numpy.typing.ArrayLike` and check it."""

Frame = Literal["base", "tool"]
FRAMES: tuple[Frame, ...] = ("base", "tool")
"""The frames the rows of J (and twists, wrenches) can be expressed in."""

Task = Literal["auto", "full", "linear", "angular", "planar"]
TASKS: tuple[Task, ...] = ("auto", "full", "linear", "angular", "planar")
"""A robot file's ``task``: which rows of J the robot controls (``auto``: chosen from its shape)."""

Part = Literal["full", "linear", "angular", "planar"]
PART_ROWS: dict[str, tuple[int, ...]] = {
    "full": (0, 1, 2, 3, 4, 5),
    "linear": (0, 1, 2),
    "angular": (3, 4, 5),
    "planar": (0, 1, 5),
}
"""The row indices of J each named part (and each task but ``auto``) stands for."""

ROW_TEXT = ("vx", "vy", "vz", "ωx", "ωy", "ωz")
"""Row names of J (and of a twist) in plain Unicode text."""

ROW_ASCII = ("vx", "vy", "vz", "wx", "wy", "wz")
"""Row names in ASCII, for file formats read by programs (JSON export)."""

ROW_HTML = tuple(f"{a}<sub>{b}</sub>" for a in ("v", "ω") for b in "xyz")
"""Row names in HTML: ``v<sub>x</sub>`` …"""

ROW_LATEX = tuple(f"{a}_{{{b}}}" for a in ("v", "\\omega") for b in "xyz")
"""Row names in LaTeX math: ``v_{x}`` … ``\\omega_{z}``."""

ROW_MATHML = tuple(f"<msub><mi>{a}</mi><mi>{b}</mi></msub>" for a in ("v", "ω") for b in "xyz")
"""Row names in MathML (presentation markup, no ``<math>`` element around them)."""

WRENCH_TEXT = ("Fx", "Fy", "Fz", "Mx", "My", "Mz")
"""Row names of a wrench ``[F; M]`` (force [N], moment [N m]) in plain text."""
