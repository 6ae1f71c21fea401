"""A widget callback that only queues an action runs on viser's event loop, not in its thread pool
(``app.viser_adapter.on_event_loop``); the app's slider bindings are such callbacks."""

from __future__ import annotations

import logging
import threading

import viser
from fakes import poll
from wsclient import ViserWsClient

from app import viser_adapter as va
from app.server import Lab


def loop_thread(server: viser.ViserServer) -> int:
    """The id of the thread running ``server``'s event loop."""
    got: list[int] = []
    server._websock_server._background_event_loop.call_soon_threadsafe(
        lambda: got.append(threading.get_ident())
    )
    return poll(lambda: got[0] if got else None, what="the event loop's thread")


def test_a_marked_callback_runs_on_the_event_loop_and_an_unmarked_one_in_the_pool(checked):
    with ViserWsClient(f"ws://127.0.0.1:{checked.get_port()}") as ws:
        poll(lambda: len(checked.get_clients()) == 1)
        (client,) = checked.get_clients().values()
        slider = client.gui.add_slider("q1", min=-1.0, max=1.0, step=0.01, initial_value=0.0)
        marked: list[tuple[float, int]] = []
        plain: list[tuple[float, int]] = []
        slider.on_update(va.on_event_loop(lambda e: marked.append((e.target.value, threading.get_ident()))))
        slider.on_update(lambda e: plain.append((e.target.value, threading.get_ident())))
        poll(lambda: ws.mark() > 0)
        ws.set_value(va.handle_uuid(slider), 0.5)
        poll(lambda: marked and plain, what="both callbacks called")
        loop = loop_thread(checked)
        assert marked == [(0.5, loop)]
        assert plain[0][0] == 0.5 and plain[0][1] not in (loop, threading.get_ident())
        slider.value = -0.25  # assigned by the server: called on the assigning thread, as viser does
        assert marked[-1] == (-0.25, threading.get_ident())


def test_marked_callbacks_see_every_value_in_the_order_sent(checked):
    with ViserWsClient(f"ws://127.0.0.1:{checked.get_port()}") as ws:
        poll(lambda: len(checked.get_clients()) == 1)
        (client,) = checked.get_clients().values()
        slider = client.gui.add_slider("q1", min=-1.0, max=1.0, step=0.01, initial_value=0.0)
        seen: list[float] = []
        slider.on_update(va.on_event_loop(lambda e: seen.append(e.target.value)))
        poll(lambda: ws.mark() > 0)
        sent = [round(-0.9 + 0.05 * i, 2) for i in range(20)]  # within a tab's burst of GUI updates
        for value in sent:
            ws.set_value(va.handle_uuid(slider), value)
        poll(lambda: len(seen) == len(sent), what="every value")
        assert seen == sent


def test_a_failing_marked_callback_is_logged_and_the_next_value_still_arrives(checked, caplog):
    with ViserWsClient(f"ws://127.0.0.1:{checked.get_port()}") as ws:
        poll(lambda: len(checked.get_clients()) == 1)
        (client,) = checked.get_clients().values()
        slider = client.gui.add_slider("q1", min=-1.0, max=1.0, step=0.01, initial_value=0.0)
        seen: list[float] = []

        def callback(event: viser.GuiEvent) -> None:
            if event.target.value < 0:
                raise ValueError("negative on purpose")
            seen.append(event.target.value)

        slider.on_update(va.on_event_loop(callback))
        poll(lambda: ws.mark() > 0)
        with caplog.at_level(logging.ERROR, logger="app.viser_adapter"):
            ws.set_value(va.handle_uuid(slider), -0.5)
            ws.set_value(va.handle_uuid(slider), 0.75)
            poll(lambda: seen == [0.75], what="the value after the failure")
        assert any("negative on purpose" in r.getMessage() + str(r.exc_info) for r in caplog.records)


def test_the_apps_joint_slider_dispatches_from_the_event_loop():
    """No thread hand-over between the value's arrival and the tab's queue: one fewer per change."""
    lab = Lab(port=0)
    try:
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}") as ws:
            session = poll(lambda: lab.sessions and next(iter(lab.sessions.values())), what="a tab")
            session.settle()
            threads: list[int] = []
            renderer = session.renderer

            class Watched:  # the renderer, told of the tab's queued action from which thread
                def schedule(self, tab: object) -> None:
                    threads.append(threading.get_ident())
                    renderer.schedule(tab)

                def __getattr__(self, name: str) -> object:
                    return getattr(renderer, name)

            session.renderer = Watched()  # type: ignore[assignment]
            slider = session.panel.joints.sliders[1]  # type: ignore[union-attr]
            ws.set_value(va.handle_uuid(slider), 12.0)
            poll(lambda: threads, what="the slider's action dispatched")
            assert threads == [loop_thread(lab.server)]
    finally:
        lab.stop()
