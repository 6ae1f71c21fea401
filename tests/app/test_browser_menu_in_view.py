"""Issue 28, stumble 3: the Configuration menu, the one that takes the lecture on, stays whole in the
window without scrolling: at every named configuration of every 6-joint robot (the singularities' long
descriptions and decoupling lines took 4–5 lines and pushed it below the fold) and on a follower of the
default ``serve --presenter`` (the Classroom box pushed it down), at 1280×720 and 1366×768, in headless
Chromium. "In view" is read as a student's click would reach it: the row's box lies inside the window and
the page's topmost element at its corners and centre is the row itself (not clipped by its scroll area,
not under the "more below" band). Screenshots go to ``$APP_SCREENSHOT_DIR`` (default: pytest's temporary
directory)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from browser_helpers import ARGS, CHROMIUM, app_page, new_page, require_browser
from fakes import poll
from server_process import Server, printed_presenter_link

import robots
from app.core.actions import GoTo
from app.core.commands import ChooseRobot
from app.server import Lab
from app.services.catalog import DEFAULT_ROBOT
from app.views.panel.joints import configuration_label

pytestmark = [pytest.mark.browser, pytest.mark.slow]

SIZES = [{"width": 1280, "height": 720}, {"width": 1366, "height": 768}]

# The Configuration row (label and menu): its box, whether each of its corners and its centre is what the
# page shows there, and the value the menu shows.
_MENU = """() => {
  const label = [...document.querySelectorAll('[data-dock-region] label')].find(
    (l) => l.textContent.trim() === 'Configuration');
  if (!label) return null;
  const row = label.closest('.mantine-Flex-root') || label.parentElement;
  const input = row.querySelector('input');
  const b = row.getBoundingClientRect();
  const points = [[b.left + 3, b.top + 3], [b.right - 3, b.top + 3], [b.left + 3, b.bottom - 3],
                  [b.right - 3, b.bottom - 3], [(b.left + b.right) / 2, (b.top + b.bottom) / 2]];
  const hit = points.map(([x, y]) => { const e = document.elementFromPoint(x, y); return !!(e && row.contains(e)); });
  return {top: b.top, bottom: b.bottom, left: b.left, right: b.right, width: innerWidth, height: innerHeight,
          hit, value: input ? input.value : null};
}"""


def _six_joint_robots() -> list[str]:
    return [name for name in robots.names() if robots.load(name).dof == 6]


def _label(conf) -> str:
    name = configuration_label(conf.name)
    return f"{name} (singular)" if conf.singular else name


def _whole_in_view(m) -> bool:
    return (
        m is not None
        and m["top"] >= 0
        and m["left"] >= 0
        and m["bottom"] <= m["height"]
        and m["right"] <= m["width"]
        and all(m["hit"])
    )


def _settled(page, value: str):
    """The menu's measure once it shows ``value`` and the layout (its script runs every 0.4 s) no longer
    moves it between two reads."""
    last: list = [None]

    def same():
        m = page.evaluate(_MENU)
        if m is None or m["value"] != value:
            return None
        if last[0] == m:
            return m
        last[0] = m
        page.wait_for_timeout(450)
        return None

    return poll(same, what=f"the menu showing {value!r}, laid out")


def _out(tmp_path: Path) -> Path:
    out = Path(os.environ.get("APP_SCREENSHOT_DIR", tmp_path))
    out.mkdir(parents=True, exist_ok=True)
    return out


def test_the_six_joint_robots_are_there():
    assert {"puma560", "ur5", "stanford"} <= set(_six_joint_robots())


@pytest.mark.parametrize("size", SIZES, ids=[f"{s['width']}x{s['height']}" for s in SIZES])
def test_the_configuration_menu_stays_in_view_at_every_named_configuration(tmp_path, size):
    out = _out(tmp_path)
    names = _six_joint_robots()
    lab = Lab(port=0, robot=names[0])
    outside = []
    with app_page(lab, viewport=size) as (page, session, errors):
        for name in names:
            robot = robots.load(name)
            if session.state.robot_name != name:
                session.dispatch(ChooseRobot(name))
                poll(lambda name=name: session.state.robot_name == name and session.snapshot is not None)
            for conf in robot.configurations:
                session.dispatch(GoTo(conf.name))
                m = _settled(page, _label(conf))
                if not _whole_in_view(m):
                    outside.append((name, conf.name, m))
                if conf.singular:
                    page.screenshot(path=str(out / f"menu_{size['width']}_{name}_{conf.name}.png"))
        assert not errors, errors
    assert not outside, outside


@pytest.mark.parametrize("size", SIZES, ids=[f"{s['width']}x{s['height']}" for s in SIZES])
def test_a_follower_sees_the_configuration_menu_at_every_singularity_the_presenter_picks(tmp_path, size):
    out = _out(tmp_path)
    sync_playwright = require_browser()
    server = Server(tmp_path, argv=["serve", "--presenter", "--port", "0"])
    try:
        link = printed_presenter_link(server)
        base = link.split("?", 1)[0]
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=ARGS)
            try:
                presenter = new_page(browser, size)
                presenter.goto(link)
                title = presenter.get_by_text("Classroom · presenting", exact=False)
                poll(lambda: title.count() > 0 and title.first.is_visible(), what="the tab presents")
                follower = new_page(browser, size)
                follower.goto(base)
                follower.wait_for_selector("[role=slider]", state="attached")
                following = follower.get_by_text("Classroom · following", exact=False)
                poll(lambda: following.count() > 0 and following.first.is_visible(), what="the tab follows")
                poll(lambda: (presenter.evaluate(_MENU) or {}).get("value") == "home")
                robot = robots.load(DEFAULT_ROBOT)  # what serve shows first
                assert robot.dof == 6
                outside = []
                for conf in [c for c in robot.configurations if c.singular]:
                    label = _label(conf)
                    presenter.get_by_label("Configuration", exact=True).first.click()
                    presenter.get_by_role("option", name=label, exact=True).click()
                    for who, page in (("presenter", presenter), ("follower", follower)):
                        m = _settled(page, label)
                        if not _whole_in_view(m):
                            outside.append((who, conf.name, m))
                    follower.screenshot(
                        path=str(out / f"menu_follower_{size['width']}_{robot.name}_{conf.name}.png")
                    )
                assert not outside, outside
            finally:
                browser.close()
    finally:
        server.cleanup()
