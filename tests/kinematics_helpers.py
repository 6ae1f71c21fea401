"""Helpers shared by the kinematics tests."""

from __future__ import annotations

import importlib.util

import numpy as np


def random_q(robot, rng: np.random.Generator, size: int | None = None) -> np.ndarray:
    """Configurations sampled inside the joint limits (±π / ±1 m where a joint has none)."""
    lim = robot.qlim.copy()
    for i, kind in enumerate(robot.joint_types):
        span = np.pi if kind == "revolute" else 1.0
        lim[0, i] = max(lim[0, i], -span)
        lim[1, i] = min(lim[1, i], span)
    shape = (robot.dof,) if size is None else (size, robot.dof)
    return rng.uniform(lim[0], lim[1], size=shape)


def import_source(path, text, name):
    """Write ``text`` (an exported Python module) to ``path`` and import it as ``name``."""
    path.write_text(text)
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
