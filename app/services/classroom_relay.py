"""The classroom of one worker process when the room spans several (``serve --workers N --presenter``).

:class:`RelayedClassroom` is the in-process :class:`~app.services.classroom.Classroom` (the same
tabs, roles and relays within the worker) with the room's decisions taken by the parent's
:class:`~app.services.room.RoomHub`, over a :class:`RoomChannel` (a ``multiprocessing`` pipe carrying
JSON, never pickles):

* a typed token and a reconnect key are checked by the hub (one presenter for the whole server; each
  worker counts the wrong tokens of its own tabs' connections, as one process does); the hub's
  reconnect key is the one the presenter's page keeps, so a presenter whose worker died comes back in
  another;
* the presenter's worker relays each commit to its own followers as before (the presenter's snapshot and
  scene messages) and sends the state to the hub (:mod:`app.services.state_codec`: robots the presenter
  built or uploaded as their file's text); every other worker computes the snapshot of each state it
  receives **once** and hands it to all its followers (one computation per presenter change per
  worker), dropping states a newer one already replaced, and the first follower to draw it leaves its
  scene messages for the others to replay (:class:`~app.services.scene_slot.SceneSlot`: the scene drawn
  once per change per worker);
* the presenter's camera and open tab go the same way; each worker tells the hub how many of its tabs
  follow, and the presenter is shown the room's count;
* a right token while a tab presents is a request the hub passes to the presenter's worker (``ask``);
  the presenter's answer goes back through the hub, which grants the asking tab's worker the role (with
  a new reconnect key) or tells it the presenter refused.
"""

from __future__ import annotations

import itertools
import logging
import secrets
import threading
from collections.abc import Callable
from typing import Any

from ..core.snapshot import Snapshot, compute
from ..core.state import LabState
from .catalog import RobotCatalog
from .classroom import (
    ASKED,
    KEPT,
    MAX_TOKEN_LENGTH,
    PRESENTER_AWAY,
    WAITING,
    Classroom,
    Member,
)
from .scene_slot import SceneSlot
from .state_codec import RobotWire, decode_state, dumps, encode_state, loads

__all__ = ["RoomChannel", "RelayedClassroom", "ANSWER_TIMEOUT"]

log = logging.getLogger(__name__)

ANSWER_TIMEOUT = 10.0
"""Seconds a worker waits for the hub's answer to a token or a reconnect key."""
NO_ANSWER = "the server's room did not answer: try again"
STOPPED = "The presenter stopped presenting: explore on your own."


class RoomChannel:
    """A worker's end of its pipe to the parent: JSON messages out, a reader thread for those in.

    Args:
        conn: The worker's end of a duplex ``multiprocessing`` pipe (anything with ``send_bytes``,
            ``recv_bytes``, ``poll``).
        on_message: Called on the reader thread with each message that is not an answer (of a burst of
            ``state`` messages read together, only the last).
    """

    def __init__(self, conn: Any, on_message: Callable[[dict[str, Any]], None] | None = None) -> None:
        self.conn = conn
        self.on_message = on_message
        self._send_lock = threading.Lock()
        self._answers: dict[int, tuple[threading.Event, Callable[[dict[str, Any]], Any], list[Any]]] = {}
        self._ids = itertools.count(1)
        self._thread = threading.Thread(target=self._read, name="room-channel", daemon=True)
        self.closed = False

    def start(self) -> None:
        self._thread.start()

    def send(self, message: dict[str, Any]) -> None:
        """Send ``message`` (dropped when the parent has gone: the worker is ending then)."""
        raw = dumps(message)
        try:
            with self._send_lock:
                self.conn.send_bytes(raw)
        except (OSError, ValueError, EOFError):
            self.closed = True

    def ask(
        self, message: dict[str, Any], then: Callable[[dict[str, Any]], Any], timeout: float = ANSWER_TIMEOUT
    ) -> tuple[Any] | None:
        """Send ``message``; ``then(answer)`` runs on the reader thread when the hub answers, before any
        later message of the hub is taken (so a presenter taken over right after is taken over after it
        presented). Returns ``(then's result,)``, or ``None`` when no answer came within ``timeout``."""
        ident = next(self._ids)
        event, box = threading.Event(), list[Any]()
        self._answers[ident] = (event, then, box)
        self.send({**message, "id": ident})
        event.wait(timeout)
        return (box[0],) if box else None

    def _read(self) -> None:
        while True:
            try:
                batch = [loads(self.conn.recv_bytes())]
                while len(batch) < 64 and self.conn.poll():
                    batch.append(loads(self.conn.recv_bytes()))
            except (OSError, EOFError, ValueError):
                self.closed = True
                for event, _, _ in list(self._answers.values()):
                    event.set()
                return
            last_state = max((i for i, m in enumerate(batch) if m.get("op") == "state"), default=-1)
            for i, message in enumerate(batch):
                if message.get("op") == "reply":
                    waiting = self._answers.pop(message.get("id"), None)
                    if waiting is not None:
                        event, then, box = waiting
                        try:
                            box.append(then(message))
                        except Exception:
                            log.exception("the room's answer")
                        finally:
                            event.set()
                elif (message.get("op") != "state" or i == last_state) and self.on_message is not None:
                    try:
                        self.on_message(message)
                    except Exception:  # one bad message never stops the room
                        log.exception("room message %r", message.get("op"))


class RelayedClassroom(Classroom):
    """This worker's tabs in a room whose presenter and token the parent's hub keeps.

    Args:
        channel: The pipe to the hub (:class:`RoomChannel`; its ``on_message`` is set here).
        catalog: The server's catalogue (robots are named by it between workers).
        address_of: As for :class:`~app.services.classroom.Classroom` (for the log of wrong tokens).
    """

    def __init__(
        self,
        channel: RoomChannel,
        catalog: RobotCatalog,
        address_of: Callable[[int], str] | None = None,
    ) -> None:
        # The worker never knows the token: the hub checks it. This one is never compared.
        super().__init__(secrets.token_urlsafe(32), address_of=address_of)
        self.channel = channel
        self.wire = RobotWire(catalog)
        self._remote = False  # a tab of another worker presents
        self._remote_last: tuple[LabState, Snapshot] | None = None
        self._others = 0  # followers in the other workers
        self._told_count = -1
        self.computed = 0  # snapshots computed for states of another worker
        self._asked = False  # this worker's presenter is asked to hand over (the hub keeps who asks)
        self.questions.send = channel.send  # its rounds (presenting) and bars (following) go to the hub
        channel.on_message = self._message

    # ---------------------------------------------------------------- the seam of Classroom
    def _someone_presents(self) -> bool:
        return self._presenter is not None or self._remote

    def _room_followers(self, here: int) -> int:
        return here + self._others

    def _is_asked(self) -> bool:
        return self._asked

    # ---------------------------------------------------------------- this worker's tabs
    def join(self, key: int, member: Member) -> None:
        super().join(key, member)
        self._mirror_remote(key)

    def follow(self, key: int) -> None:
        super().follow(key)
        self._mirror_remote(key)

    def _mirror_remote(self, key: int) -> None:
        with self._lock:
            member = self._members.get(key) if self._remote and key not in self._alone else None
            last, tab = self._remote_last, self._tab
        if member is not None:
            if last is not None:
                member.mirror(*last)
            if tab:
                member.mirror_tab(tab)

    def closed(self, key: int) -> None:
        with self._lock:
            was_presenter, was_asking = key == self._presenter, key == self._asking
            if was_presenter:
                self._asked = False
        super().closed(key)
        if was_presenter:
            self.channel.send({"op": "away", "key": key})
        elif was_asking:
            self.channel.send({"op": "withdraw", "key": key})

    def claim(self, key: int, token: str) -> str:
        with self._lock:
            if key not in self._members:
                return "this tab is not connected"
        why = self._spent(key)  # this connection's tries are counted here, as in one process
        if why:
            return why
        given = token[: MAX_TOKEN_LENGTH * 4]
        answer = self.channel.ask({"op": "claim", "key": key, "token": given}, self._claimed)
        return NO_ANSWER if answer is None else answer[0]

    def _claimed(self, answer: dict[str, Any]) -> str:
        key = int(answer["key"])
        if not answer.get("ok"):
            return self._wrong_try(key)
        if answer.get("waiting"):  # the presenter (in any worker) was asked to hand over
            with self._lock:
                self._asking = key if key in self._members else None
            if self._asking is None:
                self.channel.send({"op": "withdraw", "key": key})
                return "this tab is not connected"
            self._tell_all(personal={key: WAITING})
            return WAITING
        return self._granted(answer)

    def _granted(self, answer: dict[str, Any], handover: bool = False) -> str:
        """The hub made tab ``answer["key"]`` the presenter (its token, or the presenter handed over)."""
        key = int(answer["key"])
        with self._lock:
            self._asking = None if self._asking == key else self._asking
            if key not in self._members:  # closed meanwhile: the hub hears it as the presenter's close
                self._presenter = key
            self._resume_key, self._resume_until, self._last = str(answer.get("resume", "")), None, None
            self._remote, self._remote_last, self._tab = False, None, ""
        if key not in self._members:
            self.closed(key)
            return "this tab is not connected"
        self._present(key, None, handover)
        return ""

    def answer(self, key: int, accept: bool) -> None:
        """The presenting tab answers the request (the hub grants the asking tab the role, or refuses it);
        any other tab's answer changes nothing."""
        with self._lock:
            if key != self._presenter or not self._asked:
                return
            self._asked = False
        if not accept:  # told before the hub's answer: the asking tab's note (refused) comes after
            self._tell_all()
        self.channel.send({"op": "answer", "key": key, "accept": bool(accept)})

    def resume(self, key: int, resume_key: str) -> tuple[LabState, Snapshot] | None | bool:
        with self._lock:
            if key not in self._members:
                return False
        answer = self.channel.ask({"op": "resume", "key": key, "resume": resume_key}, self._resumed)
        return False if answer is None else answer[0]

    def _resumed(self, answer: dict[str, Any]) -> tuple[LabState, Snapshot] | None | bool:
        if not answer.get("ok"):
            return False
        key = int(answer["key"])
        last = None
        if answer.get("state") is not None:
            try:
                state = decode_state(answer["state"], self.wire)
                last = (state, compute(state))
            except Exception:
                log.exception("the presenter's last state could not be read")
        with self._lock:
            if key not in self._members:
                self._presenter = key
            self._resume_key, self._resume_until = str(answer.get("resume", "")), None
            self._remote, self._remote_last, self._tab = False, None, str(answer.get("tab", ""))
            self._asking, self._asked = None, False
        if key not in self._members:
            self.closed(key)
            return False
        self._present(key, last)
        return last

    def resign(self, key: int) -> None:
        with self._lock:
            presenting = key == self._presenter
            self._asked = self._asked and not presenting
        super().resign(key)
        if presenting:
            self.channel.send({"op": "resign", "key": key})

    def _relay(self, state: LabState, snapshot: Snapshot) -> None:
        super()._relay(state, snapshot)
        with self._lock:
            presenting = self._presenter is not None
        if presenting:
            self.channel.send({"op": "state", "state": encode_state(state, self.wire.reference(state))})

    def camera(self, key: int, position: tuple, look_at: tuple, up: tuple) -> None:
        super().camera(key, position, look_at, up)
        if key == self._presenter:
            pose = [list(map(float, position)), list(map(float, look_at)), list(map(float, up))]
            self.channel.send({"op": "camera", "key": key, "pose": pose})

    def tab(self, key: int, label: str) -> None:
        super().tab(key, label)
        if key == self._presenter:
            self.channel.send({"op": "tab", "key": key, "label": label})

    def _tell_all(self, note: str = "", personal: dict[int, str] | None = None) -> None:
        super()._tell_all(note, personal)
        with self._lock:
            count = len(self._following_keys())
            changed, self._told_count = count != self._told_count, count
        if changed:
            self.channel.send({"op": "count", "n": count})

    # ---------------------------------------------------------------- what the hub says
    def _message(self, message: dict[str, Any]) -> None:
        op = message.get("op")
        if op == "presenter":  # a tab of another worker presents now
            with self._lock:
                replaced = self._presenter
                unsubscribe = self._stop_relay()
                self._resume_key, self._resume_until, self._last = "", None, None
                self._remote, self._remote_last, self._tab = True, None, ""
                self._asking, self._asked = None, False
            if unsubscribe is not None:
                unsubscribe()
            self._tell_replaced(replaced, message.get("handover") is True)
        elif op in ("ask", "unask", "granted", "refused"):
            self._handover(op, message)
        elif op in ("question", "tally"):  # the room's question (app.services.question_desk)
            self.questions.from_hub(message)
        elif op == "state":
            self._remote_state(message.get("state"))
        elif op == "camera":
            pose = message.get("pose")
            with self._lock:
                targets = [self._members[k] for k in self._following_keys()] if self._remote else []
            for member in targets:
                member.mirror_camera(*(tuple(p) for p in pose or ()))
        elif op == "tab":
            label = str(message.get("label", ""))
            with self._lock:
                self._tab = label if self._remote else self._tab
                targets = [self._members[k] for k in self._following_keys()] if self._remote else []
            for member in targets:
                member.mirror_tab(label)
        elif op in ("away", "resigned"):
            with self._lock:
                if not self._remote:
                    return
                self._remote, self._asking = False, None
                if op == "resigned":
                    self._remote_last, self._tab = None, ""
            self._tell_all(PRESENTER_AWAY if op == "away" else STOPPED)
        elif op == "others":
            with self._lock:
                self._others = max(0, int(message.get("n", 0)))
                key = self._presenter
                presenter = self._members.get(key) if key is not None else None
            if presenter is not None and key is not None:
                presenter.role_changed(self.role(key))

    def _handover(self, op: str, message: dict[str, Any]) -> None:
        """What the hub says of a request to hand over: this worker's presenter is asked (or no longer),
        or this worker's asking tab presents now or was refused."""
        if op in ("ask", "unask"):
            with self._lock:
                self._asked, here = op == "ask" and self._presenter is not None, self._presenter
            if here is not None:
                self._tell_all(personal={here: ASKED} if op == "ask" else None)
        elif op == "granted":
            self._granted(message, handover=True)
        else:
            asker = int(message.get("key", -1))
            with self._lock:
                if self._asking != asker:
                    return
                self._asking = None
            self._tell_all(personal=None if message.get("quiet") else {asker: KEPT})

    def _remote_state(self, data: Any) -> None:
        """The presenter (in another worker) committed a state: compute its snapshot once, and every
        follower here draws it."""
        with self._lock:
            if not self._remote:
                return
        state = decode_state(data, self.wire)
        snapshot = compute(state)
        self.computed += 1
        with self._lock:
            if not self._remote:
                return
            self._remote_last = (state, snapshot)
            targets = [self._members[k] for k in self._following_keys()]
        slot = SceneSlot()  # the first follower to draw it draws the scene; the others replay it
        for member in targets:
            member.mirror(state, snapshot, (), slot)
            self.relayed += 1
