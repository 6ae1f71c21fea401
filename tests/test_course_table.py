"""Issue 29: docs/course.md's item-by-item table of the course holds together.

Each row is one thing the lecture notes teach, where the app shows it and the tests that hold it.
Here, without importing the app: every test named exists (its file, its function, read with ``ast``;
a parametrised id in brackets is allowed), the rows are numbered 1…N with no gap, no cell is empty,
each row names the lectures it comes from, a row in the app names at least one test and a row marked
"missing" none, and the total line counts the rows.
"""

from __future__ import annotations

import ast
import functools
import re
from dataclasses import dataclass
from pathlib import Path

import pytest
from locations import ROOT

PAGE = ROOT / "docs" / "course.md"
HEADING = "## The course, item by item"
LECTURES = ("000", "001", "002", "004")
REF_RE = re.compile(r"`(tests/[\w/]+\.py)::((?:\w+::)*\w+)(\[[^\]`]*\])?`")
TOTAL_RE = re.compile(r"\*\*(\d+) of (\d+) items are in the app\.\*\*")


@dataclass(frozen=True)
class Row:
    number: str
    lecture: str
    item: str
    where: str
    tests: str

    @property
    def missing(self) -> bool:
        return self.where.lower().startswith("missing")

    def refs(self) -> list[tuple[str, str]]:
        return [(m.group(1), m.group(2)) for m in REF_RE.finditer(self.tests)]


def table(text: str) -> tuple[list[Row], str]:
    """The rows of the table under ``HEADING`` (header and rule left out) and the text after it."""
    assert HEADING in text, f"docs/course.md has no section {HEADING!r}"
    lines = text.split(HEADING, 1)[1].splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("|"))
    end = next((i for i in range(start, len(lines)) if not lines[i].startswith("|")), len(lines))
    rows = []
    for line in lines[start + 2 : end]:  # past the header and its |---| rule
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        assert len(cells) == 5, f"a row needs 5 cells (a '|' inside a cell?): {line}"
        rows.append(Row(*cells))
    return rows, "\n".join(lines[end:])


@functools.cache
def functions_of(path: str) -> frozenset[str]:
    """Every function of a test file, as ``name`` or ``Class::name``."""
    tree = ast.parse((ROOT / path).read_text(encoding="utf-8"))
    names: set[str] = set()
    for node in tree.body:
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            names.add(node.name)
        elif isinstance(node, ast.ClassDef):
            for sub in node.body:
                if isinstance(sub, ast.FunctionDef | ast.AsyncFunctionDef):
                    names.add(f"{node.name}::{sub.name}")
    return frozenset(names)


def unresolved(rows: list[Row]) -> list[str]:
    """The references that name no file or no function there."""
    bad = []
    for row in rows:
        for path, name in row.refs():
            if not (ROOT / path).is_file():
                bad.append(f"row {row.number}: {path} does not exist")
            elif not name.split("::")[-1].startswith("test") or name not in functions_of(path):
                bad.append(f"row {row.number}: {path} has no test {name}")
    return bad


@pytest.fixture(scope="module")
def parsed() -> tuple[list[Row], str]:
    return table(PAGE.read_text(encoding="utf-8"))


def test_every_test_the_table_names_exists(parsed):
    rows, _ = parsed
    assert not unresolved(rows)


def test_rows_are_numbered_one_to_n_without_gaps(parsed):
    rows, _ = parsed
    assert rows
    assert [r.number for r in rows] == [str(i) for i in range(1, len(rows) + 1)]


def test_no_cell_is_empty_and_each_row_names_its_lectures(parsed):
    rows, _ = parsed
    for row in rows:
        assert all((row.number, row.lecture, row.item, row.where, row.tests)), row
        for part in row.lecture.split(";"):
            assert part.strip().startswith(LECTURES), f"row {row.number}: unknown lecture {part!r}"


def test_a_row_in_the_app_names_its_tests_and_a_missing_row_none(parsed):
    rows, _ = parsed
    for row in rows:
        if row.missing:
            assert not row.refs(), f"row {row.number} is missing from the app but names tests"
            continue
        assert row.refs(), f"row {row.number} names no test"
        rest = REF_RE.sub("", row.tests)
        assert not rest.replace(";", "").strip(), f"row {row.number}: not a test reference: {rest!r}"


def test_the_total_line_counts_the_rows(parsed):
    rows, after = parsed
    totals = TOTAL_RE.findall(after)
    assert len(totals) == 1, "one line '**N of M items are in the app.**' after the table"
    present, total = map(int, totals[0])
    assert total == len(rows)
    assert present == sum(not r.missing for r in rows)


def test_a_broken_reference_is_caught():
    """The check itself: a renamed test, a wrong file or a test in another file is reported."""
    good = "`tests/test_course_table.py::test_the_total_line_counts_the_rows`"
    row = Row("1", "000 §1", "x", "y", good)
    assert not unresolved([row])
    assert not unresolved([Row("1", "000 §1", "x", "y", good[:-1] + "[id]`")])
    for bad in (
        "`tests/test_course_table.py::test_the_total_line_counts_the_rowz`",
        "`tests/test_course_tabel.py::test_the_total_line_counts_the_rows`",
        "`tests/test_docs.py::test_the_total_line_counts_the_rows`",
        "`tests/test_course_table.py::table`",
    ):
        assert unresolved([Row("1", "000 §1", "x", "y", bad)]), bad


def test_the_table_is_parsed_from_a_page_like_this_one():
    text = f"intro\n{HEADING}\n\nprose\n\n| # | a | b | c | d |\n|---|---|---|---|---|\n| 1 | 000 §1 | i | missing | — |\n\n**0 of 1 items are in the app.**\n"
    rows, after = table(text)
    assert len(rows) == 1 and rows[0].missing and TOTAL_RE.search(after)
    assert Path(PAGE).name == "course.md"
