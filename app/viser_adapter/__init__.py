"""The one module that touches viser's private API; everything else in ``app/`` uses viser's public API.

Each function here wraps one private detail of viser (tested with the versions in
:data:`TESTED_VISER`). When an upgrade moves that detail, the function raises
:class:`ViserApiChanged` naming itself and the installed viser version, and
``tests/app/test_viser_adapter.py`` (which runs each function against a real
``viser.ViserServer``) fails with the same message.

Wrapped:
* :func:`message_class` — a protocol message class (``viser._messages``), for test clients.
* :func:`run_javascript` and :func:`set_page_title` — viser's ``RunJavascriptMessage``, sent
  to one client through ``client._websock_connection``.
* :func:`client_address` — the IP a tab connected from (the server's connection table), or behind a
  reverse proxy declared with ``--trusted-proxy`` (:func:`trusted_proxies`), from its
  ``X-Forwarded-For`` (:func:`forwarded_client`); the log of wrong presenter tokens names it;
  :func:`client_header` — a header of its websocket handshake (its ``Accept-Language``: the tab's
  first language).
* :func:`handle_uuid`, :func:`is_removed`, :func:`scene_handles`, :func:`node_props` — a handle's
  internal state (``handle._impl``) and a scene's node table (``SceneApi._handle_from_node_name``).
* :func:`install_message_limits` — what one websocket message and one tab may cost:
  replaces ``viser.infra._infra._message_consumer`` (looked up by viser's connection
  handler at call time) and the ``max_size`` viser passes to ``websockets``' ``serve``; only
  an upload's parts (512 KiB, the browser's) may exceed the message limit, and an upload
  declared over :data:`MAX_UPLOAD_BYTES` is never buffered (:func:`upload_too_large`).
* :func:`install_input_checks` — every value a tab sends, checked where it enters (:mod:`.gate`):
  replaces ``GuiApi._handle_gui_updates`` and its upload handlers (a tab's own widget, ``client.gui``,
  no longer relays its value to its own connection: viser's ``sync_cb``); :func:`check_message` is called
  by the message consumer for every message (``GuiFormDirtyMessage`` is never passed on). An upload
  with no part for ``RoomLimits.upload_stall_seconds`` is dropped, and when a tab leaves the memory it
  held is given back to the system (glibc's ``malloc_trim``: :mod:`.uploads`).
* :func:`allow_origins` and :func:`handshake_refusal` — the Host and Origin of every HTTP request and
  websocket handshake checked (:mod:`.handshake`, through the ``process_request`` viser passes to
  ``serve``, replaced by :func:`install_message_limits`).
* :func:`listen_on` — the same ``serve`` wrapper accepting on a listening socket shared by several
  worker processes (``jacobian-lab serve --workers N``) instead of binding host and port; a tab
  that connects before :func:`welcome_tabs` (the worker's Lab not built yet) is told to try again.
* :func:`capture_scene` and :func:`replay_scene` — a client's scene messages (its connection's
  ``queue_message`` and the messages' ``owner``), for a presenter's followers.
* :func:`share_owner` and :func:`install_shared_frames` — every tab's scene messages stamped with one
  ``owner`` (``SceneApi._owner_id``), and viser's ``_message_producer`` replaced by one that packs a
  :class:`SharedFrame` (a presenter's scene frame replayed to a room) once for every socket (:mod:`.frames`);
  a replayed frame is queued in a follower's buffer (``AsyncMessageBuffer``) as one entry, viser's
  culling of what it replaces done there (:mod:`.frame_refs`); that producer reads a socket's windows
  with :mod:`.windows` (viser's ``_window_loop`` paced once per window sent, the buffer read at once
  when a push wakes it).
* :func:`install_fast_prop_casts` — ``AssignablePropsBase._cast_value_recursive`` with its
  type aliases built once.
* :func:`update_props` — several props of a scene node in one ``SceneNodeUpdateMessage``
  (through ``handle._impl.props`` and the scene's ``_queue_scene_message``).
* :func:`install_icon_cache` — viser's ``_icons.svg_from_icon`` (also as imported by ``_gui_api`` and
  ``_gui_handles``), reading its icon archive once instead of once per icon and thread.
* :func:`install_loop_safe_events` — every ``AsyncMessageBuffer``'s ``message_event`` a
  :class:`~.events.LoopSafeEvent`, which the renderer thread may set without touching the event
  loop's waiters (viser's ``push`` sets an ``asyncio.Event`` from the calling thread).
* :func:`on_event_loop` — a widget callback that only queues an action, called on viser's event loop
  where the value arrives instead of in its thread pool (``GuiApi._thread_executor``, :mod:`.inline`).
* :func:`quiet_banner` — viser's console lines (``rich.print``, printed whatever ``verbose`` says) left
  out while a server starts and stops: the app prints its address once, not once per worker.
* :func:`install_panel_ledger` — a tab's GUI ids named after where each element sits (viser's
  ``_make_uuid``, found from its caller's ``self``) and a digest of what its panel shows (``_GuiHandle``'s
  ``__init__``, ``remove``, ``_queue_update`` and an input's ``value``: :mod:`.panel_ledger`), so that
  followers showing the same panel take one follower's frame (:func:`capture_frame`,
  :func:`take_gui_updates`).
* :func:`set_pose` — a scene node's position and orientation (``handle._impl.position`` / ``wxyz``,
  ``SetPositionMessage`` / ``SetOrientationMessage``) without viser's attribute hook and casts;
  :func:`set_camera` — a tab's camera pose (``CameraHandle._state``), its orientation worked out once.

A package of fourteen modules (:mod:`.core`, :mod:`.limits`, :mod:`.gate`, :mod:`.uploads`,
:mod:`.handshake`, :mod:`.props`, :mod:`.mirror`, :mod:`.frames`, :mod:`.frame_refs`, :mod:`.windows`,
:mod:`.panel_ledger`, :mod:`.icons`, :mod:`.events`, :mod:`.inline`), so each stays short; nothing outside
this package touches viser's private API.
"""

from .core import (
    TESTED_VISER,
    ViserApiChanged,
    client_address,
    client_header,
    clip,
    forwarded_client,
    handle_uuid,
    is_removed,
    message_class,
    node_props,
    quiet_banner,
    run_javascript,
    scene_handles,
    set_page_title,
    trusted_proxies,
)
from .events import LoopSafeEvent, install_loop_safe_events
from .frames import SHARED_OWNER, SharedFrame, install_shared_frames, share_owner, uninstall_shared_frames
from .gate import check_gui_value, check_message, install_input_checks, room_limits, uninstall_input_checks
from .handshake import allow_origins, handshake_refusal
from .icons import install_icon_cache
from .inline import on_event_loop
from .limits import (
    MAX_UPLOAD_BYTES,
    UPLOAD_PART_BYTES,
    MessageLimits,
    install_message_limits,
    listen_on,
    uninstall_message_limits,
    upload_too_large,
    welcome_tabs,
)
from .mirror import capture_scene, replay_scene, ridden_frame, send_ridden
from .panel_ledger import (
    capture_frame,
    gui_digest,
    install_panel_ledger,
    panel_after,
    panel_ledger_installed,
    take_gui_updates,
    uninstall_panel_ledger,
)
from .props import install_fast_prop_casts, set_camera, set_pose, update_props

__all__ = [
    "TESTED_VISER",
    "ViserApiChanged",
    "message_class",
    "run_javascript",
    "set_page_title",
    "handle_uuid",
    "is_removed",
    "scene_handles",
    "node_props",
    "install_input_checks",
    "uninstall_input_checks",
    "check_message",
    "check_gui_value",
    "room_limits",
    "allow_origins",
    "handshake_refusal",
    "MessageLimits",
    "install_message_limits",
    "listen_on",
    "welcome_tabs",
    "uninstall_message_limits",
    "upload_too_large",
    "MAX_UPLOAD_BYTES",
    "UPLOAD_PART_BYTES",
    "install_fast_prop_casts",
    "install_icon_cache",
    "install_loop_safe_events",
    "LoopSafeEvent",
    "capture_scene",
    "replay_scene",
    "SHARED_OWNER",
    "SharedFrame",
    "share_owner",
    "install_shared_frames",
    "uninstall_shared_frames",
    "update_props",
    "on_event_loop",
    "set_pose",
    "set_camera",
    "clip",
    "client_address",
    "forwarded_client",
    "trusted_proxies",
    "client_header",
    "quiet_banner",
    "install_panel_ledger",
    "uninstall_panel_ledger",
    "panel_ledger_installed",
    "gui_digest",
    "take_gui_updates",
    "panel_after",
    "capture_frame",
    "ridden_frame",
    "send_ridden",
]
