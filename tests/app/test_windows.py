"""A socket's windows (``app/viser_adapter/windows.py``, issue 32) against viser's own window generator:
the same messages in the same order over random pushes, atomic blocks and culling, the backlog marker
right after the backlog, and one pause per window a follower is sent where viser's loop waited three or
four times."""

from __future__ import annotations

import asyncio
import contextlib
import random

import pytest
from viser.infra._async_message_buffer import AsyncMessageBuffer

from app.viser_adapter import install_loop_safe_events, message_class
from app.viser_adapter import windows as windows_module
from app.viser_adapter.events import LoopSafeEvent
from app.viser_adapter.windows import windows


@pytest.fixture
def loop():
    install_loop_safe_events()  # as the server does: the buffers' events are LoopSafeEvents
    loop = asyncio.new_event_loop()
    yield loop
    loop.close()


def update(uuid: str, value: object):
    return message_class("GuiUpdateMessage")(uuid, {"value": value})


class Socket:
    """One buffer and a generator of its windows (ours or viser's), read until it has taken all."""

    def __init__(self, loop, ours: bool, persistent: bool = False, marker: object = None) -> None:
        self.buffer = AsyncMessageBuffer(loop, persistent_messages=persistent)
        self.ours, self.marker, self.sent, self.windows = ours, marker, [], 0
        self.gen = None

    def start(self) -> None:
        b = self.buffer
        if self.ours:
            self.gen = windows(b, 7, self.marker)
        else:
            self.gen = b.window_generator(7, backlog_done_message=self.marker)

    async def read_all(self) -> None:
        """Windows until the generator has read everything pushed (its cursor at the last message)."""
        b = self.buffer
        while b.generator_cursors.get(7, -2) < b.message_counter - 1 or self.marker_pending():
            window = await asyncio.wait_for(self.gen.__anext__(), 30)
            self.sent.extend(window)
            self.windows += 1

    def marker_pending(self) -> bool:
        return self.marker is not None and self.marker not in self.sent

    async def close(self) -> None:
        self.buffer.set_done()
        await self.gen.aclose()


@pytest.mark.parametrize("persistent", [False, True])
@pytest.mark.parametrize("seed", range(6))
def test_the_same_messages_as_viser_in_the_same_order(loop, seed, persistent):
    rng = random.Random(seed)
    marker = update("marker", 0)
    sockets = [Socket(loop, ours, persistent, marker) for ours in (True, False)]
    ops = []
    for _ in range(rng.randint(0, 6)):  # a backlog before the socket connects
        ops.append(("push", f"u{rng.randint(0, 4)}", rng.random()))
    ops.append(("start",))
    for _ in range(60):
        r = rng.random()
        if r < 0.55:
            ops.append(("push", f"u{rng.randint(0, 4)}", rng.random()))
        elif r < 0.65:  # a draw: several pushes in one atomic block, read after it ends
            ops.append(
                ("atomic", [(f"u{rng.randint(0, 4)}", rng.random()) for _ in range(rng.randint(1, 5))])
            )
        elif r < 0.7:
            ops.append(("flush",))
        else:
            ops.append(("read",))
    ops.append(("read",))

    async def run(socket: Socket) -> None:
        b = socket.buffer
        for op in ops:
            if op[0] == "push":
                b.push(update(op[1], op[2]))
            elif op[0] == "start":
                socket.start()
            elif op[0] == "atomic":
                b.atomic_start()
                for uuid, value in op[1]:
                    b.push(update(uuid, value))
                b.atomic_end()
            elif op[0] == "flush":
                b.flush()
            elif op[0] == "read":
                await socket.read_all()
        await socket.close()

    for socket in sockets:
        loop.run_until_complete(run(socket))
    ours, theirs = ([(m.uuid, m.updates) for m in s.sent] for s in sockets)
    assert ours == theirs and ours  # the backlog marker included, where viser puts it
    backlog = sum(1 for op in ops[: ops.index(("start",))] if op[0] == "push")
    assert sockets[0].sent.index(marker) <= backlog  # right after the backlog (culled entries absent)


def test_a_follower_window_is_paced_once_where_viser_waited_more(loop, monkeypatch):
    """A presenter's move reaches a follower as one atomic block (its frame and panel updates): with
    viser's loop each window cost three or four ``asyncio.wait`` with a timer; ours sleeps until the next
    push and waits out a pause only when that push comes within the window's length."""
    waits = {"ours": 0, "viser": 0}
    real_wait = asyncio.wait

    def counting(kind: str):
        async def wait(*args, **kwargs):
            waits[kind] += 1
            return await real_wait(*args, **kwargs)

        return wait

    async def room(socket: Socket, kind: str) -> int:
        socket.start()
        reader = asyncio.ensure_future(consume(socket))
        for move in range(12):
            b = socket.buffer
            b.atomic_start()
            for uuid in ("frame", "slider", "matrix", "status"):
                b.push(update(uuid, move))
            b.atomic_end()
            while len(socket.sent) < 4 * (move + 1):  # the move sent: then the next one, as a room's
                await asyncio.sleep(0.001)
            await asyncio.sleep(0.03)  # the presenter's next move comes later than a window
        reader.cancel()
        with contextlib.suppress(asyncio.CancelledError):
            await reader  # the generator is free again: then closed
        await socket.close()
        return len(socket.sent)

    async def consume(socket: Socket) -> None:
        while True:
            socket.sent.extend(await socket.gen.__anext__())
            socket.windows += 1

    for kind, ours in (("ours", True), ("viser", False)):
        monkeypatch.setattr(windows_module.asyncio, "wait", counting(kind))  # the one asyncio module
        socket = Socket(loop, ours)
        assert loop.run_until_complete(room(socket, kind)) == 48
        if ours:
            assert isinstance(socket.buffer.message_event, LoopSafeEvent)
            assert socket.windows == 12  # one window a move: the atomic block was never split
            # moves further apart than a window: the pause after each is over before the next push, so
            # it is never waited out (no timer); a tight loop could still wake within one: at most a few
            assert waits["ours"] <= 2, waits
    assert waits["viser"] >= 2 * 12  # what was saved: viser's loop waited at least twice a window


def test_a_flush_cuts_the_pause_and_a_closed_buffer_ends_the_windows(loop):
    socket = Socket(loop, ours=True)
    socket.buffer.window_duration_sec = 3600.0  # a pause no test could wait out: only a flush ends it

    async def run() -> list:
        b = socket.buffer
        socket.start()
        b.push(update("a", 1))
        first = await asyncio.wait_for(socket.gen.__anext__(), 30)
        nxt = asyncio.ensure_future(socket.gen.__anext__())
        await asyncio.sleep(0)  # one step of its task: it drained the buffer, so it pauses
        b.push(update("b", 2))  # within the window's pause
        await asyncio.sleep(0)
        assert not nxt.done()
        b.flush()
        second = await asyncio.wait_for(nxt, 30)
        b.set_done()
        with pytest.raises(StopAsyncIteration):
            await asyncio.wait_for(socket.gen.__anext__(), 30)
        return [m.uuid for m in (*first, *second)]

    assert loop.run_until_complete(run()) == ["a", "b"]
    assert 7 not in socket.buffer.generator_cursors  # a closed socket holds no cursor back
