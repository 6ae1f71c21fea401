"""The kinematics package's structure: what issue 7 asks of every module of kinematics/."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import kinematics

KINEMATICS = Path(kinematics.__file__).parent


MODULES = [pytest.param(p, id=str(p.relative_to(KINEMATICS))) for p in sorted(KINEMATICS.rglob("*.py"))]


@pytest.mark.parametrize("path", MODULES)
def test_kinematics_module_structure(path):
    """No private name imported across modules, no import of the robot library, no file over 400 lines."""
    text = path.read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 400
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.ImportFrom) and node.module is not None:
            assert node.module.split(".")[0] != "robots" or node.level > 0
            if node.level > 0 or node.module.startswith("kinematics"):
                private = [
                    a.name for a in node.names if a.name.startswith("_") and not a.name.startswith("__")
                ]
                assert not private, f"{path.name} imports private {private} from {node.module}"
        elif isinstance(node, ast.Import):
            assert all(a.name.split(".")[0] != "robots" for a in node.names)
