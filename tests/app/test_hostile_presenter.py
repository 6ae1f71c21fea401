"""Point 6 of issue 18: the presenter token holds. Wrong tokens are counted per address and per server
(reconnecting tabs gain nothing), ``--presenter`` alone makes a strong random token and a link, a weak
token is warned about, the token box is masked, and a presenter replaced by another tab is told."""

from __future__ import annotations

import pytest
from app_helpers import running_lab, wait_until
from hostile_helpers import RoundTrips, slider, widgets
from wsclient import ViserWsClient

from app.cli.main import main
from app.services.classroom import TAKEN_OVER, Classroom, presenter_link, random_token, token_weakness
from app.services.ratelimit import RoomLimits
from app.viser_adapter import message_class

TOKEN = "Xq7-vR2pLw9sKd4TzY"
UPDATE = message_class("GuiUpdateMessage")


def _is_token_box(m: dict) -> bool:
    return m["type"] == "GuiTextMessage" and m.get("props", {}).get("label") == "Presenter token"


def _token_box(ws: ViserWsClient) -> str:
    """The uuid of the "Presenter token" input (the page has other text inputs: the Build tab's, the
    page's own report)."""
    wait_until(lambda: any(_is_token_box(m) for m in widgets(ws).values()), timeout=60)
    return next(u for u, m in widgets(ws).items() if _is_token_box(m))


def _notice(ws: ViserWsClient, mark: int, title: str) -> str:
    _, m = ws.wait_for(
        lambda m: m["type"] == "NotificationShowMessage" and m["props"]["title"] == title,
        after=mark,
        timeout=30,
    )
    return m["props"]["body"]


def test_reconnecting_tabs_share_their_address_s_tries_and_the_room_carries_on():
    """The attack of the issue: tabs that reconnect to get fresh tries. Five wrong tokens from one
    address, then even the right one is refused unread, whichever tab sends it."""
    with running_lab(robot="planar2", presenter_token=TOKEN) as (lab, session, good):
        with RoundTrips(good, slider(good)) as trips:
            seen = set(lab.sessions)
            for i in range(7):
                with ViserWsClient(f"ws://127.0.0.1:{lab.port}") as bad:  # a fresh tab each time
                    new_tab = lambda known=frozenset(seen): set(lab.sessions) - known  # noqa: E731
                    wait_until(new_tab, timeout=60)  # its inputs are bound
                    seen |= set(lab.sessions)
                    box, mark = _token_box(bad), bad.mark()
                    bad.send(UPDATE(box, {"value": TOKEN if i == 6 else f"guess-{i}"}))
                    body = _notice(bad, mark, "Not the presenter")
                    expected = (
                        "not the presenter token" if i < 5 else "too many wrong tokens from this computer"
                    )
                    assert expected in body, (i, body)
            trips.check()
        assert lab.classroom.limits.wrong_tokens() == 5
        assert not any(s.following.role.presenting for s in lab.sessions.values())


def test_wrong_tokens_are_limited_per_server_across_addresses():
    clock = type("Clock", (), {"now": 0.0, "__call__": lambda self: self.now})()
    limits = RoomLimits(token_tries_per_address=5, token_tries_per_server=30, clock=clock)
    for address in range(30):
        assert limits.try_token(f"10.0.0.{address}", right=False) == "that is not the presenter token"
    assert "too many wrong tokens in this room" in limits.try_token("10.0.1.1", right=True)
    clock.now += 61
    assert limits.try_token("10.0.1.1", right=True) == ""


def test_the_presenter_replaced_by_another_tab_is_told():
    with running_lab(robot="planar2", presenter_token=TOKEN) as (lab, first, ws_first):
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}") as ws_second:
            wait_until(lambda: len(lab.sessions) == 2)
            second = next(s for s in lab.sessions.values() if s is not first)
            assert lab.classroom.claim(first.key, TOKEN) == ""
            wait_until(lambda: first.following.role.presenting)
            mark = ws_first.mark()
            box = _token_box(ws_second)
            ws_second.send(UPDATE(box, {"value": TOKEN}))
            wait_until(lambda: second.following.role.presenting, timeout=20)
            assert first.following.role.following
            assert _notice(ws_first, mark, "Classroom") == TAKEN_OVER


def test_the_token_box_is_masked_and_filled_from_the_presenter_link():
    """The script is sent for the token box; that it works in a real page (masked, filled, the link's
    query dropped) is tests/app/test_browser_room.py's (the fragment link it used to read never
    connected: a WebSocket address may not hold a fragment)."""
    with running_lab(robot="planar2", presenter_token=TOKEN) as (lab, session, ws):
        box = _token_box(ws)
        _, script = ws.wait_for(
            lambda m: m["type"] == "RunJavascriptMessage" and box in m["source"], timeout=30
        )
        assert 'input.type = "password"' in script["source"] and 'fields.get("presenter")' in script["source"]
        assert "history.replaceState" in script["source"]  # the token leaves the address bar


def test_one_presenter_link_in_the_query_never_the_fragment():
    """Issue 26, point 2: every path prints the link this one function builds (a fragment would keep
    viser's websocket from connecting); the token is quoted, so any token survives the address."""
    assert presenter_link("http://lab:8080", "a b/c#d") == "http://lab:8080/?presenter=a%20b%2Fc%23d"
    assert presenter_link("http://lab:8080/", TOKEN) == f"http://lab:8080/?presenter={TOKEN}"
    assert "#" not in presenter_link("http://lab:8080", TOKEN)


def test_serve_prints_a_presenter_link_not_a_token_to_type(capsys):
    from app.server import serve

    lab = serve(robot="planar2", port=0, block=False, presenter_token=TOKEN)
    try:
        out = capsys.readouterr().out
        assert f"{lab.url}/?presenter={TOKEN}" in out and "off the projector" in out
    finally:
        lab.stop()


def test_presenter_alone_is_random_and_strong_and_a_weak_token_is_warned_about(monkeypatch, capsys):
    import app.server

    calls: list[dict] = []
    monkeypatch.setattr(app.server, "serve", lambda **kwargs: calls.append(kwargs))
    assert main(["serve", "--presenter", "--port", "8124", "--workers", "1"]) == 0
    token = calls[-1]["presenter_token"]
    assert len(token) >= 16 and token_weakness(token) == "" and "warning" not in capsys.readouterr().err
    assert main(["serve", "--presenter", "--port", "8124", "--workers", "1"]) == 0
    assert calls[-1]["presenter_token"] != token
    for flag in ("--presenter", "--presenter-token"):
        assert main(["serve", flag, "lecture-7", "--port", "8124", "--workers", "1"]) == 0
        assert calls[-1]["presenter_token"] == "lecture-7"
        assert "warning: the presenter token 9 characters long is easy to guess" in capsys.readouterr().err


@pytest.mark.parametrize("token", ["lecture-7", "password", "aaaaaaaaaaa", "Tr0ub4dor&3"])
def test_weak_tokens_are_named(token):
    assert "easy to guess" in token_weakness(token)


def test_random_tokens_are_strong():
    assert all(token_weakness(random_token()) == "" for _ in range(50))


def test_a_classroom_without_addresses_counts_per_tab():
    room_ = Classroom("right-token-1234567")
    assert room_.address(3) == "tab 3"
