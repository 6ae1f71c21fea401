"""Helpers shared by the kinematics tests."""

from __future__ import annotations

import importlib.util

from fakes import random_q  # its home is tests/fakes.py; here for tests written before

__all__ = ["import_source", "random_q"]


def import_source(path, text, name):
    """Write ``text`` (an exported Python module) to ``path`` and import it as ``name``."""
    path.write_text(text)
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
