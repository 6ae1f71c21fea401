"""viser's private API, part 3: cheaper prop assignment (see the package)."""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

import numpy as np
import viser

from .core import ViserApiChanged, _private, message_class

__all__ = ["install_fast_prop_casts", "update_props", "set_pose"]


# --------------------------------------------------------------------------- faster prop assignment
_FAST_CAST_INSTALLED = False


def install_fast_prop_casts() -> None:
    """Make every handle prop and pose assignment cheaper, with the same result.

    viser 1.1's ``AssignablePropsBase._cast_value_recursive`` builds four ``numpy.typing``
    aliases (``npt.NDArray[np.float32]``, ...) on every assignment to compare the prop's type
    hint with them: about a third of the cost of moving a scene node. This builds them once.
    Idempotent.

    Raises:
        ViserApiChanged: the method moved.
    """
    global _FAST_CAST_INSTALLED
    if _FAST_CAST_INSTALLED:
        return
    import numpy as np
    import numpy.typing as npt

    props_api = _private(
        "install_fast_prop_casts",
        "viser._assignable_props_api.AssignablePropsBase._cast_value_recursive",
        lambda: __import__("viser._assignable_props_api", fromlist=["AssignablePropsBase"]),
    )
    base = props_api.AssignablePropsBase
    if not callable(getattr(base, "_cast_value_recursive", None)):
        raise ViserApiChanged("install_fast_prop_casts", "AssignablePropsBase._cast_value_recursive is gone")
    f16, f32 = npt.NDArray[np.float16], npt.NDArray[np.float32]
    f64, u8 = npt.NDArray[np.float64], npt.NDArray[np.uint8]
    colors_to_uint8 = props_api.colors_to_uint8

    def cast(self: Any, hint: Any, value: Any, prop_name: str) -> Any:
        if hint == f32:
            return np.asarray(value).astype(np.float32)
        if hint == f64:
            return np.asarray(value).astype(np.float64)
        if hint == f16:
            return np.asarray(value).astype(np.float16)
        if hint == u8 and "color" in prop_name:
            return colors_to_uint8(value)
        if isinstance(value, np.ndarray):
            return value
        if (
            isinstance(value, tuple)
            and getattr(hint, "__origin__", None) is tuple
            and len(getattr(hint, "__args__", ())) == 2
            and hint.__args__[1] is ...
        ):
            element = hint.__args__[0]
            return tuple(cast(self, element, item, prop_name) for item in value)
        return value

    base._jl_original_cast = base._cast_value_recursive
    base._cast_value_recursive = cast
    _install_unchanged_skip(base)
    _install_fast_pose_setter()
    _FAST_CAST_INSTALLED = True


_PLAIN = (str, bool, int, float)


def _install_unchanged_skip(base: Any) -> None:
    """``AssignablePropsBase.__setattr__`` returning at once when a plain prop (a string, bool or number,
    not a property such as an input's ``value``) is given the value it holds, of the same type: viser
    skips it too, after casting it. A follower's panel draw assigns ~15 props a move, ~10 unchanged."""
    original = base.__setattr__

    def setattr_unless_unchanged(self: Any, name: str, value: Any) -> None:
        if type(value) in _PLAIN and name in self._prop_hints:
            impl = self.__dict__.get("_impl")
            if (
                impl is not None
                and not impl.removed
                and not isinstance(getattr(type(self), name, None), property)
            ):
                current = getattr(impl.props, name, None)
                if type(current) is type(value) and current == value:
                    return
        original(self, name, value)

    base.__setattr__ = setattr_unless_unchanged


def _install_fast_pose_setter() -> None:
    """``viser._scene_handles._set_pose_vector`` (every ``position`` / ``wxyz`` assignment) with the
    same tolerance as its ``np.allclose`` (rtol 1e-5, atol 1e-8) computed on 3 or 4 floats in plain
    Python: ``np.allclose`` costs tens of microseconds for a 3-vector."""
    handles = _private(
        "install_fast_prop_casts",
        "viser._scene_handles._set_pose_vector",
        lambda: __import__("viser._scene_handles", fromlist=["_set_pose_vector"]),
    )
    scene_api = __import__("viser._scene_api", fromlist=["cast_vector"])
    original = getattr(handles, "_set_pose_vector", None)
    if not callable(original) or not callable(getattr(scene_api, "cast_vector", None)):
        raise ViserApiChanged("install_fast_prop_casts", "_set_pose_vector or cast_vector is gone")
    cast_vector = scene_api.cast_vector

    def set_pose_vector(current: Any, value: Any, length: int, queue: Any, make_message: Any) -> None:
        value_cast = cast_vector(value, length)
        old = current.tolist()
        if len(old) == len(value_cast) and all(
            abs(a - b) <= 1e-8 + 1e-5 * abs(b) for a, b in zip(value_cast, old, strict=True)
        ):
            return
        current[:] = value_cast
        queue(make_message(value_cast))

    setattr(handles, "_jl_original_set_pose_vector", original)  # noqa: B010 (a module, not a class)
    setattr(handles, "_set_pose_vector", set_pose_vector)  # noqa: B010


# --------------------------------------------------------------------------- several props, one message
def update_props(handle: Any, **updates: Any) -> bool:
    """Assign several props of the scene node ``handle`` at once, sending ONE update message.

    viser sends one ``SceneNodeUpdateMessage`` per assigned prop (three for a batched mesh's
    positions, orientations and scales), each cast, compared, copied and serialized on its own.
    Here the changed props travel together: one message of ``{name: value}``, which the browser
    merges into the node's props exactly as it merges one. An array is stored at the dtype of the
    prop's current value and sent only when it differs; a scalar only when it differs.

    Arrays and plain scalars take this path; anything else (a prop not set yet, a tuple that viser
    converts) is assigned through viser's own setter.

    Returns:
        Whether anything was sent.

    Raises:
        RuntimeError: the node was removed.
        ViserApiChanged: the handle's internals or the message class moved.
    """
    import numpy as np

    try:
        impl = handle._impl
        removed, props, queue = impl.removed, impl.props, impl.api._queue_scene_message
    except AttributeError as exc:
        raise ViserApiChanged(
            "update_props", f"handle._impl.removed / props / api._queue_scene_message ({exc})"
        ) from exc
    if removed:
        raise RuntimeError(f"update_props: {type(handle).__name__} {impl.name!r} was removed")
    changed: dict[str, Any] = {}
    for name, value in updates.items():
        current = getattr(props, name)  # AttributeError: the node has no such prop
        if isinstance(current, np.ndarray):
            new = np.asarray(value, dtype=current.dtype)
            if new.shape == current.shape:
                if np.array_equal(current, new):
                    continue
                current[...] = new
            else:
                setattr(props, name, new.copy())
            # The wire gets its own copy: the stored array is updated in place next time,
            # maybe while the event loop is still serializing this message.
            changed[name] = new.copy()
        elif _floats(value) and _floats(current) and len(value) == len(current):  # e.g. a scale (x, y, z)
            if value == current:
                continue
            setattr(props, name, value)
            changed[name] = value
        elif isinstance(value, np.ndarray) or isinstance(current, (list, tuple, dict)):
            setattr(handle, name, value)  # first array for an unset prop, or a sequence: viser's own path
        else:
            if current == value:
                continue
            setattr(props, name, value)
            changed[name] = value
    if not changed:
        return False
    queue(_update_message()(impl.name, changed))
    for name in changed:
        handle._on_prop_assigned(name)
    return True


_UPDATE_MESSAGE: list[type] = []


def _update_message() -> type:
    if not _UPDATE_MESSAGE:
        from .core import message_class

        _UPDATE_MESSAGE.append(message_class("SceneNodeUpdateMessage"))
    return _UPDATE_MESSAGE[0]


def _floats(value: Any) -> bool:
    """Whether ``value`` is a tuple of plain floats (a prop viser stores and sends as it is)."""
    return type(value) is tuple and all(type(x) is float for x in value)


# --------------------------------------------------------------------------- node poses
def set_pose(
    handle: Any,
    position: Sequence[float] | None = None,
    wxyz: Sequence[float] | None = None,
) -> None:
    """Move the scene node ``handle``: what assigning ``handle.position`` / ``handle.wxyz`` does, with
    the same tolerance (rtol 1e-5, atol 1e-8: nothing is sent for an unchanged pose), without viser's
    attribute hook, property and casts (a tenth of a redraw for a tab's joint labels).

    Args:
        position, wxyz: Plain floats (the caller makes them finite); ``None`` leaves that part.

    Raises:
        RuntimeError: the node was removed.
        ViserApiChanged: the handle's internals or the message classes moved.
    """
    try:
        impl = handle._impl
        removed, queue = impl.removed, impl.api._queue_scene_message
    except AttributeError as exc:
        raise ViserApiChanged("set_pose", f"handle._impl.removed / api._queue_scene_message ({exc})") from exc
    if removed:
        raise RuntimeError(f"set_pose: {type(handle).__name__} {impl.name!r} was removed")
    for value, current, make in (
        (position, impl.position, _pose_message("SetPositionMessage")),
        (wxyz, impl.wxyz, _pose_message("SetOrientationMessage")),
    ):
        if value is None:
            continue
        old = current.tolist()
        if len(old) != len(value):
            raise ValueError(f"set_pose: expected {len(old)} numbers, got {len(value)}")
        if all(abs(a - b) <= 1e-8 + 1e-5 * abs(b) for a, b in zip(value, old, strict=True)):
            continue
        current[:] = value
        queue(make(impl.name, tuple(value)))


_POSE_MESSAGES: dict[str, type] = {}


def _pose_message(name: str) -> type:
    if name not in _POSE_MESSAGES:
        from .core import message_class

        _POSE_MESSAGES[name] = message_class(name)
    return _POSE_MESSAGES[name]


# --------------------------------------------------------------------------- a tab's camera
def set_camera(client: viser.ClientHandle, position: Any, look_at: Any, up: Any) -> None:
    """Point ``client``'s camera: what assigning its ``up_direction``, ``position`` and then ``look_at``
    sends (a message for each that changed, in that order) and keeps (the handle's
    pose and orientation), with the orientation worked out once instead of four times (a follower's share
    of a presenter's orbit: viser's setters each rebuild the orientation, and the position's moves
    ``look_at`` first).

    Raises:
        ValueError: a value is not finite, or ``look_at`` is ``position``.
        ViserApiChanged: the camera's state or its message classes moved.
    """
    cam = client.camera
    try:
        state, update = cam._state, cam._update_wxyz
        queue = state.client._websock_connection.queue_message
    except AttributeError as exc:
        raise ViserApiChanged("set_camera", f"CameraHandle._state / _update_wxyz ({exc})") from exc
    new = [np.asarray(v, np.float64).reshape(3) for v in (up, position, look_at)]
    if not all(np.isfinite(v).all() for v in new):
        raise ValueError(f"a camera pose must be finite: {[v.tolist() for v in new]}")
    old = (state.up_direction, state.position, state.look_at)
    changed = [not np.allclose(o, n) for o, n in zip(old, new, strict=True)]
    if not any(changed):
        return
    state.up_direction, state.position, state.look_at = new
    try:
        update()
    except Exception:
        state.up_direction, state.position, state.look_at = old
        raise
    state.update_timestamp = time.time()
    for name, value, sent in zip(_CAMERA_MESSAGES, new, changed, strict=True):
        if sent:
            queue(message_class(name)(tuple(float(x) for x in value)))


_CAMERA_MESSAGES = ("SetCameraUpDirectionMessage", "SetCameraPositionMessage", "SetCameraLookAtMessage")
