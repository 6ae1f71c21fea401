"""Server-level tests: the Derive tab's glyphs are drawn only while the Derive tab is open (issue 28,
stumble 1: an "ω₁" on the Puma's waist in the J(q) tab, "v₁"/"ω₁" on planar3 during the climb, frame
axes in the Maps tab). The walk itself stays in the options, so opening the tab again draws it."""

from __future__ import annotations

import json

from app_helpers import derive_walk, scene_node, wait_until

from app.core.commands import ChooseRobot
from app.views.panel import TAB_LABELS

_DERIVE_NODES = ("arrows", "thin_arrows", "lines", *(f"label_{k}" for k in range(6)))


def open_tab(session, label: str) -> None:
    """The page reports that the user opened the tab called ``label`` (as its script does)."""
    assert label in TAB_LABELS
    session.panel.report.value = json.dumps({"kind": "tab", "tab": label})
    session.settle()
    wait_until(lambda: session.page.tab == label)
    session.settle()


def shown(session) -> list[str]:
    """The Derive glyph nodes the tab's browser shows."""
    return [name for name in _DERIVE_NODES if scene_node(session, f"/lab/derive/{name}").visible]


def test_derive_glyphs_leave_with_the_derive_tab(session):
    session.dispatch(ChooseRobot("puma560"))
    session.settle()
    open_tab(session, "Derive")
    derive_walk(session, "propagation", 0)  # ω₁ and v₁ on the waist
    assert "arrows" in shown(session) and "label_0" in shown(session)
    open_tab(session, "J(q)")
    assert shown(session) == []  # no "ω₁" on the Puma's waist in the J(q) tab
    open_tab(session, "Derive")
    assert "arrows" in shown(session)  # the walk is kept: back on its tab, drawn again


def test_derive_glyphs_stay_away_on_another_robot_and_tab(session):
    session.dispatch(ChooseRobot("puma560"))
    session.settle()
    open_tab(session, "Derive")
    derive_walk(session, "dh", 2)  # the DH frames x₂, z₂ …
    assert any(n.startswith("label_") for n in shown(session))
    open_tab(session, "Maps")
    assert shown(session) == []  # no frame axes in the Maps tab
    session.dispatch(ChooseRobot("planar3"))  # a new robot's scene: built while Maps is open
    session.settle()
    assert session.state.options.derive == "dh"  # the walk is still chosen …
    assert shown(session) == []  # … and not drawn
    open_tab(session, "Motion")
    assert shown(session) == []  # no "v₁"/"ω₁" on planar3 during the climb
    open_tab(session, "Derive")
    assert shown(session)
