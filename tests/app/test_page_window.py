"""The page's window report (kind "view": its size on load and on resize), read as hostile input: a size
in CSS px and a touch flag, anything else ignored (the labels stay placed for the camera's canvas)."""

from __future__ import annotations

import json

import pytest

from app.core.page_state import parse_report
from app.views.panel import TAB_LABELS


def _read(**fields):
    return parse_report(json.dumps({"kind": "view", **fields}), TAB_LABELS)


def test_a_window_report_gives_its_size_and_touch():
    assert _read(width=390, height=844, touch=True).window == (390.0, 844.0, True)
    assert _read(width=1280, height=720.5).window == (1280.0, 720.5, False)
    assert _read(width=1280, height=720, touch="yes").window == (1280.0, 720.0, False)  # only true is true


@pytest.mark.parametrize(
    "fields",
    [{}, {"width": "1280", "height": 720}, {"width": True, "height": 720}, {"width": 0, "height": 720},
     {"width": 1e9, "height": 720}, {"width": 1280, "height": None}, {"width": [1], "height": 2}],
)  # fmt: skip
def test_a_window_report_that_is_not_a_size_is_ignored(fields):
    assert _read(**fields).window is None


def test_nan_is_not_a_size():
    assert parse_report('{"kind": "view", "width": NaN, "height": 720}', TAB_LABELS).window is None
