"""viser's private API, part 14: a tab's GUI ids that follow its panel's structure, and what its panel
shows as one number, so that followers showing the same panel can be sent one frame.

viser gives every GUI element a random id (``viser._gui_api._make_uuid``), so two tabs' panels, built
by the same code from the same robot, differ in every message: a follower's slider update could never be
another follower's. Here a tab's element (``client.gui``) is named after where it sits: its container's
id and how many elements that container held when it was made (``root-3-0``; a name this tab has
given before gets a suffix, ``root-3-0_1``: viser's page may drop an element removed and made again
under the same id in one batch). Two tabs that built the same panel in the same order, after the same
rebuilds, hold the same ids; elements of the server's own GUI (``server.gui``, shown to every tab) keep
random ids. The ids are no secret, as viser's were not: a tab's messages reach only its own elements.

A tab's :class:`PanelLedger` keeps its live elements by id and an order-free digest of what each shows
(id, kind, container, value and props but the order, which viser numbers process-wide when none is
given: only its sequence shows), brought up to date lazily from the elements touched since (a prop or
value assigned, a value a browser sent, an element made or removed). Two tabs of equal
digests hold the same ids showing the same values: a frame of GUI updates drawn for one is valid for
the other (:func:`take_gui_updates` then sets the other's elements to match, as if it had drawn them).

:func:`capture_frame` collects every message queued for a tab inside a block (its GUI updates, its scene
messages, a scene frame it replayed), for followers that show what it showed before.
"""

from __future__ import annotations

import contextlib
import importlib
import sys
import threading
import uuid as _uuid
from collections.abc import Iterator, Sequence
from typing import Any

import viser

from .core import ViserApiChanged, _private

__all__ = [
    "PanelLedger",
    "install_panel_ledger",
    "panel_ledger_installed",
    "gui_digest",
    "take_gui_updates",
    "can_take_gui_updates",
    "panel_after",
    "capture_frame",
    "captured_into",
]

_LEDGER = "_jl_ledger"
_CAPTURE = "_jl_capture"
_original: dict[str, Any] = {}


def _hashed(value: Any) -> int:
    try:
        return hash(value)
    except TypeError:  # a list, a dict, an array: its text
        return hash(repr(value))


class PanelLedger:
    """One tab's GUI elements by id, and the digest of what they show."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self.live: dict[str, Any] = {}
        self._kids: dict[str, int] = {}  # container id -> how many live elements it holds
        self._issued: set[str] = set()  # every structural id made for this tab (never made twice)
        self._contrib: dict[str, int] = {}
        self._total = 0
        self._dirty: set[str] = set()

    # ------------------------------------------------------------------ ids
    def new_id(self, parent: str) -> str:
        """The id of an element made now in container ``parent``."""
        with self._lock:
            base = f"{parent}-{self._kids.get(parent, 0)}"  # letters, digits, - and _: safe in any selector
            made, k = base, 0
            while made in self._issued or made in self.live:  # an id is never given twice in a tab: the
                # browser may drop an element removed and added again under one id in one batch
                k += 1
                made = f"{base}_{k}"
            self._issued.add(made)
        return made

    # ------------------------------------------------------------------ what happens to elements
    def created(self, handle: Any) -> None:
        impl = handle._impl
        with self._lock:
            self.live[impl.uuid] = handle
            self._kids[impl.parent_container_id] = self._kids.get(impl.parent_container_id, 0) + 1
            self._dirty.add(impl.uuid)

    def removed(self, handle: Any) -> None:
        impl = handle._impl
        with self._lock:
            if self.live.pop(impl.uuid, None) is not None:
                left = self._kids.get(impl.parent_container_id, 1) - 1
                if left > 0:
                    self._kids[impl.parent_container_id] = left
                else:
                    self._kids.pop(impl.parent_container_id, None)
            self._dirty.add(impl.uuid)

    def touch(self, uuid: str) -> None:
        with self._lock:
            self._dirty.add(uuid)

    # ------------------------------------------------------------------ digest
    def digest(self) -> int:
        """An order-free digest of every live element's id, kind, container, value and props."""
        with self._lock:
            dirty, self._dirty = self._dirty, set()
            for uuid in dirty:
                self._total ^= self._contrib.pop(uuid, 0)
                handle = self.live.get(uuid)
                if handle is not None:
                    part = _contribution(handle)
                    self._contrib[uuid] = part
                    self._total ^= part
            return self._total


def _contribution(handle: Any) -> int:
    impl = handle._impl
    props = impl.props
    shown = (
        tuple((name, _hashed(value)) for name, value in vars(props).items() if name != "order")
        if props is not None
        else ()
    )  # not viser's default order: a process-wide counter, other numbers in the same sequence per tab
    return hash((impl.uuid, type(handle).__name__, impl.parent_container_id, _hashed(impl.value), shown))


def _ledger(gui: Any) -> PanelLedger:
    ledger = gui.__dict__.get(_LEDGER)
    if ledger is None:
        ledger = gui.__dict__.setdefault(_LEDGER, PanelLedger())
    return ledger


def _client_gui(owner: Any) -> Any:
    """The tab GUI (``client.gui``) a call to ``_make_uuid`` is made for, else None."""
    from viser._gui_api import GuiApi

    gui = owner if isinstance(owner, GuiApi) else getattr(getattr(owner, "_impl", None), "gui_api", None)
    if gui is None or isinstance(gui._owner, viser.ViserServer):
        return None
    return gui


def _make_id() -> str:
    """viser's ``_make_uuid`` for a tab's element: the structural id (see the module)."""
    try:
        gui = _client_gui(sys._getframe(1).f_locals.get("self"))
        if gui is not None:
            return _ledger(gui).new_id(gui._get_container_uuid())
    except Exception:  # anything unexpected: viser's own random id (that tab then draws its own)
        pass
    return str(_uuid.uuid4())


def install_panel_ledger() -> None:
    """Structural ids for tabs' GUI elements and every tab's :class:`PanelLedger` (idempotent).

    Raises:
        ViserApiChanged: ``_make_uuid``, ``_GuiHandle`` or an input's ``value`` moved.
    """
    if _original:
        return
    gui_api = _private(
        "install_panel_ledger", "viser._gui_api", lambda: importlib.import_module("viser._gui_api")
    )
    handles = _private(
        "install_panel_ledger", "viser._gui_handles", lambda: importlib.import_module("viser._gui_handles")
    )
    base, inputs = getattr(handles, "_GuiHandle", None), getattr(handles, "_GuiInputHandle", None)
    value = getattr(inputs, "value", None) if inputs is not None else None
    if (
        not callable(getattr(gui_api, "_make_uuid", None))
        or not callable(getattr(handles, "_make_uuid", None))
        or base is None
        or not all(callable(getattr(base, name, None)) for name in ("__init__", "remove", "_queue_update"))
        or not isinstance(value, property)
        or value.fset is None
        or not callable(getattr(gui_api.GuiApi, "_get_container_uuid", None))
    ):
        raise ViserApiChanged("install_panel_ledger", "_make_uuid, _GuiHandle or _GuiInputHandle.value moved")
    _original.update(
        api_uuid=vars(gui_api)["_make_uuid"], handles_uuid=vars(handles)["_make_uuid"], init=base.__init__,
        remove=base.remove, queue=base._queue_update, value=value,
    )  # fmt: skip
    init, remove, queue, setter = base.__init__, base.remove, base._queue_update, value.fset
    assert inputs is not None

    def created(self: Any, impl: Any) -> None:
        init(self, impl)
        _ledger(impl.gui_api).created(self)

    def removed(self: Any) -> None:
        was = self._impl.removed
        remove(self)
        if not was:
            _ledger(self._impl.gui_api).removed(self)

    def queued(self: Any, name: str, value: Any) -> None:
        queue(self, name, value)
        _ledger(self._impl.gui_api).touch(self._impl.uuid)

    def set_value(self: Any, new: Any) -> None:
        setter(self, new)
        _ledger(self._impl.gui_api).touch(self._impl.uuid)

    setattr(gui_api, "_make_uuid", _make_id)  # noqa: B010 (modules' functions, replaced for every caller)
    setattr(handles, "_make_uuid", _make_id)  # noqa: B010
    for name, fn in (("__init__", created), ("remove", removed), ("_queue_update", queued)):
        setattr(base, name, fn)
    setattr(inputs, "value", property(value.fget, set_value, value.fdel, value.__doc__))  # noqa: B010


def panel_ledger_installed() -> bool:
    return bool(_original)


def uninstall_panel_ledger() -> None:
    """viser's own ids and handles back (for tests)."""
    if not _original:
        return
    import viser._gui_api as gui_api
    import viser._gui_handles as handles

    setattr(gui_api, "_make_uuid", _original["api_uuid"])  # noqa: B010
    setattr(handles, "_make_uuid", _original["handles_uuid"])  # noqa: B010
    for name, key in (("__init__", "init"), ("remove", "remove"), ("_queue_update", "queue")):
        setattr(handles._GuiHandle, name, _original[key])
    setattr(handles._GuiInputHandle, "value", _original["value"])  # noqa: B010
    _original.clear()


def touched(gui: Any, uuid: str) -> None:
    """A browser sent element ``uuid`` of ``gui`` a value (the input gate calls this)."""
    if _original:
        _ledger(gui).touch(uuid)


def gui_digest(client: viser.ClientHandle) -> int:
    """The digest of what ``client``'s panel shows (:class:`PanelLedger`)."""
    return _ledger(client.gui).digest()


def can_take_gui_updates(client: viser.ClientHandle, messages: Sequence[Any]) -> bool:
    """Whether every GUI update among ``messages`` names a live element of ``client``."""
    from viser._messages import GuiUpdateMessage

    live = _ledger(client.gui).live
    return all(
        m.uuid in live and not live[m.uuid]._impl.removed for m in messages if type(m) is GuiUpdateMessage
    )


def panel_after(client: viser.ClientHandle, messages: Sequence[Any]) -> tuple[int, dict[str, int]]:
    """``client``'s digest and the digest parts of the elements the GUI updates among ``messages`` name:
    what a tab of the same digest before holds once it has taken them (:func:`take_gui_updates`)."""
    from viser._messages import GuiUpdateMessage

    ledger = _ledger(client.gui)
    total = ledger.digest()
    with ledger._lock:
        parts = {m.uuid: ledger._contrib.get(m.uuid, 0) for m in messages if type(m) is GuiUpdateMessage}
    return total, parts


def take_gui_updates(
    client: viser.ClientHandle, messages: Sequence[Any], after: tuple[int, dict[str, int]] | None = None
) -> bool:
    """Set ``client``'s elements to what the GUI updates among ``messages`` (drawn for a tab of the same
    digest) set there, without sending anything; False (nothing set) when an update names an element
    ``client`` does not have. ``after``: the drawing tab's :func:`panel_after` (then this tab's digest is
    that one's at once, without hashing its elements again)."""
    from viser._messages import GuiUpdateMessage

    if not can_take_gui_updates(client, messages):
        return False
    ledger = _ledger(client.gui)
    live = ledger.live
    updated = []
    for message in (m for m in messages if type(m) is GuiUpdateMessage):
        impl = live[message.uuid]._impl
        for name, value in message.updates.items():
            if name == "value":
                impl.value = value
            else:
                setattr(impl.props, name, value)
        updated.append(message.uuid)
    with ledger._lock:
        if after is not None and all(uuid in after[1] for uuid in updated):
            # Same elements, same values as the drawing tab's: the same parts. A part a browser changed
            # meanwhile is still marked and is worked out again at the next digest.
            ledger._contrib.update((uuid, after[1][uuid]) for uuid in updated)
            ledger._total = after[0]
        else:
            ledger._dirty.update(updated)
    return True


@contextlib.contextmanager
def capture_frame(client: viser.ClientHandle) -> Iterator[list[Any]]:
    """Collect (and still send) every message queued for ``client`` inside the block, with the messages
    of a scene frame it replays (:func:`~.mirror.replay_scene`), in order."""
    conn = _private("capture_frame", "ClientHandle._websock_connection", lambda: client._websock_connection)
    captured: list[Any] = []
    before = conn.__dict__.get("queue_message")
    original = conn.queue_message

    def queue(message: Any) -> None:
        captured.append(message)
        original(message)

    conn.__dict__["queue_message"] = queue  # an instance attribute: shadows the method for this connection
    conn.__dict__[_CAPTURE] = captured
    try:
        yield captured
    finally:
        conn.__dict__.pop(_CAPTURE, None)
        if before is None:
            conn.__dict__.pop("queue_message", None)
        else:
            conn.__dict__["queue_message"] = before


def captured_into(conn: Any) -> list[Any] | None:
    """The list :func:`capture_frame` collects ``conn``'s messages into, if a capture is running."""
    return conn.__dict__.get(_CAPTURE)
