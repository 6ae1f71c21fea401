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


# --------------------------------------------------------------------------- the layers of the tree
# The import rules of the layout (docs: the architecture page), as data. A module belongs to the
# longest prefix listed; it may import only modules under the prefixes it is allowed (its own
# layer always), and none of the outside packages it is refused. Imports inside functions count;
# imports under ``if TYPE_CHECKING:`` do not (they never run).
ROOT = KINEMATICS.parent
PACKAGES = ("app", "kinematics", "robots")
ALLOWED: dict[str, tuple[str, ...]] = {
    "app.core": ("kinematics", "robots"),
    "app.views": ("app.core", "app.viser_adapter", "kinematics", "robots"),
    "app.services": ("app.core", "kinematics", "robots"),
    "app.viser_adapter": ("app.services.ratelimit",),
    "app.demo": ("app.core", "app.views", "kinematics", "robots"),
    "app.tab": (
        "app.core",
        "app.views",
        "app.services",
        "app.demo",
        "app.viser_adapter",
        "kinematics",
        "robots",
    ),
    "app.cli": ("app", "kinematics", "robots"),
    "app.server": ("app", "kinematics", "robots"),
    "app.notebook": ("app", "kinematics", "robots"),  # a lab in a Jupyter cell: a composition root too
    "app": ("app.server",),  # app/__init__: serve() starts the server
    "kinematics": (),
    "robots": ("kinematics",),
}
REFUSED: dict[str, tuple[str, ...]] = {"app.core": ("viser",), "kinematics": ("viser",)}
"""Outside packages a layer never imports (the pure core and the maths know nothing of viser)."""
SERVER_IMPORTERS = ("app.cli", "app.notebook", "app")
"""The only modules that may import app.server (the composition root)."""
MAX_MODULES = {"app": 8, "kinematics": 20}
"""Modules directly in these folders, at most (the rest lives in sub-packages that name a layer)."""
MAX_LINES = 400


def module_name(path: Path, root: Path = ROOT) -> str:
    """``app/tab/session.py`` → ``app.tab.session``; a package's ``__init__.py`` → the package."""
    parts = list(path.relative_to(root).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def imports(source: str, name: str, is_package: bool, known: set[str]) -> set[str]:
    """The modules ``source`` (module ``name``) imports: relative imports resolved, ``from p import m``
    read as module ``p.m`` when that is one of ``known``, imports inside functions included, those
    under ``if TYPE_CHECKING:`` left out."""
    found: set[str] = set()
    package = name.split(".") if is_package else name.split(".")[:-1]

    def visit(node: ast.AST) -> None:
        if isinstance(node, ast.If) and _type_checking(node.test):
            for child in node.orelse:
                visit(child)
            return
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - node.level + 1]
                target = ".".join([*base, node.module] if node.module else base)
            else:
                target = node.module or ""
            for alias in node.names:
                found.add(f"{target}.{alias.name}" if f"{target}.{alias.name}" in known else target)
        for child in ast.iter_child_nodes(node):
            visit(child)

    visit(ast.parse(source))
    return found


def import_graph(root: Path = ROOT, packages: tuple[str, ...] = PACKAGES) -> dict[str, set[str]]:
    """Every module of ``packages`` → the modules it imports (outside ones included)."""
    files = {module_name(p, root): p for package in packages for p in sorted((root / package).rglob("*.py"))}
    known = set(files)
    return {
        name: imports(path.read_text(encoding="utf-8"), name, path.name == "__init__.py", known)
        for name, path in files.items()
    }


def _under(module: str, prefix: str) -> bool:
    return module == prefix or module.startswith(prefix + ".")


def layer_of(module: str, layers: dict[str, tuple[str, ...]] = ALLOWED) -> str | None:
    """The longest layer prefix ``module`` is under (None: no layer)."""
    return max((p for p in layers if _under(module, p)), key=len, default=None)


def violations(
    graph: dict[str, set[str]],
    allowed: dict[str, tuple[str, ...]] = ALLOWED,
    refused: dict[str, tuple[str, ...]] = REFUSED,
    packages: tuple[str, ...] = PACKAGES,
    server: str = "app.server",
    server_importers: tuple[str, ...] = SERVER_IMPORTERS,
) -> list[str]:
    """Every import that breaks the rules, as "importer → imported (why)"."""
    out = []
    for module, targets in sorted(graph.items()):
        layer = layer_of(module, allowed)
        for target in sorted(targets):
            top = target.split(".")[0]
            if layer is not None and any(
                _under(target, r) for r in refused.get(layer_of(module, refused) or "", ())
            ):
                out.append(f"{module} → {target} (refused in {layer})")
            if top not in packages:
                continue
            if (
                _under(target, server)
                and module != server
                and layer_of(module, allowed) not in server_importers
            ):
                out.append(f"{module} → {target} (only {', '.join(server_importers)} import the server)")
                continue
            if layer is None or _under(target, layer):
                continue
            if not any(_under(target, a) for a in allowed[layer]):
                out.append(
                    f"{module} → {target} ({layer} may import {', '.join(allowed[layer]) or 'only itself'})"
                )
    return out


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The import circles of ``graph`` (its strongly connected parts of more than one module, or a
    module importing itself), each sorted; only edges between modules of the graph count."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def connect(v: str) -> None:  # Tarjan's algorithm
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in graph:
                continue
            if w not in index:
                connect(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            part = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                part.append(w)
                if w == v:
                    break
            if len(part) > 1 or v in graph[v]:
                found.append(sorted(part))

    for v in sorted(graph):
        if v not in index:
            connect(v)
    return sorted(found)


GRAPH = import_graph()


def test_every_module_of_app_kinematics_and_robots_has_a_layer():
    assert {m.split(".")[0] for m in GRAPH} == set(PACKAGES)
    assert [m for m in GRAPH if layer_of(m) is None] == []
    assert len(GRAPH) > 100  # the walk found the tree (not an empty folder)


def test_imports_follow_the_layers():
    assert violations(GRAPH) == []


def test_no_import_circle():
    assert circles(GRAPH) == []


@pytest.mark.parametrize("folder", sorted(MAX_MODULES))
def test_few_modules_directly_in_a_package(folder):
    modules = sorted(p.name for p in (ROOT / folder).glob("*.py"))
    assert len(modules) <= MAX_MODULES[folder], modules


def test_no_file_over_400_lines():
    long = {
        str(p.relative_to(ROOT)): n
        for package in PACKAGES
        for p in (ROOT / package).rglob("*.py")
        if (n := len(p.read_text(encoding="utf-8").splitlines())) > MAX_LINES
    }
    assert long == {}


# --------------------------------------------------------------------------- the checker itself
def test_the_checker_finds_a_planted_violation_and_circle_in_a_small_graph():
    graph = {
        "app.core.state": {"numpy", "kinematics.model"},
        "app.core.reducer": {"app.core.state", "viser"},  # refused: viser in the core
        "app.views.panel": {"app.core.state", "app.services.catalog"},  # views may not use services
        "app.services.catalog": {"app.core.state"},
        "app.tab.session": {"app.views.panel", "app.services.catalog", "app.server"},  # not the server
        "app.server": {"app.tab.session"},
        "app.cli.main": {"app.server"},
        "kinematics.model": {"kinematics.numeric"},
        "kinematics.numeric": {"kinematics.model", "robots"},  # a circle, and robots from the maths
        "robots": {"kinematics.model"},
    }
    assert violations(graph) == [
        "app.core.reducer → viser (refused in app.core)",
        "app.tab.session → app.server (only app.cli, app.notebook, app import the server)",
        "app.views.panel → app.services.catalog (app.views may import app.core, app.viser_adapter, "
        "kinematics, robots)",
        "kinematics.numeric → robots (kinematics may import only itself)",
    ]
    assert circles(graph) == [
        ["app.server", "app.tab.session"],
        ["kinematics.model", "kinematics.numeric", "robots"],
    ]
    del graph["app.tab.session"], graph["kinematics.numeric"]
    graph["app.core.reducer"] = {"app.core.state"}
    graph["app.views.panel"] = {"app.core.state"}
    assert violations(graph) == [] and circles(graph) == []


def test_imports_are_resolved_relative_and_type_checking_ones_left_out():
    source = """
from __future__ import annotations
from typing import TYPE_CHECKING
import numpy as np
from . import fmt
from ..core import state
if TYPE_CHECKING:
    from ..tab.session import ClientSession
else:
    from ..core.snapshot import compute
def later():
    from ..services.catalog import RobotCatalog
"""
    known = {"app.views.fmt", "app.core.state", "app.core.snapshot", "app.services.catalog"}
    found = imports(source, "app.views.panel", is_package=False, known=known)
    assert found == {
        "__future__",
        "typing",
        "numpy",
        "app.views.fmt",
        "app.core.state",
        "app.core.snapshot",
        "app.services.catalog",
    }
    inside = imports(
        "from . import x\nfrom .y import z\n", "app.views", is_package=True, known={"app.views.x"}
    )
    assert inside == {"app.views.x", "app.views.y"}
