"""A replayed frame is queued for a follower as one buffer entry (``app/viser_adapter/frame_refs.py``,
issue 32), with viser's culling kept: held against viser's own buffer fed the same messages one by one,
over random sequences of frames and single messages (a slow socket that drains now and then), and the
wire bytes of a window of such entries against viser's own producer."""

from __future__ import annotations

import asyncio
import random

import numpy as np
import pytest
import zstandard
from fakes import poll
from test_classroom import room
from test_shared_frames import gui, same, viser_bytes
from viser.infra._async_message_buffer import AsyncMessageBuffer
from wsclient import decode_frame

from app.core.actions import SetJoint
from app.viser_adapter import SHARED_OWNER, SharedFrame, message_class
from app.viser_adapter import frames as frames_module
from app.viser_adapter.frame_refs import push_frame
from app.viser_adapter.frames import FrameRef, JoinedFrame


@pytest.fixture
def loop():
    loop = asyncio.new_event_loop()
    yield loop
    loop.close()


def node_messages(nodes, seed: float) -> list:
    """A frame's messages: each node's points and position (new objects, the keys of those nodes)."""
    update, position = message_class("SceneNodeUpdateMessage"), message_class("SetPositionMessage")
    out = []
    for n in nodes:
        out.append(update(f"/n{n}", {"points": np.full((2, 3), seed + n, dtype=np.float32)}))
        out.append(position(f"/n{n}", (seed, float(n), 0.0)))
    for m in out:
        m.owner = SHARED_OWNER
    return out


def expanded(buffer: AsyncMessageBuffer) -> list:
    """What the buffer still holds, in order, as the messages the socket will be sent."""
    out = []
    for ident in sorted(buffer.message_from_id):
        entry = buffer.message_from_id[ident]
        out.extend(entry.messages() if isinstance(entry, FrameRef) else [entry])
    return out


def effect(messages: list) -> dict:
    """What a browser ends with after ``messages``: the last message of each redundancy key."""
    return {m.redundancy_key(): m for m in messages}


def drain(buffer: AsyncMessageBuffer) -> list:
    with buffer.buffer_lock:
        return [buffer.pop_message_locked(i) for i in sorted(buffer.message_from_id)]


def test_a_newer_frame_replaces_the_waiting_messages_of_its_nodes(loop):
    ours = AsyncMessageBuffer(loop, persistent_messages=False)
    a, b = SharedFrame(node_messages([0, 1, 2], 1.0)), SharedFrame(node_messages([1], 2.0))
    single = node_messages([5], 3.0)[1]  # a position of node 5, queued on its own between
    push_frame(ours, a)
    ours.push(single)
    ours.push(gui("x"))
    push_frame(ours, b)
    entries = [ours.message_from_id[i] for i in sorted(ours.message_from_id)]
    assert len(entries) == 4 and isinstance(entries[0], FrameRef) and isinstance(entries[3], FrameRef)
    assert entries[0].frame is a and entries[0].skip == {2, 3}  # node 1's two messages: b's now
    assert entries[3].frame is b and entries[3].whole
    # viser's own buffer, fed message by message, holds the same messages in the same order
    theirs = AsyncMessageBuffer(loop, persistent_messages=False)
    for m in [*a.messages, single, entries[2], *b.messages]:
        theirs.push(m)
    assert expanded(ours) == [theirs.message_from_id[i] for i in sorted(theirs.message_from_id)]
    push_frame(ours, SharedFrame(node_messages([0, 2, 5], 4.0)))  # a's last messages replaced: a leaves
    assert not any(isinstance(e, FrameRef) and e.frame is a for e in ours.message_from_id.values())
    assert single not in ours.message_from_id.values()  # the single one too, as viser would drop it


@pytest.mark.parametrize("seed", range(8))
def test_random_frames_and_singles_leave_what_viser_s_buffer_leaves(loop, seed):
    rng = random.Random(seed)
    ours = AsyncMessageBuffer(loop, persistent_messages=False)
    theirs = AsyncMessageBuffer(loop, persistent_messages=False)
    sent_ours: list = []
    sent_theirs: list = []
    frames_only = True
    for step in range(60):
        roll = rng.random()
        if roll < 0.6:
            nodes = rng.sample(range(6), rng.randint(1, 4))
            frame = SharedFrame(node_messages(nodes, float(step)))
            push_frame(ours, frame)
            for m in frame.messages:
                theirs.push(m)
        elif roll < 0.85:
            m = node_messages([rng.randrange(6)], float(step))[rng.randrange(2)]
            frames_only = False  # a single message after a frame: viser drops the frame's, we send both
            ours.push(m)
            theirs.push(m)
        else:  # the socket takes what waits (a slow one, now and then)
            sent_ours += [x for e in drain(ours) for x in (e.messages() if isinstance(e, FrameRef) else [e])]
            sent_theirs += drain(theirs)
        # the order of what is sent keeps the browser's end state, and is viser's when only frames come
        assert effect(sent_ours + expanded(ours)) == effect(sent_theirs + expanded(theirs))
        if frames_only:
            assert expanded(ours) == expanded(theirs)
    waiting = [e for e in ours.message_from_id.values() if isinstance(e, FrameRef)]
    assert len(waiting) <= 6  # each waiting frame still has a node no newer frame replaced


def test_a_window_of_frame_entries_decodes_as_viser_s_own():
    a, b = SharedFrame(node_messages([0, 1, 2], 1.0)), SharedFrame(node_messages([1, 3], 2.0))
    window = [gui("before"), FrameRef(a, frozenset({2, 3})), FrameRef(b), gui("after")]
    plain = [gui_ for gui_ in window if not isinstance(gui_, FrameRef)]
    messages = [plain[0], *window[1].messages(), *b.messages, plain[1]]
    infra = frames_module._infra_module()
    ours = decode_frame(frames_module._wire(infra, zstandard.ZstdCompressor(level=1), window))
    same(ours, decode_frame(viser_bytes(messages)))
    assert b._packed is not None and a._packed is None  # the whole one placed as packed, the cut one not


def test_a_follower_is_queued_one_entry_per_presenter_frame():
    """On the old code each follower's buffer was pushed every message of the presenter's frame."""
    with room(3) as (lab, presenter, followers):
        poll(lambda: all(f.role.following for f in followers))
        for s in lab.sessions.values():
            s.settle()
        pushed: dict[int, list] = {}
        for f in followers:
            buffer = f.client._websock_connection.get_message_buffer()
            seen = pushed[f.key] = []

            def push(message, _push=buffer.push, seen=seen):
                seen.append(message)
                _push(message)

            buffer.push = push  # an instance attribute: shadows the method for this buffer only
        for i in range(3):
            for seen in pushed.values():
                seen.clear()
            presenter.dispatch(SetJoint(1, -0.3 + 0.2 * i))
            presenter.settle()
            for f in followers:
                poll(lambda f=f: f.state is presenter.state)
                f.settle()
            frame = tuple(presenter.screen.scene_messages)
            assert len(frame) >= 8  # the arm, the ellipsoid, the columns, the labels ...
            for seen in pushed.values():
                refs = [m for m in seen if isinstance(m, FrameRef)]
                assert len(refs) == 1 and refs[0].whole
                # the presenter's frame, or (a follower sent another follower's draw: app.tab.ride) that
                # frame joined with the GUI updates of the draw, in one entry
                got = refs[0].frame
                gui = message_class("GuiUpdateMessage")
                if isinstance(got, JoinedFrame):
                    assert got.parts[0].messages == frame
                    assert all(type(m) is gui for part in got.parts[1:] for m in part.messages)
                else:
                    assert got.messages == frame
                assert not any(m is x for m in seen for x in frame)  # none of its messages one by one


def test_a_slow_rider_is_left_only_the_latest_of_the_frames_it_was_sent(loop):
    """Followers sent one follower's draw (app/tab/ride.py) get it as one JoinedFrame entry: the room's
    scene frame and the draw's GUI updates. A socket that does not read is left, element by element and
    node by node, only the latest of what waits: the same messages viser's own buffer would keep, fed
    message by message; the others' buffers are not touched."""
    update = message_class("GuiUpdateMessage")
    slow = AsyncMessageBuffer(loop, persistent_messages=False)
    other = AsyncMessageBuffer(loop, persistent_messages=False)
    theirs = AsyncMessageBuffer(loop, persistent_messages=False)
    for move in range(6):
        scene = SharedFrame(node_messages([0, 1, 2], float(move)))
        panel = SharedFrame(
            [update("root-3-0-1", {"value": float(move)}), update("root-7-2", {"content": f"<p>{move}</p>"})],
            tag=False,
        )
        joined = JoinedFrame([scene, panel])
        push_frame(slow, joined)
        for m in joined.messages:
            theirs.push(m)
        push_frame(other, joined)
        drain(other)  # a follower that reads
    entries = list(slow.message_from_id.values())
    assert len(entries) == 1 and isinstance(entries[0], FrameRef) and entries[0].whole  # only the last move
    assert expanded(slow) == [theirs.message_from_id[i] for i in sorted(theirs.message_from_id)]
    assert not other.message_from_id
    raws, buffers = entries[0].frame.packed()  # each part packed once: the scene's arrays, then the panel
    assert len(raws) == 8 and len(buffers) == len(scene.packed()[1])
