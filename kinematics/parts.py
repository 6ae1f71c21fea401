"""The parts a :class:`~kinematics.model.Robot` is made of: joints, axes, DH rows, named configurations.

Each part checks itself on construction, so every loader (DH table, robot file, URDF, a chain
built by hand) gets the same checks and the same messages: a
:class:`~kinematics.errors.RobotDefinitionError` naming the joint, axis or configuration and the
attribute, and saying what was expected.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Literal, TypeVar

import numpy as np

from .conventions import TASKS, FloatArray, Task
from .errors import RobotDefinitionError
from .transforms import check_rigid_transform
from .validation import (
    MAX_ANGLE,
    MAX_LENGTH,
    MAX_MULTIPLIER,
    bounded_number,
    frozen_array,
    is_number,
    joint_limits,
    show,
)

__all__ = [
    "Joint",
    "Axis",
    "DHRow",
    "NamedConfiguration",
    "JointType",
    "Convention",
    "Task",
    "JOINT_TYPES",
    "CONVENTIONS",
    "TASKS",
    "check_choice",
    "param_names",
    "value_bound",
    "FrozenNames",
]

_S = TypeVar("_S", bound=str)
_V = TypeVar("_V")
JointType = Literal["revolute", "prismatic"]
Convention = Literal["standard", "modified"]
JOINT_TYPES: tuple[JointType, ...] = ("revolute", "prismatic")
CONVENTIONS: tuple[Convention, ...] = ("standard", "modified")


def check_choice(value: object, allowed: Sequence[_S], where: str) -> _S:
    """``value`` if it is one of ``allowed``, else a RobotDefinitionError listing them (and the
    closest one, for a typo)."""
    for choice in allowed:
        if isinstance(value, str) and value == choice:
            return choice
    hint = difflib.get_close_matches(value, allowed, n=1) if isinstance(value, str) else []
    maybe = f" (did you mean {hint[0]!r}?)" if hint else ""
    raise RobotDefinitionError(
        f"{where}: expected one of {', '.join(map(repr, allowed))}, got {show(value)}{maybe}"
    )


def _text(value: object, where: str) -> str:
    if not isinstance(value, str):
        raise RobotDefinitionError(f"{where}: expected a string, got {show(value)}")
    return value


def value_bound(kind: str) -> tuple[float, str]:
    """Largest |value| and its unit for an axis or joint of ``kind``."""
    return (MAX_ANGLE, "rad") if kind == "revolute" else (MAX_LENGTH, "m")


@dataclass(frozen=True)
class Joint:
    """An actuated joint: one entry of ``q``.

    Attributes:
        name: Display name, unique within the robot (not empty).
        kind: ``"revolute"`` (q in [rad]) or ``"prismatic"`` (q in [m]).
        qlim: (lower, upper) limits, finite and lower < upper, or ``None`` if unlimited.
            Limits bound sliders and sampling only, never the maths. On construction a side
            of magnitude ≥ :data:`~kinematics.validation.UNLIMITED` (a URDF's ``±1e16``,
            ``±inf``, ``1e308``) means "unlimited", and a joint unlimited on either side is
            stored as unlimited (``None``); NaN is an error (see
            :func:`~kinematics.validation.joint_limits`).
    """

    name: str
    kind: JointType
    qlim: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        name = _text(self.name, "joint name")
        if not name:
            raise RobotDefinitionError("joint name: expected a non-empty string")
        check_choice(self.kind, JOINT_TYPES, f"joint {name!r}, kind")
        object.__setattr__(self, "qlim", joint_limits(self.qlim, f"joint {name!r}, qlim"))


@dataclass(frozen=True, eq=False)
class Axis:
    """One moving axis of the chain, always about/along its joint frame's z.

    Attributes:
        name: Name of the joint this axis comes from (URDF joint name, DH row name).
        kind: ``"revolute"`` or ``"prismatic"``.
        joint_index: Index into ``q`` of the joint that drives this axis.
        multiplier: Axis value = multiplier · q[joint_index] + offset (|multiplier| ≤ 1e6).
        offset: See ``multiplier`` ([rad] or [m]).
        T_parent_joint: 4×4 rigid transform from the previous link frame to this joint frame.
        T_joint_child: 4×4 rigid transform from the moved joint frame to this axis' link frame.
        corners: Points [m] in the moved joint frame through which the drawn link
            passes on its way to the link frame origin (the DH "d then a" corner).

    Every field is checked on construction (RobotDefinitionError naming the axis); the
    transforms are stored as read-only arrays.
    """

    name: str
    kind: JointType
    joint_index: int
    multiplier: float
    offset: float
    T_parent_joint: FloatArray
    T_joint_child: FloatArray
    corners: tuple[tuple[float, float, float], ...] = ()

    def __post_init__(self) -> None:
        where = f"axis {show(self.name)}"
        _text(self.name, f"{where}, name")
        check_choice(self.kind, JOINT_TYPES, f"{where}, kind")
        if not (is_number(self.joint_index) and isinstance(self.joint_index, (int, np.integer))):
            raise RobotDefinitionError(f"{where}, joint_index: expected an int, got {show(self.joint_index)}")
        bound, unit = value_bound(self.kind)
        set_ = object.__setattr__
        set_(self, "joint_index", int(self.joint_index))
        set_(self, "multiplier", bounded_number(self.multiplier, MAX_MULTIPLIER, "", f"{where}, multiplier"))
        set_(self, "offset", bounded_number(self.offset, bound, unit, f"{where}, offset"))
        for attr in ("T_parent_joint", "T_joint_child"):
            set_(self, attr, frozen_array(check_rigid_transform(getattr(self, attr), f"{where}, {attr}")))
        corners = []
        if not isinstance(self.corners, (tuple, list)):
            raise RobotDefinitionError(f"{where}, corners: expected a tuple of (x, y, z) points")
        for c in self.corners:
            if not isinstance(c, (tuple, list, np.ndarray)) or len(c) != 3:
                raise RobotDefinitionError(f"{where}, corners: expected (x, y, z) points, got {show(c)}")
            x, y, z = (bounded_number(v, MAX_LENGTH, "m", f"{where}, corners") for v in c)
            corners.append((x, y, z))
        set_(self, "corners", tuple(corners))


@dataclass(frozen=True)
class DHRow:
    """One row of a DH table, in [m] and [rad], as given by the user (checked by :mod:`kinematics.dh`)."""

    joint: JointType
    a: float
    alpha: float
    d: float
    theta: float
    qlim: tuple[float, float] | None = None
    name: str = ""


@dataclass(frozen=True, eq=False)
class NamedConfiguration:
    """A configuration worth visiting (home, a singular pose, ...).

    Attributes:
        name: Short identifier (``"home"``, ``"wrist_singular"``).
        q: Joint values [rad] / [m], shape (n,), finite (stored read-only).
        description: One sentence for the GUI.
        singular: Kind of singularity ("wrist", "elbow", "shoulder", "boundary", ...)
            or "" for a regular configuration.
        translations: The description in other languages, language code → {"description": text}
            (``{"pl": {"description": "…"}}``; read-only, empty by default; see :func:`translations`).
    """

    name: str
    q: FloatArray
    description: str = ""
    singular: str = ""
    translations: Mapping[str, Mapping[str, str]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        name = _text(self.name, "configuration name")
        where = f"configuration {name!r}"
        _text(self.description, f"{where}, description")
        _text(self.singular, f"{where}, singular")
        object.__setattr__(
            self, "translations", translations(self.translations, ("description",), f"{where}, translations")
        )
        raw = self.q
        if isinstance(raw, (str, bytes)) or not isinstance(raw, (Sequence, np.ndarray)):
            raise RobotDefinitionError(f"{where}: q must be a sequence of numbers, got {show(raw)}")
        values = [bounded_number(v, MAX_ANGLE, "", f"{where}, q[{i}]") for i, v in enumerate(raw)]
        object.__setattr__(self, "q", frozen_array(values))


_PARAM_KEY = re.compile(r"(a|alpha|d|theta)[0-9]{1,4}|[xyz][bt]")
_PARAM_NAME = re.compile(r"[A-Za-z][A-Za-z0-9]{0,15}")
_RESERVED = re.compile(r"q[0-9]+|pi|E|I|oo|nan|zoo")


class FrozenNames(Mapping[str, _V]):
    """A read-only, picklable mapping by name (of names, or a language's texts by its code): robots
    travel to the symbolic worker process."""

    __slots__ = ("_items",)

    def __init__(self, items: Mapping[str, _V]) -> None:
        self._items = dict(items)

    def __getitem__(self, key: str) -> _V:
        return self._items[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._items)

    def __len__(self) -> int:
        return len(self._items)

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self._items!r})"


def param_names(value: object, name: str) -> Mapping[str, str]:
    """Checked, read-only course names of the symbolic parameters (see ``Robot.param_names``)."""
    where = f"robot {name!r}, param_names"
    if not isinstance(value, Mapping):
        raise RobotDefinitionError(f"{where}: expected a mapping of parameter names, got {show(value)}")
    out: dict[str, str] = {}
    for key, new in value.items():
        if not isinstance(key, str) or not _PARAM_KEY.fullmatch(key):
            raise RobotDefinitionError(
                f"{where}: key {show(key)} is not a parameter name; expected a{{k}}, alpha{{k}}, d{{i}}, "
                "theta{i} (d{i}0, theta{i}0 for an offset) or xt, yt, zt, xb, yb, zb"
            )
        if not isinstance(new, str) or not _PARAM_NAME.fullmatch(new) or _RESERVED.fullmatch(new):
            raise RobotDefinitionError(
                f"{where}, {key!r}: expected a letter then up to 15 letters or digits, "
                f"not a joint symbol q1… nor pi, E, I, oo, nan, zoo; got {show(new)}"
            )
        if new != key and _PARAM_KEY.fullmatch(new):
            raise RobotDefinitionError(f"{where}, {key!r}: {new!r} is itself a default parameter name")
        if new in out.values():
            raise RobotDefinitionError(f"{where}, {key!r}: the name {new!r} is given twice")
        out[key] = new
    return FrozenNames(out)


_LANGUAGE_CODE = re.compile(r"[a-z]{2,3}")


def translations(value: object, keys: Sequence[str], where: str) -> Mapping[str, Mapping[str, str]]:
    """Checked, read-only texts in other languages: language code (``"pt"``, ``"es"``, ``"pl"``: two
    or three lowercase letters) → {key: text}, each key one of ``keys`` (``"title"``, ``"description"``).

    The kinematics never read them: they travel with the robot for whoever shows it (the app shows a
    robot's texts in the tab's language, falling back to the English attribute).
    """
    if not isinstance(value, Mapping):
        raise RobotDefinitionError(f"{where}: expected a mapping of language codes, got {show(value)}")
    out: dict[str, Mapping[str, str]] = {}
    for code, texts in value.items():
        if not isinstance(code, str) or not _LANGUAGE_CODE.fullmatch(code):
            raise RobotDefinitionError(
                f"{where}: {show(code)} is not a language code (e.g. 'pt', 'es', 'pl')"
            )
        if not isinstance(texts, Mapping):
            raise RobotDefinitionError(f"{where}, {code!r}: expected a table of texts, got {show(texts)}")
        for key, text in texts.items():
            if key not in keys:
                allowed = ", ".join(map(repr, keys))
                raise RobotDefinitionError(f"{where}, {code!r}: unknown key {show(key)}; allowed: {allowed}")
            _text(text, f"{where}, {code!r}, {key!r}")
        out[code] = FrozenNames(texts)
    return FrozenNames(out)
