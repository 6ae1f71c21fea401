"""Issue 31: 60 websocket followers of the default ``serve --presenter --workers 2`` answer a question;
the presenter's bars count every answer once, across both workers (each follower picks a known choice,
so the bars are known), and a click naming another tab's answer reaches only the sender's own panel."""

from __future__ import annotations

import html
import re
import urllib.parse

import pytest
from fakes import poll
from server_process import Server, printed_presenter_link
from wsclient import ViserWsClient

pytestmark = [pytest.mark.slow]

FOLLOWERS = 60
PAGE_LOADED = '{"kind": "load", "address": "", "resume": "", "tab": ""}'
CHOICES = ("regular", "wrist", "elbow", "shoulder", "boundary", "another kind")


def _uuid(ws: ViserWsClient, kind: str, label: str) -> str:
    _, msg = ws.wait_for(lambda m: m["type"] == kind and m["props"].get("label") == label, timeout=120)
    return msg["uuid"]


def _bars(ws: ViserWsClient, after: int, want: str) -> str:
    """The presenter's bars' HTML once they read ``want`` ("60 of 60 tabs answered")."""
    try:
        _, msg = ws.wait_for(
            lambda m: m["type"] == "GuiUpdateMessage" and want in str(m.get("updates")),
            after=after,
            timeout=60,
        )
    except TimeoutError:
        said = [str(m.get("updates")) for _, m in ws.messages[after:] if "answered" in str(m.get("updates"))]
        raise AssertionError(f"never {want!r}; last: {said[-1:]}") from None
    return html.unescape(str(msg["updates"]))


def test_sixty_websocket_followers_on_two_workers_every_answer_counted_once(tmp_path):
    server = Server(tmp_path, argv=["serve", "--presenter", "--port", "0", "--workers", "2"])
    clients: list[ViserWsClient] = []
    try:
        token = urllib.parse.parse_qs(urllib.parse.urlsplit(printed_presenter_link(server)).query)[
            "presenter"
        ][0]
        presenter = ViserWsClient(server.url())
        presenter.start()
        clients.append(presenter)
        presenter.set_value(_uuid(presenter, "GuiTextMessage", "page"), PAGE_LOADED)
        ask = _uuid(presenter, "GuiButtonMessage", "Ask the room")
        presenter.set_value(_uuid(presenter, "GuiTextMessage", "Presenter token"), token)
        presenter.wait_for(
            lambda m: m["type"] == "GuiUpdateMessage" and "You are presenting" in str(m.get("updates")),
            timeout=120,
        )
        room = []
        for _ in range(FOLLOWERS):
            c = ViserWsClient(server.url())
            c.start()
            c.set_value(_uuid(c, "GuiTextMessage", "page"), PAGE_LOADED)
            clients.append(c)
            box = _uuid(c, "GuiFolderMessage", "Question")
            room.append((c, box, [_uuid(c, "GuiButtonMessage", str(i)) for i in range(6)]))
        poll(
            lambda: len(set(re.findall(r"open in process (\d+)", server.log.read_text()))) == 2,
            what="tabs on both workers",
        )
        mark = presenter.mark()
        presenter.set_value(ask, True)
        want = [0] * 6
        for k, (c, box, buttons) in enumerate(room):
            c.wait_for(  # its Question box opened: the question reached it
                lambda m, box=box: (
                    m["type"] == "GuiUpdateMessage"
                    and m.get("uuid") == box
                    and m.get("updates", {}).get("visible") is True
                ),
                timeout=120,
            )
            choice = k % 5  # regular, wrist, elbow, shoulder, boundary: 12 each
            c.set_value(buttons[choice], True)
            want[choice] += 1
            if k == 1:
                # Tab 0 sends a click naming tab 1's "shoulder". A tab's GUI ids follow its panel's
                # structure, so that id is also tab 0's own "shoulder": the click changes tab 0's answer (its
                # own widget), never tab 1's (a tab's messages reach only its own widgets); an id no tab has
                # changes nothing. Sent before the others answer: the room's count ends after it.
                room[0][0].set_value(room[1][2][3], True)
                room[0][0].set_value("root-999-999", True)
                want[0] -= 1
                want[3] += 1
        bars = _bars(presenter, mark, f"{FOLLOWERS} of {FOLLOWERS} tabs answered")
        rows = re.findall(r'anywhere">([^<]+?)</span>.*?text-align:right">(\d+)</span>', bars)
        assert rows == [(label, str(n)) for label, n in zip(CHOICES, want, strict=True)], bars
    finally:
        for c in clients:
            c.close()
        server.cleanup()
