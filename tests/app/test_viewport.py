"""The visible part of the 3-D view at each window size (app.views.panel.viewport); the same rectangles
are measured on real browser boxes in tests/app/test_browser_phone.py."""

from __future__ import annotations

import pytest

from app.views.panel.viewport import Rect, is_phone_layout, panel_zoom, visible_view_rect


@pytest.mark.parametrize(
    ("size", "zoom"),
    [
        ((1280, 720), 1.0),
        ((1920, 1080), 1.5),
        ((853, 480), 0.8),
        ((844, 390), 0.8),
        ((768, 1024), 1.0),
        ((2560, 1440), 1.6),
        ((1366, 768), 1.05),
    ],
)
def test_zoom_is_the_page_scripts(size, zoom):
    # 1920/1280 = 1.5; 2560/1280 = 2 capped at 1.6; 1366/1280 = 1.067 → 1.05 (twentieths); under 600 px
    # high 480/600 = 0.8, 390/600 = 0.65 raised to 0.8.
    assert panel_zoom(*size) == pytest.approx(zoom)


def test_projector_keeps_what_the_column_leaves():
    assert visible_view_rect(1280, 720) == Rect(0, 0, 1280 - 404, 720)
    assert visible_view_rect(1920, 1080) == Rect(0, 0, 1920 - 606, 1080)


def test_phone_upright_sees_the_upper_half():
    assert is_phone_layout(390) and is_phone_layout(576) and not is_phone_layout(577)
    assert visible_view_rect(390, 844) == Rect(0, 0, 390, 422)


@pytest.mark.parametrize("size", [(390, 844), (844, 390), (768, 1024), (1280, 720), (360, 640)])
def test_view_keeps_at_least_45_percent(size):
    r = visible_view_rect(*size)
    assert r.width * r.height >= 0.45 * size[0] * size[1]


def test_a_phone_held_sideways_keeps_the_column_at_zoom_1():
    # 844x390 with a mouse: zoom 0.8 (a 150 % zoomed laptop); on a touch screen 1, its text 13 px.
    assert panel_zoom(844, 390, touch=True) == 1.0
    assert visible_view_rect(844, 390, touch=True) == Rect(0, 0, 844 - 404, 390)
    assert 440 * 390 >= 0.45 * 844 * 390
