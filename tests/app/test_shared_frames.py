"""A presenter's scene frame is serialised once per process, whatever the room (issue 32).

Every tab's scene has one owner (``share_owner``), so a follower is sent the presenter's very message
objects; the producer that replaces viser's (``app/viser_adapter/frames.py``) packs such a frame once
and places the packed bytes in every socket's window. Held here: the count of packings against the
number of sockets, the followers' decoded frames against the presenter's, and the wire bytes against
viser's own producer for windows that hold a whole frame, a frame cut by a newer one (a socket that
fell behind) and none.
"""

from __future__ import annotations

import asyncio

import numpy as np
import pytest
from fakes import poll
from test_classroom import room
from wsclient import ViserWsClient, decode_frame

from app.core.actions import SetJoint
from app.viser_adapter import SHARED_OWNER, SharedFrame, message_class
from app.viser_adapter import frames as frames_module

ARM = "/lab/arm/cylinders"


def arm_update(m: dict) -> bool:
    return m["type"] == "SceneNodeUpdateMessage" and m["name"] == ARM


class Serialised:
    """Counts, per message object, how often viser's ``as_serializable_dict`` turned it into a dict (the
    messages are kept, so that no later message takes a counted one's id)."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch) -> None:
        self.calls: dict[int, list] = {}
        base = message_class("SetPositionMessage").__mro__[1]  # viser's Message
        original = base.as_serializable_dict

        def counting(message, binary_buffers=None):
            self.calls.setdefault(id(message), []).append(message)
            return original(message, binary_buffers)

        monkeypatch.setattr(base, "as_serializable_dict", counting)

    def of(self, messages) -> list[int]:
        return [sum(x is m for x in self.calls.get(id(m), ())) for m in messages]


@pytest.mark.parametrize("n_followers", [1, 5])
def test_a_presenter_frame_is_packed_once_for_every_follower(monkeypatch, n_followers):
    serialised = Serialised(monkeypatch)
    with room(n_followers) as (lab, presenter, followers):
        poll(lambda: all(f.role.following for f in followers))
        watchers = [ViserWsClient(f"ws://127.0.0.1:{lab.port}") for _ in range(2)]
        try:
            for w in watchers:
                w.start()
            poll(lambda: len(lab.sessions) == 3 + n_followers)
            poll(lambda: all(s.role.following for s in lab.sessions.values() if s is not presenter))
            for s in lab.sessions.values():
                s.settle()
            for i in range(4):
                marks = [w.mark() for w in watchers]
                presenter.dispatch(SetJoint(1, -0.4 + 0.2 * i))
                presenter.settle()
                got = [w.wait_for(arm_update, after=m)[1] for w, m in zip(watchers, marks, strict=True)]
                for s in lab.sessions.values():
                    s.settle()
                np.testing.assert_array_equal(got[0]["updates"]["batched_positions"],
                                              got[1]["updates"]["batched_positions"])  # fmt: skip
                frame = presenter.screen.scene_messages
                assert frame and all(m.owner == SHARED_OWNER for m in frame)
                assert frames_module.frame_of(frame).messages == tuple(frame)  # tagged as one frame
                # each of the frame's messages turned into a dict once, for the presenter's socket
                # and the 2 + n followers' (viser's own producer: 3 + n times each)
                assert serialised.of(frame) == [1] * len(frame), (serialised.of(frame), n_followers)
        finally:
            for w in watchers:
                w.close()


def scene_messages(k: int) -> list:
    update, position = message_class("SceneNodeUpdateMessage"), message_class("SetPositionMessage")
    out = []
    for i in range(k):
        points = np.arange(12, dtype=np.float32).reshape(4, 3) * (i + 1)
        out.append(update(f"/n{i}", {"points": points, "color": (i, 2, 3)}))
        out.append(position(f"/n{i}", (0.1 * i, 0.0, 1.0)))
    for m in out:
        m.owner = SHARED_OWNER
    return out


def gui(text: str) -> object:
    return message_class("GuiUpdateMessage")(f"uuid-{text}", {"content": text, "values": np.ones(3)})


def viser_bytes(window: list) -> bytes:
    """What viser's own producer sends for ``window`` (run over a one-window buffer)."""
    original = (
        frames_module._original.get("_message_producer") or frames_module._infra_module()._message_producer
    )
    sent: list[bytes] = []

    class Buffer:
        done = False

        def window_generator(self, client_id, backlog_done_message=None):
            async def gen():
                yield window
                self.done = True

            return gen()

    class Socket:
        async def send(self, data: bytes) -> None:
            sent.append(data)

    asyncio.run(original(Socket(), Buffer(), 0))
    assert len(sent) == 1
    return sent[0]


def same(a: list[dict], b: list[dict]) -> None:
    assert len(a) == len(b)
    for x, y in zip(a, b, strict=True):
        assert x.keys() == y.keys()
        for key in x:
            if isinstance(x[key], dict):
                same([x[key]], [y[key]])
            elif isinstance(x[key], np.ndarray):
                np.testing.assert_array_equal(x[key], y[key])
            else:
                assert x[key] == y[key], key


@pytest.mark.parametrize("cut", [None, 3, "no frame"])
def test_the_wire_bytes_decode_as_viser_s_own(cut):
    """A whole frame between GUI messages, the same frame with message 3 gone (a newer frame replaced
    it in a socket that fell behind), and a window without a frame: decoded, the same messages as
    viser's own producer sends."""
    frame_messages = scene_messages(3)
    frame = SharedFrame(frame_messages)
    window = [gui("before"), *frame_messages, gui("after")]
    if cut == "no frame":
        window = [gui("a"), gui("b")]
    elif cut is not None:
        del window[1 + cut]
    infra = frames_module._infra_module()
    import zstandard

    ours = decode_frame(frames_module._wire(infra, zstandard.ZstdCompressor(level=1), window))
    same(ours, decode_frame(viser_bytes(window)))
    if cut is None:
        assert frame._packed is not None  # a whole frame is placed as packed
        assert frames_module._whole_frame(window) == (1, frame)
    else:
        assert frames_module._whole_frame(window) is None  # serialised for this socket, as viser does


def test_a_frame_placed_twice_is_packed_once():
    frame_messages = scene_messages(2)
    frame = SharedFrame(frame_messages)
    infra = frames_module._infra_module()
    import zstandard

    zstd = zstandard.ZstdCompressor(level=1)
    first = frame.packed()
    a = decode_frame(frames_module._wire(infra, zstd, [gui("x"), *frame_messages]))
    b = decode_frame(frames_module._wire(infra, zstd, [*frame_messages]))
    assert frame.packed() is first
    same(a[1:], b)
    assert frames_module.frame_of(frame_messages) is frame  # the messages know their frame
    assert frames_module.frame_of(frame_messages[:-1]) is not frame


def test_a_drag_of_the_handle_reaches_its_tab_under_the_shared_owner():
    """The browser echoes the owner of the node it drags; with every tab's owner the same, the drag
    still reaches that tab's handle (viser dispatches per connection, then by owner)."""
    from app_helpers import running_lab

    from kinematics import fk

    with running_lab(robot="planar2") as (lab, session, ws):
        session.panel.motion.gizmo.value = True
        session.settle()
        assert session.client.scene._owner_id == SHARED_OWNER
        T = fk(session.state.robot, session.state.q)
        target = T[:3, 3] + np.array([-0.05, 0.04, 0.0])
        drag = message_class("TransformControlsUpdateMessage")(
            "/lab/drive/handle", (1.0, 0.0, 0.0, 0.0), tuple(float(x) for x in target), SHARED_OWNER
        )
        ws.send(drag)
        poll(lambda: np.allclose(fk(session.state.robot, session.state.q)[:2, 3], target[:2], atol=1e-6))


def test_a_gui_update_of_plain_values_is_serialised_as_viser_serialises_it():
    """The producer builds a GUI update of plain values (str, bool, int, float) itself: over random
    updates, the same dict as viser's ``as_serializable_dict`` and the same msgpack bytes; numpy values
    and tuples still go through viser's walk."""
    import random

    update = message_class("GuiUpdateMessage")
    rng = random.Random(3)
    values = [
        "<div>J</div>", "", "ação ∞", True, False, 0, -7, 2**40, 0.5, -1e-300, float("inf"),
        np.float32(0.25), np.int64(3), np.bool_(True), (1.0, 2.0), ("a", np.float64(2.0)),
    ]  # fmt: skip
    fast = 0
    for i in range(200):
        keys = rng.sample(["value", "content", "label", "visible", "precision", "hint"], rng.randint(1, 3))
        message = update(f"uuid-{i}", {k: rng.choice(values) for k in keys})
        ours, theirs = [], []
        got = frames_module._serializable(message, ours)
        assert got == message.as_serializable_dict(theirs) and ours == theirs
        assert frames_module._ENCODE(got) == frames_module._ENCODE(message.as_serializable_dict([]))
        plain = all(type(v) in (str, bool, int, float) for v in message.updates.values())
        fast += plain
        assert (got["updates"] is message.updates) == plain  # the plain ones are not walked
    assert 20 < fast < 200


def test_a_window_of_whole_frames_is_compressed_once_for_every_socket():
    """Followers sent one follower's draw (app/tab/ride.py) have the same window: its messages are
    compressed once (one zstd frame), each socket's timestamp after them in a raw zstd frame of its own;
    decoded (across frames, as the browser's ZSTD_decompress reads them), viser's own messages."""
    import time

    import msgspec
    import zstandard

    from app.viser_adapter.frames import FrameRef

    scene, panel = SharedFrame(scene_messages(3)), SharedFrame([gui("a"), gui("b")], tag=False)
    panel_plain = SharedFrame(
        [message_class("GuiUpdateMessage")(f"u{i}", {"value": 0.5 * i}) for i in range(3)]
    )
    window = [FrameRef(scene), FrameRef(panel_plain)]
    infra = frames_module._infra_module()

    class Counting:
        def __init__(self) -> None:
            self.zstd, self.calls = zstandard.ZstdCompressor(level=1), 0

        def compress(self, data: bytes) -> bytes:
            self.calls += 1
            return self.zstd.compress(data)

    zstd = Counting()
    first = frames_module._wire(infra, zstd, window)
    time.sleep(0.002)  # another socket, later: its own timestamp
    second = frames_module._wire(infra, zstd, window)
    assert zstd.calls == 1
    want = decode_frame(viser_bytes([*scene.messages, *panel_plain.messages]))
    same(decode_frame(first), want)
    same(decode_frame(second), want)

    def stamp(data: bytes) -> float:
        size = int.from_bytes(data[8:16], "little")
        reader = zstandard.ZstdDecompressor().stream_reader(data[16 : 16 + size], read_across_frames=True)
        return msgspec.msgpack.decode(reader.read())["timestampSec"]

    assert stamp(second) > stamp(first)
    # Arrays in a frame after the first cannot share its numbering: serialised for the socket, as before.
    mixed = [FrameRef(SharedFrame([gui("c")], tag=False)), FrameRef(panel)]
    assert frames_module._whole_frames(mixed) is None
    same(
        decode_frame(frames_module._wire(infra, zstd, mixed)),
        decode_frame(viser_bytes([gui("c"), *panel.messages])),
    )
