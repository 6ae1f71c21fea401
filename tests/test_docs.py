"""The README and the manual in docs/ name only what exists: every project path, every module and
every attribute they name (``app/tab/session.py``, ``kinematics.analytic_jacobian.euler_angles``), and
every relative link."""

from __future__ import annotations

import importlib
import re

import pytest
from locations import ROOT

PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
PACKAGES = ("app", "kinematics", "robots")
TOP = ("app", "kinematics", "robots", "tests", "bench", "docs", "examples", ".ci")

_TOP = "|".join(re.escape(t) for t in TOP)
PATH_RE = re.compile(r"(?<![\w./-])((?:" + _TOP + r")/[\w./-]*[\w/])")
DOTTED_RE = re.compile(r"(?<![\w./-])((?:" + "|".join(PACKAGES) + r")(?:\.[A-Za-z_]\w*)+)")
LINK_RE = re.compile(r"\]\(([^)#\s]+)(?:#[^)]*)?\)")


def _code_spans(text: str) -> list[str]:
    """Inline code and fenced blocks: where the pages name paths and modules."""
    fenced = re.findall(r"```[^\n]*\n(.*?)```", text, flags=re.S)
    inline = re.findall(r"`([^`\n]+)`", re.sub(r"```.*?```", "", text, flags=re.S))
    return fenced + inline


def paths_named(text: str) -> set[str]:
    found: set[str] = set()
    for span in _code_spans(text):
        for m in PATH_RE.finditer(span):
            p = m.group(1)
            if "*" in p or p.endswith((".toml", ".py", "/")) or "." not in p.rsplit("/", 1)[-1]:
                found.add(p.rstrip("/"))
    return {p for p in found if not p.startswith("docs/") or p.endswith((".md", ".png"))}


def modules_named(text: str) -> set[str]:
    names: set[str] = set()
    for span in _code_spans(text):
        for m in DOTTED_RE.finditer(span):
            name = m.group(1)
            if name.endswith((".py", ".toml", ".urdf", ".md")):
                continue
            names.add(name)
    return names


def resolves(dotted: str) -> bool:
    """A module, or an attribute (a function, class or method) reached from the longest module prefix."""
    parts = dotted.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
        except ImportError:
            continue
        for attr in parts[i:]:
            if not hasattr(obj, attr):
                return False
            obj = getattr(obj, attr)
        return True
    return False


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_named_path_exists(page):
    text = page.read_text(encoding="utf-8")
    missing = sorted(p for p in paths_named(text) if not (ROOT / p).exists())
    assert not missing, f"{page.name} names paths that do not exist: {missing}"


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_named_module_resolves(page):
    text = page.read_text(encoding="utf-8")
    missing = sorted(m for m in modules_named(text) if not resolves(m))
    assert not missing, f"{page.name} names modules or attributes that do not exist: {missing}"


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_relative_link_exists(page):
    text = page.read_text(encoding="utf-8")
    links = [t for t in LINK_RE.findall(text) if "://" not in t and not t.startswith("mailto:")]
    missing = sorted(t for t in links if not (page.parent / t).exists())
    assert not missing, f"{page.name} links to files that do not exist: {missing}"


def test_the_checker_finds_what_is_missing():
    """The checks above can fail: a made-up path, module and attribute are caught."""
    text = "see `app/no_such_file.py` and `kinematics.no_such_module` and `kinematics.numeric.no_such_fn`"
    assert "app/no_such_file.py" in paths_named(text)
    assert not (ROOT / "app/no_such_file.py").exists()
    assert {"kinematics.no_such_module", "kinematics.numeric.no_such_fn"} <= modules_named(text)
    assert not resolves("kinematics.no_such_module")
    assert not resolves("kinematics.numeric.no_such_fn")
    assert resolves("kinematics.numeric.jacobian")


def test_the_front_page_is_short():
    assert len((ROOT / "README.md").read_bytes()) <= 15_000
    assert len([p for p in (ROOT / "docs").glob("*.md")]) >= 5
