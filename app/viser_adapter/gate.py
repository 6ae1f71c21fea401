"""viser's private API, part 6: every value a tab sends, checked where it enters (see the package).

viser hands a browser's values to the app as they come: a dropdown's value is not checked against its
options, a slider's against its range, a vector's length against its own, an upload's bytes against
what it declared; a client may also set any other prop of a widget (``min``, ``options``, ``label``)
and make the server relay a form's "dirty" flag into the buffer every later tab replays. Here, in one
place, each message is checked before viser sees it:

* :func:`check_message` — messages that name no widget (the camera, the gizmo, pointer events, upload
  parts; ``GuiFormDirtyMessage`` and share-link requests are never passed on), called by the message
  consumer of :mod:`.limits` for every message of every tab;
* :func:`check_gui_value` — a ``GuiUpdateMessage`` against the widget it names (only ``value``, of
  the widget's type, in its options or range, finite, of its length; never for a disabled widget
  or an upload button), installed over ``GuiApi._handle_gui_updates`` by :func:`install_input_checks`;
* uploads against the server's :class:`~app.services.ratelimit.RoomLimits`: only to an upload
  button, declared parts consistent with the declared size, bytes received never over it, in flight
  at most so many per tab and so many bytes per server, and dropped after so long without a part;
  the memory of a tab that left, and of a dropped upload, is given back (:mod:`.uploads`).

A refused message changes nothing; the tab is told in words (a notice naming the widget and what was
wrong) and the refusal is logged in one bounded line and kept in ``RoomLimits.refusals``.
"""

from __future__ import annotations

import logging
import math
from typing import Any

from ..services.ratelimit import RoomLimits
from .core import ViserApiChanged, _private, clip
from .inline import run_marked_inline
from .panel_ledger import touched
from .uploads import give_back_memory, watch_upload

__all__ = ["install_input_checks", "check_message", "check_gui_value", "room_limits", "MAX_TEXT"]

log = logging.getLogger("app.viser_adapter")

MAX_TEXT = 4096
"""Longest text a text input accepts [characters]."""
MAX_COORDINATE = 1e4
"""Largest coordinate of a camera, gizmo or pointer a tab may send [m] (a lab is a few metres)."""
MAX_PIXELS = 16384
"""Largest canvas side a tab may report [px]."""
UPLOAD_STALLED_TITLE = "Upload dropped"
UPLOAD_STALLED = (
    "The upload “{name}” stopped: no part of it arrived for {seconds} s, so it was dropped. "
    "Send the file again."
)
_NEVER_PASSED = {
    "GuiFormDirtyMessage": "a form's dirty flag (viser would keep it for every later tab)",
    "ShareUrlRequest": "a share-link request (this server shares nothing)",
    "ShareUrlDisconnect": "a share-link request (this server shares nothing)",
}

_room: RoomLimits | None = None
_original: dict[str, Any] = {}


def room_limits() -> RoomLimits | None:
    """The limits :func:`install_input_checks` enforces (``None`` before it was called)."""
    return _room


# --------------------------------------------------------------------------- pure checks
def _real(x: object) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _vector(x: object, n: int, bound: float = math.inf) -> bool:
    return isinstance(x, (list, tuple)) and len(x) == n and all(_real(v) and abs(v) <= bound for v in x)


def _unit(x: Any) -> bool:
    return _vector(x, 4, 1e3) and 1e-6 < math.fsum(v * v for v in x) ** 0.5


def check_message(message: Any) -> str:
    """Why ``message`` (any client → server message) is refused, or ``""`` to pass it on.

    Messages naming a widget are checked later, against that widget (:func:`check_gui_value`).
    """
    kind = type(message).__name__
    if kind in _NEVER_PASSED:
        return _NEVER_PASSED[kind] + " is not relayed"
    m = message
    if kind == "ViewerCameraMessage":
        ok = _unit(m.wxyz) and all(_vector(v, 3, MAX_COORDINATE) for v in (m.position, m.look_at))
        ok = ok and _vector(m.up_direction, 3, 1e3) and any(v != 0 for v in m.up_direction)
        ok = ok and _real(m.fov) and 0 < m.fov < math.pi and _real(m.near) and _real(m.far)
        ok = ok and 0 < m.near < m.far
        sides = (m.image_width, m.image_height)
        if not (ok and all(_real(s) and 1 <= s <= MAX_PIXELS for s in sides)):
            return (
                "a camera with a non-finite or out-of-range pose, field of view, clipping planes or "
                f"canvas size (each side 1 to {MAX_PIXELS} px)"
            )
    elif kind == "TransformControlsUpdateMessage":
        if not (_unit(m.wxyz) and _vector(m.position, 3, MAX_COORDINATE)):
            return f"a gizmo pose that is not finite, or farther than {MAX_COORDINATE:g} m"
    elif kind in ("ScenePointerMessage", "SceneNodeClickMessage"):
        rays = [v for v in (m.ray_origin, m.ray_direction) if v is not None]
        if not all(_vector(v, 3, MAX_COORDINATE) for v in rays):
            return "a pointer ray that is not finite"
    elif kind == "FileTransferPart":
        content = m.content
        if not isinstance(content, bytes) or not isinstance(m.part_index, int):
            return "an upload part that is not bytes"
    elif kind == "FileTransferStartUpload":
        numbers = (m.size_bytes, m.part_count)
        if not all(isinstance(v, int) and not isinstance(v, bool) and v >= 0 for v in numbers):
            return "an upload whose declared size or part count is not a count"
    return ""


def check_gui_value(handle: Any, updates: object) -> str:
    """Why a ``GuiUpdateMessage`` with ``updates`` for the widget ``handle`` is refused, or ``""``."""
    from viser import _gui_handles as gh

    impl = handle._impl
    if not isinstance(updates, dict) or set(updates) != {"value"}:
        keys = sorted(map(str, updates)) if isinstance(updates, dict) else type(updates).__name__
        return f"only its value can be set by a tab (got {clip(keys, 80)})"
    if getattr(impl.props, "disabled", False):
        return "it is disabled"
    value, current, props = updates["value"], impl.value, impl.props
    if isinstance(handle, (gh.GuiUploadButtonHandle, gh.GuiProgressBarHandle)):
        return "a file or progress is not set by a value"
    if isinstance(handle, (gh.GuiDropdownHandle, gh.GuiButtonGroupHandle)):
        options = tuple(props.options)
        if not (isinstance(value, str) and value in options):
            return f"{clip(repr(value), 80)} is not one of its {len(options)} options"
        return ""
    if isinstance(handle, (gh.GuiButtonHandle, gh.GuiCheckboxHandle)):
        return "" if isinstance(value, bool) else f"{clip(repr(value), 60)} is not true or false"
    if isinstance(current, str):
        if not isinstance(value, str) or len(value) > MAX_TEXT:
            return f"expected a text of at most {MAX_TEXT} characters"
        return ""
    if isinstance(current, tuple):
        return _check_vector(value, current, props)
    if _real(current):
        if not _real(value):
            if isinstance(value, float):  # NaN or ±∞: named in words, never echoed as "nan" on the page
                return "not a finite number (not a number, or unbounded)"
            return f"{clip(repr(value), 60)} is not a finite number"
        lo, hi = getattr(props, "min", None), getattr(props, "max", None)
        if (lo is not None and value < lo) or (hi is not None and value > hi):
            return f"{value!r} is outside its range {_range(lo, hi)}"
        return ""
    return f"a {type(handle).__name__} does not take values from a tab"


def _check_vector(value: Any, current: tuple, props: Any) -> str:
    n = len(current)
    if not _vector(value, n):
        return f"expected {n} finite numbers, got {clip(repr(value), 60)}"
    lo, hi = getattr(props, "min", None), getattr(props, "max", None)
    for i, v in enumerate(value):
        low = lo[i] if isinstance(lo, (tuple, list)) else lo
        high = hi[i] if isinstance(hi, (tuple, list)) else hi
        if (low is not None and v < low) or (high is not None and v > high):
            return f"number {i + 1} ({v!r}) is outside its range {_range(low, high)}"
    if isinstance(current[0], int) and not all(float(v).is_integer() for v in value):
        return "expected whole numbers"
    return ""


def _range(lo: object, hi: object) -> str:
    return f"[{'−∞' if lo is None else f'{lo:g}'}, {'∞' if hi is None else f'{hi:g}'}]"


def _label(handle: Any) -> str:
    """The widget's label, or its buttons' labels, or its kind."""
    props = handle._impl.props
    options = getattr(props, "options", None)
    label = getattr(props, "label", None) or (" / ".join(map(str, options)) if options else None)
    return clip(label or type(handle).__name__, 60)


# --------------------------------------------------------------------------- installing
def install_input_checks(room: RoomLimits | None = None) -> RoomLimits:
    """Check every widget value and upload of every tab of every viser server created from now on.

    Replaces ``GuiApi._handle_gui_updates``, ``_handle_file_transfer_start``,
    ``_handle_file_transfer_part``, ``_finish_file_upload`` and ``_drop_uploads_from_client`` (each
    viser GUI registers its handlers when created: call this before creating the server). Calling
    again replaces the limits.

    Returns:
        The limits in force (``room``, or fresh defaults).
    """
    global _room
    _room = room if room is not None else RoomLimits()
    gui_api = _private("install_input_checks", "viser._gui_api.GuiApi", _gui_api_class)
    names = (
        "_handle_gui_updates",
        "_handle_file_transfer_start",
        "_handle_file_transfer_part",
        "_finish_file_upload",
        "_drop_uploads_from_client",
        "_resolve_client",
    )
    missing = [n for n in names if not callable(getattr(gui_api, n, None))]
    if missing:
        raise ViserApiChanged("install_input_checks", f"GuiApi has no {', '.join(missing)}")
    if not _original:
        for name in names[:5]:
            _original[name] = getattr(gui_api, name)
        gui_api._handle_gui_updates = _gui_updates
        gui_api._handle_file_transfer_start = _transfer_start
        gui_api._handle_file_transfer_part = _transfer_part
        gui_api._finish_file_upload = _finish_upload
        gui_api._drop_uploads_from_client = _drop_uploads
    return _room


def uninstall_input_checks() -> None:
    """Give viser back its own handlers (for tests)."""
    global _room
    gui_api = _gui_api_class()
    for name, fn in list(_original.items()):
        setattr(gui_api, name, fn)
        del _original[name]
    _room = None


def _gui_api_class() -> Any:
    from viser._gui_api import GuiApi

    return GuiApi


def refuse(api: Any, client_id: int, what: str, why: str) -> None:
    """Record and log a refused message and tell its tab (``api``: the viser GUI it was sent to)."""
    text = f"{what}: {why}. Nothing was changed."
    log.warning("refused a message of client %s: %s", client_id, clip(text, 300))
    tell(api, client_id, text)


def tell(api: Any, client_id: int, text: str, title: str = "Refused") -> None:
    """Record ``text`` (a refusal, or an upload dropped) with the refusals and show it to the tab in a
    notice titled ``title``, unless the tab was shown enough of them for now."""
    room = _room
    if room is None or not room.refuse(client_id, text):
        return  # this tab was told enough for now (its notices are rate-limited)
    client = api._resolve_client(client_id)
    if client is not None:
        try:
            client.add_notification(title, text, color="red", auto_close_seconds=8.0)
        except Exception:  # the tab has gone
            pass


async def _gui_updates(self: Any, client_id: int, message: Any) -> None:
    handle = self._gui_input_handle_from_uuid.get(message.uuid, None)
    if handle is None or handle._impl.removed:
        return
    why = check_gui_value(handle, message.updates)
    if why:
        refuse(self, client_id, f"“{_label(handle)}”", why)
        return
    state = handle._impl
    run_marked_inline(self)  # a callback that only queues an action runs here, not in the pool
    if state.sync_cb is not None and _client_owned(self):
        state.sync_cb = None  # see _client_owned
    touched(self, message.uuid)  # what the tab's panel shows changes (its digest: .panel_ledger)
    await _original["_handle_gui_updates"](self, client_id, message)
    touched(self, message.uuid)


def _client_owned(api: Any) -> bool:
    """Whether the viser GUI ``api`` belongs to one tab (``client.gui``), not to the whole server.

    viser relays every value a tab sends to "the other clients" of the widget's connection
    (``sync_cb``, a ``GuiUpdateMessage`` with ``excluded_self_client``): for a tab's own widget that
    connection is the tab's alone, so the message is queued, wakes the event loop, and is dropped
    unsent (one more buffered message and one more empty window per change). Such widgets get no
    relay; a widget of the whole server keeps it.
    """
    from viser import ClientHandle

    return isinstance(getattr(api, "_owner", None), ClientHandle)


def _transfer_start(self: Any, client_id: int, message: Any) -> None:
    from viser import _gui_handles as gh

    handle = self._gui_input_handle_from_uuid.get(message.source_component_uuid, None)
    if handle is None:
        return  # another GUI of this server owns it, or nothing does
    if not isinstance(handle, gh.GuiUploadButtonHandle):
        refuse(self, client_id, f"An upload to “{_label(handle)}”", "it is not an upload button")
        return
    room = _room
    size, parts = message.size_bytes, message.part_count
    why = room.start_upload(client_id, message.transfer_uuid, size, parts) if room is not None else ""
    if why:
        refuse(self, client_id, f"The upload “{clip(message.filename, 60)}”", why)
        return
    _original["_handle_file_transfer_start"](self, client_id, message)
    if room is not None and message.transfer_uuid in self._current_file_upload_states:
        watch_upload(self, message.transfer_uuid, room.upload_stall_seconds, room.upload_idle, _drop_stalled)


def _drop_stalled(self: Any, transfer: str) -> None:
    """An upload had no part for ``RoomLimits.upload_stall_seconds``: its parts go, its tab is told."""
    state = self._current_file_upload_states.pop(transfer, None)
    room = _room
    if room is not None:
        room.end_upload(transfer)
    if state is not None:
        seconds = f"{room.upload_stall_seconds:g}" if room is not None else "?"
        text = UPLOAD_STALLED.format(name=clip(state["filename"], 60), seconds=seconds)
        log.warning("dropped an upload of client %s: %s", state["client_id"], text)
        tell(self, state["client_id"], text, UPLOAD_STALLED_TITLE)
        give_back_memory()


def _transfer_part(self: Any, client_id: int, message: Any) -> None:
    state = self._current_file_upload_states.get(message.transfer_uuid)
    if state is None:
        return
    room = _room
    why = room.receive_part(message.transfer_uuid, len(message.content)) if room else ""
    if why or state.get("client_id") != client_id:
        self._current_file_upload_states.pop(message.transfer_uuid, None)
        if room is not None:
            room.end_upload(message.transfer_uuid)
        refuse(self, client_id, f"The upload “{clip(state['filename'], 60)}”", why or "not this tab's")
        give_back_memory()
        return
    _original["_handle_file_transfer_part"](self, client_id, message)


def _finish_upload(self: Any, client_id: int, transfer_uuid: str, source: str | None) -> None:
    if _room is not None:
        _room.end_upload(transfer_uuid)
    _original["_finish_file_upload"](self, client_id, transfer_uuid, source)


def _drop_uploads(self: Any, client_id: int) -> None:
    """The tab left (viser's disconnect handler): its uploads end, and what it held goes back to the
    system once freed (viser's page, the tab's widgets, its unfinished uploads' parts)."""
    if _room is not None:
        _room.end_tab(client_id)
    _original["_drop_uploads_from_client"](self, client_id)
    give_back_memory()
