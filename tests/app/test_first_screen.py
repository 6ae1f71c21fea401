"""What a new student sees first (issue 21, item 15): the robot dropdown lists library robots by title
and name (the label picked chooses that robot, a value that is not one of the labels is refused where
it enters), and one line under the status says what to do first, until the first change."""

from __future__ import annotations

from app_helpers import running_lab, wait_until
from hostile_helpers import widgets

import robots
from app.core.actions import SetJoint
from app.core.commands import ChooseRobot
from app.core.robot_menu import robot_label, robot_menu
from app.views.panel.hint import FIRST_HINT
from app.viser_adapter import message_class

UPDATE = message_class("GuiUpdateMessage")


def test_library_robots_are_listed_by_title_and_name_others_by_name():
    for name in robots.names():
        title = robots.load(name).title
        assert robot_label(name) == f"{title} ({name})"
    assert robot_label("puma560") == "Unimation PUMA 560 (puma560)"
    menu = robot_menu(["two_link", "puma560", "trr"])
    assert menu.labels == ("two_link", "Unimation PUMA 560 (puma560)", "TRR robot (course example) (trr)")
    assert menu.name_of("TRR robot (course example) (trr)") == "trr"
    assert menu.name_of("trr") == "trr" and menu.name_of("ur5") is None  # not listed
    assert menu.label_of("puma560") == "Unimation PUMA 560 (puma560)"


def test_a_file_robot_named_like_a_library_label_gets_its_own_entry():
    twin = "Unimation PUMA 560 (puma560)"
    menu = robot_menu([twin, "puma560"])
    assert len(set(menu.labels)) == 2
    assert menu.name_of(menu.labels[0]) == twin and menu.name_of(menu.labels[1]) == "puma560"


def test_the_dropdown_shows_titles_and_the_browser_may_send_only_a_label():
    with running_lab(robot="planar2") as (lab, session, ws):
        session.settle()
        menu = session.panel.robot
        assert "Unimation PUMA 560 (puma560)" in menu.options
        assert menu.value == "Planar 2R arm (planar2)"
        robot_menus = lambda: [u for u, m in widgets(ws).items() if m["props"].get("label") == "Robot"]  # noqa: E731
        (uuid,) = wait_until(lambda: robot_menus() or None)  # the client may not have it yet
        before = lab.room.refused
        ws.send(UPDATE(uuid, {"value": "trr"}))  # a name, not one of the menu's entries
        wait_until(lambda: lab.room.refused > before)
        assert "Robot" in lab.room.refusals[-1][1]
        session.settle()
        assert session.state.robot_name == "planar2"
        ws.send(UPDATE(uuid, {"value": "TRR robot (course example) (trr)"}))
        wait_until(lambda: session.state.robot_name == "trr")
        session.settle()
        assert menu.value == "TRR robot (course example) (trr)"


def test_the_first_hint_shows_until_the_first_change_and_never_again(session):
    hint = session.panel.hint
    assert not session.state.started
    assert hint.visible and FIRST_HINT in hint.content and "joint slider" in hint.content
    assert FIRST_HINT not in session.panel.status.content  # over the 3-D view, not in the panel's flow
    session.dispatch(SetJoint(1, 0.2))
    session.settle()
    assert session.state.started and not hint.visible and hint.content == ""
    session.dispatch(ChooseRobot("trr"))  # a new robot: the hint stays gone
    session.settle()
    assert session.state.robot_name == "trr" and not hint.visible
