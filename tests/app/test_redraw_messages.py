"""What a redraw sends to its tab, counted over the websocket: only what changed, once.

Every message costs the server (serialising, compressing, sending) and the browser; with sixty
tabs exploring at once the server is CPU-bound, so a redraw must not resend what the browser
already shows, and each scene node that moves costs one message.
"""

from __future__ import annotations

import collections

import numpy as np
from app_helpers import scene_node
from fakes import poll

from app.core.actions import SetJoint, SetOption
from app.core.commands import Redraw
from app.viser_adapter import handle_uuid

SENTINEL = "/jl_test_sentinel"
"""A hidden frame this test moves once the session has drawn: messages reach the browser in the order
they were queued, so once its move arrives every message drawn before it has. (Waiting for a cylinders
message with the arm's current positions does not tell: an older frame can have the same positions,
and a change still on its way into the session is not drawn yet, so two changes could fall in one
window and be coalesced into one redraw — the CI failure at 0736d1d.)"""


_SENTINELS: dict[int, object] = {}


def _after(ws, mark: int) -> list[dict]:
    return [m for _, m in ws.messages[mark:] if m.get("name") != SENTINEL]


def _wait_drawn(ws, session, mark: int) -> list[dict]:
    """Everything sent from ``mark`` until the browser got everything the session last drew."""
    session.settle()
    node = _SENTINELS.get(id(session))
    if node is None:
        node = _SENTINELS[id(session)] = session.client.scene.add_frame(
            SENTINEL, visible=False, show_axes=False
        )
    x = float(node.position[0]) + 1.0
    node.position = (x, 0.0, 0.0)

    def arrived(m: dict) -> bool:
        return m.get("name") == SENTINEL and tuple(m.get("position", ()))[:1] == (x,)

    ws.wait_for(arrived, after=mark)
    return _after(ws, mark)


def _move(ws, session, q2: float) -> None:
    """Move q2 to ``q2`` degrees as the browser does, and wait until the session has taken it."""
    ws.set_value(handle_uuid(session.panel.joints.sliders[1]), q2)
    poll(lambda: np.isclose(session.state.q[1], np.radians(q2)), what=f"q2 = {q2}° taken")


def _redraw_of(ws, session, q2: float) -> list[dict]:
    """The messages of one slider change of q2 (to ``q2`` degrees), sent as the browser does."""
    _wait_drawn(ws, session, 0)  # whatever came before is in
    mark = ws.mark()
    _move(ws, session, q2)
    return _wait_drawn(ws, session, mark)


def test_a_redraw_of_an_unchanged_state_sends_nothing(lab_client, session):
    _, _, ws = lab_client
    first = _redraw_of(ws, session, 20.0)
    mark = ws.mark()
    redraws = session.redraws
    session.dispatch(Redraw())  # the same state drawn again: every value is the one already shown
    session.settle()
    assert session.redraws == redraws + 1
    _move(ws, session, 25.0)  # a later change ends the list
    sent = _wait_drawn(ws, session, mark)
    # Only the later change's redraw arrived: one message per node and kind, as in the first change.
    kinds = collections.Counter((m["type"], m.get("name") or m.get("uuid")) for m in sent)
    assert max(kinds.values()) == 1, [k for k, n in kinds.items() if n > 1]
    assert set(kinds) <= {(m["type"], m.get("name") or m.get("uuid")) for m in first}


def test_a_slider_change_moves_each_node_with_one_message_and_leaves_the_rest_alone(lab_client, session):
    _, _, ws = lab_client
    _redraw_of(ws, session, 10.0)
    sent = _redraw_of(ws, session, 12.0)
    kinds = collections.Counter((m["type"], m.get("name") or m.get("uuid")) for m in sent)
    twice = [k for k, n in kinds.items() if n > 1]
    assert not twice, [str(m)[:300] for m in sent if (m["type"], m.get("name") or m.get("uuid")) in twice]
    names = {m.get("name") for m in sent if m.get("name")}
    # q2 moved: joints 3… and the glyphs at the tool moved; the base, the grid, q1's label did not.
    assert {"/lab/arm/cylinders", "/lab/arm/label_2", "/lab/jacobian/columns"} <= names
    assert not names & {"/lab/arm/label_0", "/lab/arm/label_1", "/lab/arm/grid", "/lab/arm/pedestal"}
    # One message carries the cylinders' positions and orientations (their sizes did not change).
    cylinders = next(m for m in sent if m.get("name") == "/lab/arm/cylinders")
    assert sorted(cylinders["updates"]) == ["batched_positions", "batched_wxyzs"]
    # Hidden glyphs and the GUI inputs the user did not touch send nothing.
    hidden = {"/lab/jacobian/angular_columns", "/lab/jacobian/rotational_ellipsoid"}
    hidden |= {"/lab/jacobian/force_ellipsoid", "/lab/jacobian/twist_and_force"}
    assert not names & hidden
    slider_uuids = {handle_uuid(s) for s in session.panel.joints.sliders}
    assert not {m.get("uuid") for m in sent} & slider_uuids  # the browser already shows its value


def test_a_glyph_switched_off_costs_no_message_while_the_arm_moves(lab_client, session):
    _, _, ws = lab_client
    session.dispatch(SetOption("columns", False))
    session.dispatch(SetJoint(1, 0.1))
    session.settle()
    sent = _redraw_of(ws, session, 15.0)
    assert "/lab/jacobian/columns" not in {m.get("name") for m in sent}
    assert not scene_node(session, "/lab/jacobian/columns").visible
    session.dispatch(SetOption("columns", True))  # shown again: drawn where the arm now is
    session.settle()
    node = scene_node(session, "/lab/jacobian/columns")
    assert node.visible
    starts = np.asarray(node.points)[:, 0]
    np.testing.assert_allclose(starts, np.tile(session.snapshot.tool_point, (len(starts), 1)), atol=1e-6)
