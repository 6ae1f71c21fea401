"""The app's symbolic J fits a 600 px panel in a real browser (Chromium): no sideways scrolling.

Chromium lays out MathML natively; each ``<math display="block">`` of
:func:`kinematics.symbolic.jacobian_mathml` is measured in a 600 px wide page. Needs Debian's
``/usr/bin/chromium`` and Playwright: skipped without them, failing when ``CI`` is set.
"""

from __future__ import annotations

import pytest
from browser_helpers import ARGS, CHROMIUM, new_page, require_browser
from locations import DATA

import kinematics
import robots
from kinematics.symbolic import jacobian_mathml

PANEL = 600

pytestmark = pytest.mark.browser


@pytest.fixture(scope="module")
def measure():
    """A function: HTML fragment -> (widest block formula [px], widest legend/note line [px])."""
    sync_playwright = require_browser()
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=ARGS)
        page = new_page(browser, {"width": 1000, "height": 800})

        def run(fragment: str) -> tuple[float, float]:
            page.set_content(f'<div id="panel" style="width: {PANEL}px; font-size: 16px">{fragment}</div>')
            return page.evaluate(
                """() => {
                const panel = document.getElementById('panel');
                const blocks = [...panel.querySelectorAll('math[display=block] > mrow')];
                const widest = Math.max(...blocks.map(b => b.getBoundingClientRect().width));
                return [widest, panel.scrollWidth];
            }"""
            )

        yield run
        browser.close()


@pytest.mark.slow
@pytest.mark.parametrize("name", ["puma560", "panda", "stanford", "iiwa14_like.urdf", "xarm7_like.urdf"])
def test_symbolic_j_fits_the_panel(measure, name):
    robot = kinematics.robot_from_urdf(str(DATA / name)) if name.endswith(".urdf") else robots.load(name)
    text = jacobian_mathml(robot, "base", timeout=120)
    widest, scroll = measure(text)
    assert 0 < widest <= PANEL and scroll <= PANEL
    without_wrapping, _ = measure(jacobian_mathml(robot, "base", timeout=120, layout="matrix"))
    if robot.dof >= 6:  # the whole matrix would not fit: the layout is what makes it fit
        assert without_wrapping > PANEL


APP_TEXT = 380
"""Width of the app's panel text [px] (the panel is 400 px, scaled as a whole at other sizes)."""


@pytest.mark.slow
@pytest.mark.parametrize("letters", [False, True], ids=["numbers", "letters"])
@pytest.mark.parametrize("name", ["planar2", "planar3", "trr", "elbow3r", "scara", "wrist"])
def test_the_small_arms_j_fits_the_apps_panel_with_or_without_course_letters(measure, name, letters):
    """Issue 21: the 3R's lettered J (l₁ s₁ + l₂ s₁₂ + l₃ s₁₂₃ …, 455 px as one matrix) scrolled sideways
    in the 380 px of the app's panel; a J wider than the panel is now shown column by column."""
    robot = robots.load(name)
    widest, scroll = measure(jacobian_mathml(robot, "base", timeout=120, symbolic_params=letters))
    assert 0 < widest <= APP_TEXT, widest
