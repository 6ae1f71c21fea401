"""A new student's first screen in a real headless Chromium at 1280×720 (issue 21, item 15): the robot
menu lists titles, one line says what to do first and goes at the first move, the status lines wrap
instead of ending in "…". Screenshots go to ``$APP_SCREENSHOT_DIR`` (default: pytest's temporary
directory).
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from browser_helpers import app_page
from fakes import poll

from app.core.actions import GoTo
from app.server import Lab

pytestmark = pytest.mark.browser

_CUT = """() => [...document.querySelectorAll('.jl-sub')]
  .filter((e) => e.offsetParent !== null)
  .map((e) => ({text: e.textContent, desc: e.classList.contains('jl-desc'), cut: e.scrollWidth > e.clientWidth + 1,
                lines: Math.round(e.clientHeight / parseFloat(getComputedStyle(e).lineHeight))}))"""


def _out(tmp_path: Path) -> Path:
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    return out


@pytest.mark.slow
def test_the_first_screen_says_what_to_do_and_lists_robots_by_title(tmp_path):
    out = _out(tmp_path)
    with app_page(Lab(port=0)) as (page, session, errors):
        hint = page.locator(".jl-hint")
        hint.wait_for(state="visible")
        assert "drag a joint slider" in hint.inner_text()
        box = hint.bounding_box()
        assert box["height"] < 36  # one line …
        canvas = page.locator("canvas").first.bounding_box()
        assert box["x"] + box["width"] <= canvas["x"] + canvas["width"]  # … over the 3-D view, not the panel
        menu = page.get_by_label("Robot", exact=True).first
        assert menu.input_value() == "Unimation PUMA 560 (puma560)"
        page.screenshot(path=str(out / "first_screen_1280x720.png"))
        menu.click()
        page.get_by_role("option", name="Stanford arm (Scheinman) (stanford)", exact=True).wait_for()
        page.screenshot(path=str(out / "first_screen_robot_menu.png"))
        page.get_by_role("option", name="TRR robot (course example) (trr)", exact=True).click()
        poll(lambda: session.state.robot_name == "trr")
        poll(lambda: page.locator(".jl-hint").count() == 0)  # choosing a robot was the first change
        assert not session.state.started or page.locator(".jl-hint").count() == 0
        session.dispatch(GoTo("stretched"))
        poll(lambda: session.state.configuration == "stretched")
        page.wait_for_function("() => [...document.querySelectorAll('.jl-sub')].some((e) => e.offsetParent)")
        lines = page.evaluate(_CUT)
        assert lines and not [x for x in lines if x["cut"]], lines  # wrapped, never cut sideways with "…"
        assert any(x["lines"] >= 2 for x in lines), lines  # the lost direction says all it has to say
        assert all(x["lines"] <= 2 for x in lines if x["desc"]), lines  # a description: two lines at most
        page.screenshot(path=str(out / "first_screen_status_wraps.png"))
        # A description cut at two lines ends in "…" and shows all of it on a click.
        desc = page.locator(".jl-desc")
        cut = page.evaluate(
            "() => { const e = document.querySelector('.jl-desc'); return e.scrollHeight > e.clientHeight + 1; }"
        )
        assert cut, lines  # the stretched TRR's 140 characters do not fit two lines at 1280×720
        two = desc.bounding_box()["height"]
        desc.click()
        poll(lambda: desc.bounding_box()["height"] > 1.4 * two)
        assert page.evaluate(
            "() => { const e = document.querySelector('.jl-desc'); return e.scrollHeight <= e.clientHeight + 1; }"
        )
        stretched = next(c for c in session.state.robot.configurations if c.name == "stretched")
        assert desc.inner_text().strip().endswith(stretched.description.strip()[-20:])
        page.screenshot(path=str(out / "first_screen_description_all.png"))
        assert not errors, errors


_FIGURE = """() => {
  const fig = document.querySelector('.jl-mapfig');
  const box = (s) => { const b = fig.querySelector(s).getBoundingClientRect();
    return {left: b.left, right: b.right, top: b.top, bottom: b.bottom, width: b.width, height: b.height}; };
  const column = document.querySelector('[data-dock-region="right"]').getBoundingClientRect();
  return {map: box('.jl-map img'), bar: box('.bar'), wticks: box('.wticks'), yticks: box('.yticks'),
          ylabel: box('.ylabel'), xticks: box('.xticks'), xlabel: box('.xlabel'), wlabel: box('.wlabel'),
          column: {left: column.left, right: column.right}};
}"""


@pytest.mark.slow
def test_the_joint_map_and_the_cloud_say_what_their_axes_and_colours_are(tmp_path):
    out = _out(tmp_path)
    with app_page(Lab(port=0)) as (page, session, errors):
        page.get_by_role("tab", name="Maps").click()
        page.get_by_label("Joint-space map of w", exact=True).first.check()
        page.get_by_label("Workspace cloud", exact=True).first.check()
        poll(lambda: page.locator(".jl-mapfig").count() > 0 and page.locator(".jl-cloudkey").count() > 0)
        page.locator(".jl-mapfig .xlabel").scroll_into_view_if_needed()
        f = page.evaluate(_FIGURE)
        m = f["map"]
        assert m["width"] > 200 and abs(m["width"] - m["height"]) < 2  # square cells, a readable size
        # Left to right: axis title, ticks, map, colour bar, its ticks, all inside the panel.
        assert f["column"]["left"] <= f["ylabel"]["left"] < f["yticks"]["left"] < m["left"]
        assert m["right"] <= f["bar"]["left"] and f["bar"]["right"] <= f["wticks"]["left"]
        assert f["wticks"]["right"] <= f["column"]["right"]
        assert m["bottom"] <= f["xticks"]["top"] + 1 and f["xticks"]["bottom"] <= f["xlabel"]["top"] + 1
        assert abs(f["bar"]["height"] - m["height"]) < 3
        assert (
            f["wlabel"]["left"] >= f["wticks"]["right"] - 1 and f["wlabel"]["right"] <= f["column"]["right"]
        )
        page.mouse.move(5, 5)  # no hint of the checkbox over the status
        page.evaluate("document.querySelector('.jl-mapfig').scrollIntoView({block: 'start'})")
        page.screenshot(path=str(out / "maps_axes_and_colour_bar.png"))
        assert not errors, errors


@pytest.mark.slow
def test_leaving_a_named_configuration_does_not_move_the_sliders_under_the_pointer(tmp_path):
    """The first touch of a slider leaves the named configuration and its description goes: the lines
    under the status keep their height, so the slider being dragged stays under the pointer."""
    out = _out(tmp_path)
    with app_page(Lab(port=0)) as (page, session, errors):
        page.locator(".jl-desc").wait_for(state="visible")  # the first screen: a configuration described
        assert session.state.configuration
        q1 = page.get_by_role("slider").nth(0)
        before = q1.bounding_box()["y"]
        page.get_by_role("slider").nth(1).focus()
        page.keyboard.press("ArrowRight")  # as a drag's first step, from the keyboard
        poll(lambda: not session.state.configuration, what="the named configuration left")
        poll(lambda: page.locator(".jl-desc").count() == 0, what="its description gone from the page")
        after = q1.bounding_box()["y"]
        page.screenshot(path=str(out / "first_move_sliders_stay.png"))
        assert abs(after - before) < 1.0, (before, after)  # was 29 px up
        assert not errors, errors
