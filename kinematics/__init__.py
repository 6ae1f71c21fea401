"""Jacobian Lab kinematics: numeric (NumPy) and symbolic (SymPy) manipulator Jacobians.

Conventions, kept everywhere in this project:

* **Units.** SI inside: metres, radians, seconds. Degrees appear only at the
  edges (revolute sliders, robot data files) and are converted at once.
* **Twists** are ordered ``[v; ω]``: ``v`` is the linear velocity of the
  *tool-frame origin* and ``ω`` the angular velocity, both expressed in the
  frame a function names (``frame="base"`` by default, or ``"tool"``).
  The geometric Jacobian maps joint rates to that twist: ``[v; ω] = J(q) q̇``.
* **Frames in names.** ``T_a_b`` is the 4×4 homogeneous transform mapping
  coordinates in frame *b* to frame *a* (``T_base_tool``: the tool pose in the
  base frame); ``R_a_b`` its rotation, ``p_a_b`` its translation.
* **Shapes and types.** One configuration ``q`` has shape (n,), a batch (N, n); results
  follow: (4, 4) / (N, 4, 4) transforms, (6, n) / (N, 6, n) Jacobians. Numeric functions take
  any ``numpy.typing.ArrayLike`` and return ``NDArray[np.float64]``
  (:data:`kinematics.conventions.FloatArray`); ``mypy --strict`` holds on the package.
* **One place.** Frames, tasks and the names of J's rows (text, HTML, LaTeX, MathML) are data in
  :mod:`kinematics.conventions`; everything that names them takes them from there.
* **Limits** bound sliders and sampling, never the maths: :func:`fk` and
  :func:`jacobian` accept any finite ``q`` (up to 1e18 rad and 1e15 m; angles are reduced
  modulo 2π, so transforms stay rigid). A limit of magnitude ≥ 1e15 (a URDF's ±1e16, ±inf)
  means "unlimited" (:attr:`Joint.qlim` is then ``None``).
* **Errors.** Every bad input raises a :class:`JacobianLabError` (a ``ValueError``) whose
  message names the row, key, joint, attribute or argument and what was expected; see
  :mod:`kinematics.errors`.
* **The model is immutable.** A :class:`Robot` never changes; the current
  configuration lives with the caller, and kinematics are functions of
  ``(robot, q)``.
* **Caches** on disk live under ``$XDG_CACHE_HOME/jacobian-lab`` (default
  ``~/.cache/jacobian-lab``); see :func:`kinematics.cache_dir`.
"""

from __future__ import annotations

import os
from pathlib import Path

from .analysis import (
    Ellipsoid,
    condition_number,
    force_ellipsoid,
    inverse_condition_number,
    manipulability,
    null_space,
    rank,
    select_rows,
    singular_values,
    task_rows,
    velocity_ellipsoid,
)
from .analytic_jacobian import analytic_jacobian, euler_angles, euler_rate_matrix
from .batched import Batch, batch
from .errors import (
    ArrayError,
    ConfigurationError,
    JacobianLabError,
    OptionError,
    RepresentationSingularityError,
    RobotDefinitionError,
    UnknownRobotError,
    UrdfError,
)
from .inverse import dls, nullspace_projector, pinv, solve_rates
from .model import Axis, DHRow, Joint, NamedConfiguration, Robot
from .numeric import (
    as_configuration,
    chain_frames,
    fk,
    jacobian,
    jacobian_dot,
    jacobian_dot_alone,
    joint_frames,
    link_frames,
)
from .singularity import SingularityReport, assess
from .urdf import robot_from_urdf, to_urdf

__all__ = [
    "Robot",
    "Joint",
    "Axis",
    "DHRow",
    "NamedConfiguration",
    "fk",
    "jacobian",
    "jacobian_dot",
    "jacobian_dot_alone",
    "batch",
    "Batch",
    "joint_frames",
    "link_frames",
    "chain_frames",
    "as_configuration",
    "analytic_jacobian",
    "euler_angles",
    "euler_rate_matrix",
    "singular_values",
    "manipulability",
    "condition_number",
    "inverse_condition_number",
    "rank",
    "null_space",
    "select_rows",
    "task_rows",
    "Ellipsoid",
    "velocity_ellipsoid",
    "force_ellipsoid",
    "pinv",
    "dls",
    "nullspace_projector",
    "solve_rates",
    "SingularityReport",
    "assess",
    "robot_from_urdf",
    "to_urdf",
    "cache_dir",
    "JacobianLabError",
    "RobotDefinitionError",
    "UnknownRobotError",
    "UrdfError",
    "ConfigurationError",
    "OptionError",
    "ArrayError",
    "RepresentationSingularityError",
]


def cache_dir() -> Path:
    """Directory for on-disk caches: ``$XDG_CACHE_HOME/jacobian-lab`` (default ``~/.cache/jacobian-lab``).

    Created on first use.
    """
    root = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    path = Path(root) / "jacobian-lab"
    path.mkdir(parents=True, exist_ok=True)
    return path
