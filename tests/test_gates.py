"""The gates around the suite: CI fails fast and never passes on a skipped browser test, the wheel's
package-data globs all match files, and the markers the inner loop selects on are registered."""

from __future__ import annotations

import re
import sys

import browser_helpers
import pytest
from locations import ROOT

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())


def test_a_missing_browser_skips_locally_and_fails_in_ci(monkeypatch, tmp_path):
    monkeypatch.setattr(browser_helpers, "CHROMIUM", str(tmp_path / "no-chromium"))
    monkeypatch.delenv("CI", raising=False)
    with pytest.raises(pytest.skip.Exception, match="no-chromium"):
        browser_helpers.require_browser()
    monkeypatch.setenv("CI", "true")
    with pytest.raises(pytest.fail.Exception, match="no-chromium"):
        browser_helpers.require_browser()


def test_ci_runs_lint_format_and_types_before_the_readmes_test_command():
    lines = [line.strip() for line in (ROOT / ".ci" / "run").read_text().splitlines()]
    readme = (ROOT / "README.md").read_text()
    command = "pip install -e '.[test]' && python tests/install_test_deps.py && python -m pytest"
    assert command in readme, "the README's test command changed: change .ci/run and this test with it"
    at = {
        gate: next(i for i, line in enumerate(lines) if line.startswith(gate))
        for gate in ("ruff check .", "ruff format --check .", "mypy")
    }
    suite = next(i for i, line in enumerate(lines) if line.startswith(command))
    assert max(at.values()) < suite
    assert lines[suite] == command + " || status=$?"  # nothing added to or taken from the command
    assert "set -euo pipefail" in lines and 'exit "$status"' in lines


@pytest.mark.parametrize("package", ["kinematics", "robots", "app"])
def test_every_package_data_glob_matches_a_file(package):
    globs = PYPROJECT["tool"]["setuptools"]["package-data"][package]
    for pattern in globs:
        assert list((ROOT / package).glob(pattern)), f"{package}: {pattern!r} matches nothing"


def test_the_inner_loops_markers_are_registered_and_strict():
    options = PYPROJECT["tool"]["pytest"]["ini_options"]
    names = {re.match(r"\w+", m).group(0) for m in options["markers"]}
    assert {"slow", "browser"} <= names
    assert "--strict-markers" in options["addopts"].split()


def test_the_license_the_metadata_names_is_there():
    assert PYPROJECT["project"]["license"] == {"text": "MIT"}
    text = (ROOT / "LICENSE").read_text()
    assert text.startswith("MIT License") and "Copyright (c) 2026 The Jacobian Lab developers" in text
