"""Every function of app.viser_adapter against a real viser server and a websocket client.

A viser upgrade that moves one of the private details the adapter wraps makes the
matching test fail with ViserApiChanged, whose message names the adapter function and
the installed viser version.
"""

from __future__ import annotations

import asyncio
import json
import re
import threading

import numpy as np
import pytest
import viser
from fakes import POLL_TIMEOUT, poll
from locations import ROOT
from packaging.specifiers import SpecifierSet
from wsclient import ViserWsClient

from app import viser_adapter as va

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib


@pytest.fixture
def server():
    srv = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        yield srv
    finally:
        srv.stop()


@pytest.fixture
def connected(server):
    """(server, client handle, websocket client) with one connected tab."""
    with ViserWsClient(f"ws://127.0.0.1:{server.get_port()}") as ws:
        poll(lambda: len(server.get_clients()) == 1)
        (client,) = server.get_clients().values()
        yield server, client, ws


def test_the_tested_range_is_the_pin_and_includes_the_installed_viser():
    deps = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    (pin,) = [d for d in deps if d.startswith("viser")]
    assert pin == f"viser{va.TESTED_VISER}"
    assert viser.__version__ in SpecifierSet(va.TESTED_VISER), (
        f"viser {viser.__version__} is outside the range app/viser_adapter.py was tested with"
    )


def test_message_class_returns_protocol_messages_and_names_itself_when_missing():
    cls = va.message_class("GuiUpdateMessage")
    message = cls("abc", {"value": 1.5})
    assert message.as_serializable_dict()["type"] == "GuiUpdateMessage"
    with pytest.raises(va.ViserApiChanged) as info:
        va.message_class("NoSuchMessage")
    assert "app.viser_adapter.message_class" in str(info.value)
    assert f"viser {viser.__version__}" in str(info.value)


def test_quiet_banner_leaves_out_viser_s_console_lines_and_only_while_it_lasts(capsys):
    """viser prints its address box on start and "Server stopped" on stop whatever ``verbose`` says:
    with N workers that was N boxes before the app's one line."""
    with va.quiet_banner():
        quiet = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
        quiet.stop()
    assert capsys.readouterr().out == ""
    loud = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)  # the swap is undone
    loud.stop()
    out = capsys.readouterr().out
    assert f"127.0.0.1:{loud.get_port()}" in out and "Server stopped" in out


def test_errors_name_the_function_and_the_viser_version():
    for fn in (va.handle_uuid, va.is_removed, va.node_props, va.scene_handles):
        with pytest.raises(va.ViserApiChanged) as info:
            fn(object())
        assert f"app.viser_adapter.{fn.__name__}:" in str(info.value)
        assert f"viser {viser.__version__} is installed" in str(info.value)


def test_run_javascript_reaches_only_that_client(connected):
    server, client, ws = connected
    with ViserWsClient(f"ws://127.0.0.1:{server.get_port()}") as other:
        poll(lambda: len(server.get_clients()) == 2)
        mark, other_mark = ws.mark(), other.mark()
        va.run_javascript(client, "window.__probe = 41 + 1;")
        _, msg = ws.wait_for(lambda m: m["type"] == "RunJavascriptMessage", after=mark)
        assert msg["source"] == "window.__probe = 41 + 1;"
        # The other tab gets nothing: the first script it receives is one sent to it afterwards.
        (other_client,) = [c for c in server.get_clients().values() if c is not client]
        va.run_javascript(other_client, "/* marker */")
        _, got = other.wait_for(lambda m: m["type"] == "RunJavascriptMessage", after=other_mark)
        assert got["source"] == "/* marker */"


def test_set_page_title_passes_the_title_as_a_string_literal(connected):
    _, client, ws = connected
    title = 'Jacobian Lab"; alert(1); // </title>\u2028'
    mark = ws.mark()
    va.set_page_title(client, title)
    _, msg = ws.wait_for(lambda m: m["type"] == "RunJavascriptMessage", after=mark)
    literal = re.search(r"window\.__jacobianLabTitle = (.*);\n", msg["source"]).group(1)
    assert json.loads(literal) == title
    assert "alert(1); //" not in msg["source"].replace(literal, "")


def test_handle_uuid_is_the_id_the_page_sends_updates_for(connected):
    _, client, ws = connected
    mark = ws.mark()
    slider = client.gui.add_slider("q1", min=-1.0, max=1.0, step=0.01, initial_value=0.0)
    uuid = va.handle_uuid(slider)
    _, msg = ws.wait_for(lambda m: m["type"] == "GuiSliderMessage", after=mark)
    assert msg["uuid"] == uuid
    seen = threading.Event()
    slider.on_update(lambda _: seen.set())
    ws.set_value(uuid, 0.25)
    assert seen.wait(POLL_TIMEOUT)
    assert slider.value == 0.25


def test_is_removed_follows_remove_for_gui_and_scene_handles(connected):
    _, client, _ = connected
    button = client.gui.add_button("go")
    box = client.scene.add_box("/probe/box", dimensions=(1.0, 1.0, 1.0))
    assert (va.is_removed(button), va.is_removed(box)) == (False, False)
    button.remove()
    box.remove()
    assert (va.is_removed(button), va.is_removed(box)) == (True, True)


def test_scene_handles_and_node_props_read_what_is_sent(connected):
    _, client, ws = connected
    sphere = client.scene.add_icosphere("/probe/ellipsoid", radius=1.0, scale=(0.3, 0.2, 0.1))
    sphere.position = (0.5, -0.25, 1.0)
    handles = va.scene_handles(client.scene)
    assert handles["/probe/ellipsoid"] is sphere
    props = va.node_props(sphere)
    np.testing.assert_allclose(props["scale"], (0.3, 0.2, 0.1))
    np.testing.assert_allclose(props["position"], (0.5, -0.25, 1.0))
    assert props["radius"] == 1.0 and props["visible"] is True
    mark = ws.mark()
    sphere.visible = False
    assert va.node_props(sphere)["visible"] is False
    ws.wait_for(
        lambda m: m["type"] == "SetSceneNodeVisibilityMessage" and m["name"] == "/probe/ellipsoid", after=mark
    )
    sphere.remove()
    assert "/probe/ellipsoid" not in va.scene_handles(client.scene)


def test_update_props_sends_the_changed_props_in_one_message(connected):
    _, client, ws = connected
    v, f = np.eye(3, dtype=np.float32), np.array([[0, 1, 2]], np.uint32)
    node = client.scene.add_batched_meshes_simple(
        "/probe/batch",
        v,
        f,
        batched_wxyzs=np.tile([1.0, 0, 0, 0], (2, 1)),
        batched_positions=np.zeros((2, 3)),
        batched_scales=np.ones((2, 3)),
    )
    positions = np.array([[0.5, -1.0, 2.0], [0.25, 0.0, -0.5]])
    wxyzs = np.array([[0.0, 1.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]])
    ws.wait_for(lambda m: m["type"] == "BatchedMeshesMessage" and m["name"] == "/probe/batch")
    mark = ws.mark()
    assert va.update_props(
        node, batched_positions=positions, batched_wxyzs=wxyzs, batched_scales=np.ones((2, 3))
    )
    _, message = ws.wait_for(lambda m: m.get("name") == "/probe/batch", after=mark)  # the next one
    assert message["type"] == "SceneNodeUpdateMessage"
    assert sorted(message["updates"]) == ["batched_positions", "batched_wxyzs"]  # scales did not change
    np.testing.assert_allclose(message["updates"]["batched_positions"].reshape(2, 3), positions)
    np.testing.assert_allclose(message["updates"]["batched_wxyzs"].reshape(2, 4), wxyzs)
    np.testing.assert_allclose(node.batched_positions, positions)  # the handle holds what was sent
    assert node.batched_positions.dtype == np.float32
    positions[0, 0] = 9.0  # the caller's array is not shared with the handle
    assert node.batched_positions[0, 0] == pytest.approx(0.5)
    assert not va.update_props(
        node, batched_positions=node.batched_positions.copy()
    )  # unchanged: nothing sent
    three = np.arange(9.0).reshape(3, 3)
    assert va.update_props(node, batched_positions=three, batched_wxyzs=np.tile([1.0, 0, 0, 0], (3, 1)))
    np.testing.assert_allclose(node.batched_positions, three)  # a new instance count is stored whole
    node.remove()
    with pytest.raises(RuntimeError, match="removed"):
        va.update_props(node, batched_positions=three)


def test_set_pose_sends_only_a_changed_position_or_orientation(connected):
    _, client, ws = connected
    node = client.scene.add_icosphere("/probe/pose", radius=1.0)
    label = client.scene.add_label("/probe/pose_label", "q1")
    ws.wait_for(lambda m: m.get("name") == "/probe/pose_label")
    mark = ws.mark()
    va.set_pose(node, (0.5, -1.0, 2.0), (0.0, 1.0, 0.0, 0.0))
    va.set_pose(label, (1.0, 2.0, 3.0))
    va.set_pose(label, (1.0, 2.0, 3.0 + 1e-9))  # within viser's own tolerance: nothing sent
    va.update_props(node, scale=(0.3, 0.2, 0.1))
    va.update_props(node, scale=(0.3, 0.2, 0.1))  # unchanged: nothing sent
    ws.wait_for(lambda m: m.get("name") == "/probe/pose" and "scale" in m.get("updates", {}), after=mark)
    sent = [m for _, m in ws.messages[mark:] if str(m.get("name", "")).startswith("/probe/pose")]
    assert [(m["type"], m["name"]) for m in sent] == [
        ("SetPositionMessage", "/probe/pose"),
        ("SetOrientationMessage", "/probe/pose"),
        ("SetPositionMessage", "/probe/pose_label"),
        ("SceneNodeUpdateMessage", "/probe/pose"),
    ]
    np.testing.assert_allclose(sent[0]["position"], (0.5, -1.0, 2.0))
    np.testing.assert_allclose(sent[1]["wxyz"], (0.0, 1.0, 0.0, 0.0))
    np.testing.assert_allclose(sent[3]["updates"]["scale"], (0.3, 0.2, 0.1))
    np.testing.assert_allclose(node.position, (0.5, -1.0, 2.0))  # the handle holds what was sent
    np.testing.assert_allclose(node.wxyz, (0.0, 1.0, 0.0, 0.0))
    np.testing.assert_allclose(label.position, (1.0, 2.0, 3.0))
    assert va.node_props(node)["scale"] == (0.3, 0.2, 0.1)
    with pytest.raises(ValueError, match="3 numbers"):
        va.set_pose(label, (1.0, 2.0))
    label.remove()
    with pytest.raises(RuntimeError, match="removed"):
        va.set_pose(label, (0.0, 0.0, 0.0))


def test_install_icon_cache_reads_each_icon_once_and_gives_viser_the_same_svg(connected, monkeypatch):
    import zipfile

    from viser import _gui_api, _gui_handles, _icons

    expected = _icons.svg_from_icon(viser.Icon.MATH)  # viser's own reading (the cache may be installed)
    with zipfile.ZipFile(_icons.ICONS_DIR / "tabler-icons.zip") as archive:
        assert archive.read("math.svg").decode("utf-8") == expected
    va.install_icon_cache()
    va.install_icon_cache()  # idempotent
    assert _gui_api.svg_from_icon is _gui_handles.svg_from_icon is _icons.svg_from_icon
    opened = []
    real = zipfile.ZipFile
    monkeypatch.setattr(zipfile, "ZipFile", lambda *a, **k: opened.append(a) or real(*a, **k))
    icons = ("arrow-left", "arrow-right", "arrow-left")
    results: list[str] = []
    threads = [
        threading.Thread(target=lambda i=i: results.append(_icons.svg_from_icon(i))) for i in icons * 4
    ]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(results) == 12 and all(r.startswith("<svg") for r in results)
    assert len(opened) <= 1  # opened once per process: here, or before by the first icon read
    before = len(opened)
    assert _icons.svg_from_icon("arrow-up").startswith("<svg") and _icons.svg_from_icon("arrow-down")
    assert len(opened) == before  # new icons come from the archive already open
    assert _icons.svg_from_icon(viser.Icon.MATH) == expected
    _, client, ws = connected
    mark = ws.mark()
    client.gui.add_button("probe", icon=viser.Icon.MATH)  # viser's own path uses it
    _, message = ws.wait_for(lambda m: m["type"] == "GuiButtonMessage", after=mark)
    assert message["props"]["_icon_html"] == expected


@pytest.mark.slow
@pytest.mark.browser
def test_the_page_title_is_set_in_a_real_browser_and_kept(server):
    from browser_helpers import ARGS, CHROMIUM, new_page, require_browser

    sync_playwright = require_browser()
    server.on_client_connect(lambda client: va.set_page_title(client, "Jacobian Lab"))
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=ARGS)
        try:
            page = new_page(browser, {"width": 800, "height": 600})
            page.goto(f"http://127.0.0.1:{server.get_port()}")
            page.wait_for_function("document.title === 'Jacobian Lab'")
            page.evaluate("document.title = 'Viser'")  # as a page reset would
            page.wait_for_function("document.title === 'Jacobian Lab'")
        finally:
            browser.close()


def _loop_waiting_on(make_event):
    """(loop, its thread, the event, a future of one task awaiting the event) with the task waiting."""
    loop = asyncio.new_event_loop()
    thread = threading.Thread(target=loop.run_forever, daemon=True)
    thread.start()
    event = asyncio.run_coroutine_threadsafe(_make(make_event), loop).result(POLL_TIMEOUT)
    waiting = asyncio.run_coroutine_threadsafe(event.wait(), loop)
    poll(lambda: len(event._waiters) == 1, what="the task waiting")
    return loop, thread, event, waiting


async def _make(make_event):
    return make_event()


def _stop(loop, thread):
    loop.call_soon_threadsafe(loop.stop)
    thread.join(POLL_TIMEOUT)
    loop.close()


def test_an_asyncio_event_set_off_its_loop_completes_the_loops_futures_from_the_wrong_thread():
    """What viser's push does from the renderer thread (the cause of 'deque mutated during iteration')."""
    loop, thread, event, waiting = _loop_waiting_on(asyncio.Event)
    try:
        event.set()  # from this thread, which runs no loop
        assert event._waiters[0].done()  # completed here, while the loop's thread may change the deque
    finally:
        _stop(loop, thread)


def test_a_loop_safe_event_set_off_its_loop_leaves_the_waking_to_the_loops_thread():
    loop, thread, event, waiting = _loop_waiting_on(va.LoopSafeEvent)
    try:
        event.set()
        assert event.is_set()  # seen at once (viser reads it synchronously)
        assert not event._waiters[0].done()  # the loop's futures untouched from this thread
        loop.call_soon_threadsafe(event.set)  # what viser's push does next: the flag is up already
        assert waiting.result(POLL_TIMEOUT) is True
    finally:
        _stop(loop, thread)


def test_install_loop_safe_events_gives_every_buffer_one_and_messages_still_arrive():
    va.install_loop_safe_events()
    srv = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        with ViserWsClient(f"ws://127.0.0.1:{srv.get_port()}") as ws:
            poll(lambda: len(srv.get_clients()) == 1)
            (client,) = srv.get_clients().values()
            buffers = [
                srv._websock_server.get_message_buffer(),
                client._websock_connection.get_message_buffer(),
            ]
            assert all(isinstance(b.message_event, va.LoopSafeEvent) for b in buffers)
            mark = ws.mark()
            threading.Thread(target=lambda: client.gui.add_markdown("from another thread")).start()
            ws.wait_for(lambda m: "from another thread" in json.dumps(m, default=str), after=mark)
    finally:
        srv.stop()


def _queued(client: viser.ClientHandle) -> int:
    """How many messages were ever queued on ``client``'s own connection."""
    return client._websock_connection.get_message_buffer().message_counter


def test_a_tabs_own_widget_is_not_echoed_to_its_own_connection(checked):
    """viser relays a value a tab sends to the widget's other clients; a tab's own widget has none, so
    nothing is queued (viser queued a message that its only client then skipped)."""
    with ViserWsClient(f"ws://127.0.0.1:{checked.get_port()}") as ws:
        poll(lambda: len(checked.get_clients()) == 1)
        (client,) = checked.get_clients().values()
        slider = client.gui.add_slider("q1", min=-1.0, max=1.0, step=0.01, initial_value=0.0)
        seen: list[float] = []
        slider.on_update(lambda _: seen.append(slider.value))
        poll(lambda: _queued(client) > 0 and ws.mark() > 0)
        for value in (0.25, 0.5):
            before = _queued(client)
            ws.set_value(va.handle_uuid(slider), value)
            poll(lambda v=value: seen[-1:] == [v])
            assert _queued(client) == before
        assert slider.value == 0.5


def test_a_shared_widget_still_relays_a_tabs_value_to_the_other_tabs(checked):
    slider = checked.gui.add_slider("shared", min=-1.0, max=1.0, step=0.01, initial_value=0.0)
    url = f"ws://127.0.0.1:{checked.get_port()}"
    with ViserWsClient(url) as ws, ViserWsClient(url) as other:
        poll(lambda: len(checked.get_clients()) == 2)
        mark = other.mark()
        ws.set_value(va.handle_uuid(slider), 0.75)
        _, msg = other.wait_for(
            lambda m: m["type"] == "GuiUpdateMessage" and m["uuid"] == va.handle_uuid(slider), after=mark
        )
        assert msg["updates"] == {"value": 0.75}
        poll(lambda: slider.value == 0.75)


def test_an_unchanged_plain_prop_queues_nothing_and_a_changed_one_is_sent(connected):
    """install_fast_prop_casts returns early for a string, bool or number a handle already holds (viser
    skips it too, after casting); a changed one, a property such as an input's value, and a removed
    handle behave as viser's own assignment."""
    _, client, ws = connected
    va.install_fast_prop_casts()
    html = client.gui.add_html("<b>one</b>")
    slider = client.gui.add_slider("s", min=0.0, max=1.0, step=0.01, initial_value=0.5)
    queued: list = []
    conn = client.gui._websock_interface
    original = conn.queue_message
    conn.queue_message = lambda m: (queued.append(m), original(m))[1]
    try:
        html.content = "<b>one</b>"
        html.visible = True
        slider.max = 1.0
        assert queued == []
        html.content = "<b>two</b>"
        slider.max = 2  # an int for a float prop: cast and sent, as viser does
        slider.value = 0.5  # a property: viser's own setter decides
        updates = [m.updates for m in queued]
        assert {"content": "<b>two</b>"} in updates and {"max": 2.0} in updates
        assert html.content == "<b>two</b>" and slider.max == 2.0
        _, sent = ws.wait_for(lambda m: m["type"] == "GuiUpdateMessage" and "content" in m["updates"])
        assert sent["updates"]["content"] == "<b>two</b>"
    finally:
        del conn.queue_message
    html.remove()
    with pytest.raises(RuntimeError, match="removed"):
        html.content = "<b>two</b>"  # the value it held, but removed: refused as viser refuses it


def test_set_camera_leaves_the_camera_as_visers_setters_do_and_sends_its_final_pose(server):
    """Two tabs, one pointed with viser's own setters (up, position, then look_at), one with
    ``set_camera``: the same pose and orientation on the server, and the last position, look-at and up
    each browser was sent are the same; an unchanged pose sends nothing; a bad one changes nothing."""
    url = f"ws://127.0.0.1:{server.get_port()}"
    with ViserWsClient(url) as ws_a, ViserWsClient(url) as ws_b:
        poll(lambda: len(server.get_clients()) == 2)
        a, b = sorted(server.get_clients().values(), key=lambda c: c.client_id)  # ws_a connected first
        rng = np.random.default_rng(7)
        for i in range(5):
            position, look_at = rng.normal(size=3) * 2 + np.array([0, 0, 3.0]), rng.normal(size=3) * 0.3
            # The last pose's up is one no earlier pose had: its arrival means every earlier one arrived.
            up = (0.0, 0.0, 1.0) if rng.random() < 0.6 and i < 4 else tuple(rng.normal(size=3))
            a.camera.up_direction = up
            a.camera.position = position
            a.camera.look_at = look_at
            va.set_camera(b, position, look_at, up)
            for name in ("position", "look_at", "up_direction"):
                np.testing.assert_allclose(getattr(b.camera, name), getattr(a.camera, name), atol=1e-12)
            q_a, q_b = np.asarray(a.camera.wxyz), np.asarray(b.camera.wxyz)
            assert np.allclose(q_a, q_b, atol=1e-9) or np.allclose(q_a, -q_b, atol=1e-9)

        def last(ws, kind: str):
            with ws._cond:
                sent = [m for _, m in ws.messages if m["type"] == kind]
            return sent[-1] if sent else None

        final = {"SetCameraPositionMessage": position, "SetCameraLookAtMessage": look_at}
        final["SetCameraUpDirectionMessage"] = np.asarray(up)
        for kind, value in final.items():
            key = "look_at" if kind == "SetCameraLookAtMessage" else "position"  # (viser's up: "position")

            def arrived(ws, kind=kind, key=key, value=value) -> bool:  # the last pose's: nothing in flight
                got = last(ws, kind)
                return got is not None and np.allclose(got[key], value)

            poll(lambda arrived=arrived: arrived(ws_a) and arrived(ws_b), what=f"the last {kind} in both")
            assert np.allclose(last(ws_a, kind)[key], last(ws_b, kind)[key])  # alike
        mark = ws_b.mark()
        va.set_camera(b, b.camera.position.copy(), b.camera.look_at.copy(), b.camera.up_direction.copy())
        before = b.camera.position.copy()
        with pytest.raises(ValueError, match="finite"):
            va.set_camera(b, (np.nan, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0))
        np.testing.assert_array_equal(b.camera.position, before)
        va.set_camera(b, before + 1.0, b.camera.look_at, b.camera.up_direction)  # a change: sent after
        ws_b.wait_for(lambda m: m["type"] == "SetCameraPositionMessage", after=mark)
        kinds = [m["type"] for _, m in ws_b.messages[mark:] if m["type"].startswith("SetCamera")]
        assert kinds == ["SetCameraPositionMessage"]  # nothing for the unchanged pose nor the refused one
