"""The classroom of a server of several worker processes, as the parent process keeps it.

``serve --workers N --presenter`` runs one :class:`RoomHub` in the supervising parent. Each worker's
:class:`~app.services.classroom_relay.RelayedClassroom` talks to it over its own pipe, in JSON messages
(``{"op": …}``); the hub answers and says which workers to tell what. It holds what must be one for the
whole server: the presenter token (each worker counts its own connections' wrong tries: tries are
limited per connection, never per address nor per room), which tab of which worker presents, its
reconnect key and grace (:data:`~app.services.classroom.RESUME_GRACE`), the last state it showed and
the tab it has open (for followers that arrive later, in any worker), and each worker's count of
followers (the presenter is shown the room's). The hub does no I/O and keeps no thread: the parent's
loop feeds it (:meth:`RoomHub.handle`, :meth:`RoomHub.started`, :meth:`RoomHub.gone`) and sends what
it returns.

Worker → hub: ``claim`` (id, key, token), ``resume`` (id, key, resume), ``state`` (the
presenter's commit, :mod:`app.services.state_codec`), ``camera``, ``tab``, ``away`` (the presenter's
tab closed), ``resign``, ``count`` (its followers), ``answer`` (key, accept: the presenter's answer
to a hand-over), ``withdraw`` (key: the asking tab closed), ``question`` (the presenter's round of the
room's question changed: :mod:`app.services.question_desk`), ``tally`` (a worker's bars of it). Hub →
worker: ``reply`` (id, …; ``waiting`` when the presenter was asked), ``presenter`` (a tab of another
worker presents now; ``handover`` when its presenter agreed), ``state``, ``camera``, ``tab``, ``away``,
``resigned``, ``others`` (followers in the other workers), ``ask`` / ``unask`` (to the presenter's
worker: a tab asks to present, or no longer), ``granted`` (key, resume: the asking tab presents) /
``refused`` (key; ``quiet`` when a newer request replaced it), ``question`` (to every other worker),
``tally`` (worker, round, counts: to the presenter's worker).

A hand-over: a right token typed while a tab presents (and is connected) is kept as ``asking``
(worker, key), one at a time, and the presenter's worker is asked; only the presenter's worker's
``answer`` for the presenter counts. Away, resign, a takeover by reconnect key and a worker gone clear
the request.
"""

from __future__ import annotations

import hmac
import secrets
import time
from collections.abc import Callable
from typing import Any

from .classroom import MAX_TOKEN_LENGTH, RESUME_GRACE

__all__ = ["RoomHub", "Outgoing"]

Outgoing = list[tuple[int, dict[str, Any]]]
"""Messages to send: (worker index, message)."""


class RoomHub:
    """The room's presenter, token and follower counts, for N workers.

    Args:
        token: The presenter token.
        clock: Monotonic clock [s].
    """

    def __init__(self, token: str, clock: Callable[[], float] = time.monotonic) -> None:
        if not token or len(token) > MAX_TOKEN_LENGTH:
            raise ValueError(f"a presenter token needs 1 to {MAX_TOKEN_LENGTH} characters")
        self._token = token.encode("utf-8")
        self._clock = clock
        self.workers: set[int] = set()
        self.presenter: tuple[int, int] | None = None  # (worker, tab key)
        self.resume_key = ""
        self.resume_until: float | None = None
        self.last: Any = None  # the presenter's last state, as sent
        self.tab = ""
        self.asking: tuple[int, int] | None = None  # (worker, tab key) that asks the presenter to hand over
        self.counts: dict[int, int] = {}
        self.question: dict[str, Any] | None = None  # the room's question, as the presenter's worker sent it
        self._told_others: dict[int, int] = {}
        self.relayed = 0

    # ---------------------------------------------------------------- workers
    def started(self, worker: int) -> Outgoing:
        """Worker ``worker`` serves (again): it learns who presents, what, and the others' followers."""
        self.workers.add(worker)
        self.counts[worker] = 0
        self._told_others.pop(worker, None)
        out: Outgoing = []
        if self.presenter is not None and self.presenter[0] != worker:
            out.append((worker, {"op": "presenter"}))
            if self.last is not None:
                out.append((worker, {"op": "state", "state": self.last}))
            if self.tab:
                out.append((worker, {"op": "tab", "label": self.tab}))
            if self.question is not None:
                out.append((worker, {"op": "question", **self.question}))
        return out + self._counts()

    def gone(self, worker: int) -> Outgoing:
        """Worker ``worker`` ended: its followers are gone; if its tab presented, it may come back (in
        any worker) with its reconnect key, as after a reload."""
        self.workers.discard(worker)
        self.counts.pop(worker, None)
        self._told_others.pop(worker, None)
        out = self._away(worker) if self.presenter is not None and self.presenter[0] == worker else []
        if self.asking is not None and self.asking[0] == worker:
            out += self._withdraw()
        return out + self._counts()

    # ---------------------------------------------------------------- messages
    def handle(self, worker: int, message: Any) -> Outgoing:
        """What worker ``worker`` said; returns what to send to whom. A malformed message is dropped."""
        if not isinstance(message, dict):
            return []
        op = message.get("op")
        try:
            if op == "claim":
                return self._claim(worker, message)
            if op == "resume":
                return self._resume(worker, message)
            if op == "count":
                self.counts[worker] = max(0, int(message.get("n", 0)))
                return self._counts()
            if op == "withdraw" and self.asking == (worker, int(message["key"])):
                return self._withdraw()
            if op == "tally":  # a worker's bars of the room's question, to the presenter's worker
                if self.presenter is None or self.presenter[0] == worker:
                    return []
                tally = {"op": "tally", "worker": worker, "round": int(message["round"])}
                return [(self.presenter[0], {**tally, "counts": message.get("counts")})]
        except (TypeError, ValueError, KeyError):
            return []
        if self.presenter is None or self.presenter[0] != worker:
            return []  # only the presenter's worker speaks for the presenter
        if op == "state":
            self.last = message.get("state")
            return self._others(worker, {"op": "state", "state": self.last})
        if op == "camera":
            return self._others(worker, {"op": "camera", "pose": message.get("pose")})
        if op == "tab":
            self.tab = str(message.get("label", ""))
            return self._others(worker, {"op": "tab", "label": self.tab})
        if op == "question":  # the room's question changed: every other worker's tabs are told
            self.question = {k: message.get(k) for k in ("round", "phase", "question")}
            return self._others(worker, {"op": "question", **self.question})
        if op == "away" and message.get("key") == self.presenter[1]:
            return self._away(worker)
        if op == "resign" and message.get("key") == self.presenter[1]:
            self.presenter, self.resume_key, self.resume_until, self.last, self.tab = None, "", None, None, ""
            self.asking = None
            return self._others(worker, {"op": "resigned"})
        if op == "answer" and message.get("key") == self.presenter[1] and self.asking is not None:
            return self._answer(message.get("accept") is True)
        return []

    def _answer(self, accept: bool) -> Outgoing:
        """The presenter answered the request: the asking tab presents, or is told it was refused."""
        assert self.asking is not None
        (worker, key), self.asking = self.asking, None
        if not accept:
            return [(worker, {"op": "refused", "key": key})]
        self.resume_key, self.resume_until, self.last, self.tab = secrets.token_urlsafe(24), None, None, ""
        self.presenter = (worker, key)
        granted = {"op": "granted", "key": key, "resume": self.resume_key}
        return [(worker, granted), *self._others(worker, {"op": "presenter", "handover": True})]

    def _withdraw(self) -> Outgoing:
        """The asking tab is gone: the presenter's worker is no longer asked."""
        self.asking = None
        return [(self.presenter[0], {"op": "unask"})] if self.presenter is not None else []

    def _claim(self, worker: int, message: dict[str, Any]) -> Outgoing:
        given = str(message.get("token", "")).encode("utf-8")[: MAX_TOKEN_LENGTH * 4]
        ok = hmac.compare_digest(given, self._token)
        key = int(message["key"])
        reply: dict[str, Any] = {"op": "reply", "id": message.get("id"), "key": key, "ok": ok}
        if not ok:  # the worker counts it against the tab's connection
            return [(worker, reply)]
        if self.presenter is not None and self.presenter != (worker, key):  # ask it to hand over
            replaced, self.asking = self.asking, (worker, key)
            out: Outgoing = [(worker, {**reply, "waiting": True}), (self.presenter[0], {"op": "ask"})]
            if replaced is not None and replaced != self.asking:
                out.append((replaced[0], {"op": "refused", "key": replaced[1], "quiet": True}))
            return out
        self.resume_key, self.resume_until, self.last, self.tab = secrets.token_urlsafe(24), None, None, ""
        return [(worker, {**reply, "resume": self.resume_key}), *self._take_over(worker, key)]

    def _resume(self, worker: int, message: dict[str, Any]) -> Outgoing:
        given = str(message.get("resume", ""))
        fresh = self.presenter is not None or (
            self.resume_until is not None and self._clock() <= self.resume_until
        )
        ok = bool(self.resume_key) and fresh and hmac.compare_digest(given.encode(), self.resume_key.encode())
        key = int(message["key"])
        reply: dict[str, Any] = {"op": "reply", "id": message.get("id"), "key": key, "ok": ok}
        if not ok:
            return [(worker, reply)]
        self.resume_until = None
        reply.update(state=self.last, tab=self.tab, resume=self.resume_key)
        return [(worker, reply), *self._take_over(worker, key)]

    def _take_over(self, worker: int, key: int) -> Outgoing:
        """Tab ``key`` of ``worker`` presents: every other worker follows it (a tab of theirs that
        presented is told it was replaced); a request to hand over is dropped."""
        self.presenter, self.asking = (worker, key), None
        return self._others(worker, {"op": "presenter"})

    def _away(self, worker: int) -> Outgoing:
        self.presenter, self.resume_until, self.asking = None, self._clock() + RESUME_GRACE, None
        return self._others(worker, {"op": "away"})

    def _others(self, worker: int, message: dict[str, Any]) -> Outgoing:
        if message["op"] == "state":
            self.relayed += 1
        return [(w, message) for w in sorted(self.workers) if w != worker]

    def _counts(self) -> Outgoing:
        """Each worker whose count of the other workers' followers changed is told it."""
        total = sum(self.counts.values())
        out: Outgoing = []
        for w in sorted(self.workers):
            others = total - self.counts.get(w, 0)
            if self._told_others.get(w) != others:
                self._told_others[w] = others
                out.append((w, {"op": "others", "n": others}))
        return out
