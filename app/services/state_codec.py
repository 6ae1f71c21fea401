"""A tab's :class:`~app.core.state.LabState` as JSON data, and back: what crosses between the worker
processes of one classroom (``serve --workers N`` with a presenter).

Nothing is pickled: a state becomes a JSON object of plain values, its arrays raw little-endian bytes in
base64 (only float, integer and bool arrays), its frozen parts tagged with a class name from a fixed
list (:data:`CLASSES`). The robot travels as a reference (:class:`RobotWire`): a robot of the server's
catalogue by its name and chain (every worker has the same catalogue), a robot only the presenter's tab
has (uploaded, built in the Build tab) as the text of a robot file (:func:`robots.dumps`) or of a URDF
(:func:`kinematics.urdf.to_urdf`), read back by the same parsers as any user file. A robot read back is
kept, so every state of one robot gives the same object (a follower rebuilds its scene only when the
presenter's robot changes).
"""

from __future__ import annotations

import base64
import dataclasses
import hashlib
import json
import threading
from collections import OrderedDict
from typing import Any

import numpy as np

import robots
from kinematics import Robot
from kinematics.urdf import robot_from_urdf_string, to_urdf

from ..core.build_table import robot_toml
from ..core.motion_state import IkInfo, MotionState, Trace
from ..core.options import Options
from ..core.state import LabState
from .catalog import RobotCatalog

__all__ = ["encode_state", "decode_state", "RobotWire", "CodecError", "CLASSES"]

CLASSES: dict[str, type] = {c.__name__: c for c in (LabState, Options, MotionState, Trace, IkInfo)}
"""The frozen parts of a state that may be rebuilt from data (nothing else is ever constructed)."""
_DTYPES = {"<f8", "<i8", "|b1"}
_KEEP = 16
"""Robots a wire keeps encoded or decoded (a presenter shows a handful in one lecture)."""


class CodecError(ValueError):
    """Data that is not a state this codec wrote."""


def _encode(value: Any) -> Any:
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        a = np.ascontiguousarray(value)
        a = a.astype(a.dtype.newbyteorder("<")) if a.dtype.byteorder == ">" else a
        if a.dtype.str not in _DTYPES:
            raise CodecError(f"an array of {a.dtype} cannot be sent")
        return {"$a": [a.dtype.str, list(a.shape), base64.b64encode(a.tobytes()).decode("ascii")]}
    if isinstance(value, tuple):
        return {"$t": [_encode(v) for v in value]}
    if isinstance(value, list):
        return [_encode(v) for v in value]
    if dataclasses.is_dataclass(value) and type(value).__name__ in CLASSES:
        names = [f.name for f in dataclasses.fields(value) if f.name != "robot"]
        fields = {name: _encode(getattr(value, name)) for name in names}
        return {"$c": type(value).__name__, "f": fields}
    raise CodecError(f"a {type(value).__name__} cannot be sent")


def _decode(value: Any, robot: Any) -> Any:
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    if isinstance(value, list):
        return [_decode(v, robot) for v in value]
    if not isinstance(value, dict) or len(value) not in (1, 2):
        raise CodecError("not an encoded value")
    if "$a" in value:
        dtype, shape, data = value["$a"]
        if dtype not in _DTYPES or not all(isinstance(s, int) and s >= 0 for s in shape):
            raise CodecError("not an encoded array")
        a = np.frombuffer(base64.b64decode(data), dtype=np.dtype(dtype)).reshape(shape).copy()
        a.flags.writeable = False
        return a
    if "$t" in value:
        return tuple(_decode(v, robot) for v in value["$t"])
    cls = CLASSES.get(value.get("$c", ""))
    if cls is None or not isinstance(value.get("f"), dict):
        raise CodecError("not an encoded part of a state")
    fields = {str(k): _decode(v, robot) for k, v in value["f"].items()}
    if cls is LabState:
        fields["robot"] = robot()
    try:
        return cls(**fields)
    except TypeError as exc:
        raise CodecError(f"not an encoded {cls.__name__}: {exc}") from None


def encode_state(state: LabState, robot: dict[str, Any]) -> dict[str, Any]:
    """``state`` as JSON data, its robot given as ``robot`` (:meth:`RobotWire.reference`)."""
    return {"state": _encode(state), "robot": robot}


def decode_state(data: Any, wire: RobotWire) -> LabState:
    """The state of :func:`encode_state`'s ``data`` (its robot read by ``wire``).

    Raises:
        CodecError: not a state this codec wrote; RobotDefinitionError, UrdfError: its robot file.
    """
    if not isinstance(data, dict) or not isinstance(data.get("state"), dict):
        raise CodecError("not an encoded state")
    if data["state"].get("$c") != "LabState":
        raise CodecError("not an encoded state")
    state = _decode(data["state"], lambda: wire.robot(data.get("robot")))
    assert isinstance(state, LabState)
    return state


class RobotWire:
    """How robots travel: a catalogue robot by name, any other as a robot file's or a URDF's text.

    Args:
        catalog: The server's catalogue (the same in every worker).
    """

    def __init__(self, catalog: RobotCatalog) -> None:
        self.catalog = catalog
        self._lock = threading.Lock()
        self._sent: OrderedDict[int, tuple[Robot, dict[str, Any]]] = OrderedDict()
        self._read: OrderedDict[tuple[str, str, str], Robot] = OrderedDict()

    def reference(self, state: LabState) -> dict[str, Any]:
        """What names ``state``'s robot for another worker."""
        robot = state.robot
        with self._lock:
            kept = self._sent.get(id(robot))
            if kept is not None and kept[0] is robot:
                self._sent.move_to_end(id(robot))
                return kept[1]
        if self._shared(state):
            ref: dict[str, Any] = {"kind": "shared", "name": state.robot_name, "chain": state.chain}
        else:
            stem = "".join(c if c.isalnum() or c in "-_" else "_" for c in robot.name)[:40] or "robot"
            if robot.dh is not None:
                ref = {"kind": "toml", "stem": stem, "text": robot_toml(robot, stem)}
            else:
                ref = {"kind": "urdf", "stem": stem, "text": to_urdf(robot)}
        with self._lock:
            self._sent[id(robot)] = (robot, ref)
            while len(self._sent) > _KEEP:
                self._sent.popitem(last=False)
        return ref

    def _shared(self, state: LabState) -> bool:
        if state.robot_name not in self.catalog.names():
            return False
        try:
            shared = (
                self.catalog.load_chain(state.robot_name, state.chain)
                if state.chain
                else self.catalog.load(state.robot_name)
            )
        except Exception:
            return False
        return shared is state.robot

    def robot(self, ref: Any) -> Robot:
        """The robot ``ref`` names (the same object for the same reference)."""
        if not isinstance(ref, dict) or ref.get("kind") not in ("shared", "toml", "urdf"):
            raise CodecError("not a robot reference")
        if ref["kind"] == "shared":
            name, chain = str(ref.get("name", "")), str(ref.get("chain", ""))
            return self.catalog.load_chain(name, chain) if chain else self.catalog.load(name)
        stem, text = str(ref.get("stem", "robot")), str(ref.get("text", ""))
        key = (ref["kind"], stem, hashlib.sha256(text.encode("utf-8")).hexdigest())
        with self._lock:
            robot = self._read.get(key)
            if robot is not None:
                self._read.move_to_end(key)
                return robot
        if ref["kind"] == "toml":
            robot = robots.loads(text, f"{stem}.toml").robot
        else:
            robot = robot_from_urdf_string(text.encode("utf-8"), name=stem)
        with self._lock:
            self._read[key] = robot
            while len(self._read) > _KEEP:
                self._read.popitem(last=False)
        return robot


def dumps(data: Any) -> bytes:
    """``data`` as the bytes sent on a channel."""
    return json.dumps(data, separators=(",", ":")).encode("utf-8")


def loads(raw: bytes) -> Any:
    """What :func:`dumps` sent."""
    return json.loads(raw.decode("utf-8"))
