"""Where the tests find the project and their data, wherever a test module sits under tests/."""

from __future__ import annotations

from pathlib import Path

TESTS = Path(__file__).resolve().parent
"""tests/: the shared helpers (fakes.py, app_helpers.py …), data/ and katex/."""
ROOT = TESTS.parent
"""The project's root (pyproject.toml, app/, kinematics/, robots/)."""
DATA = TESTS / "data"
"""Test robots: URDFs (data/urdf/ and the *_like.urdf chains)."""
KATEX = TESTS / "katex"
"""The KaTeX renderer the LaTeX export is checked with (npm ci on first use)."""
