"""The robot-file format in one place: read, validate and write (lossless).

A robot file is TOML (``robots/data/puma560.toml`` is the commented example): the top-level keys
``name`` (the file stem), ``title``, ``description``, ``source``, ``convention`` and optionally
``planar`` and ``task``; optional ``[base]`` and ``[tool]`` tables (``xyz`` [m], ``rpy`` [deg]);
an optional ``[symbols]`` table (course names of the symbolic parameters, ``a2 = "l2"``); optional
``[translations.<language>]`` tables (the title and description in ``pt``, ``es`` or ``pl``); one
``[[joints]]`` table per DH row; optional ``[[configurations]]`` and ``[[motions]]``, each of which
may hold ``translations.<language>.description``. English is the file's own language: every text
has its English key, and a language a file does not translate falls back to it.

Files are in metres and DEGREES (alpha, theta, revolute limits and configuration entries,
base/tool rpy, the angular part of a motion's twist and revolute rates); :func:`read` converts
to radians and :func:`dumps` back, choosing for each angle the shortest decimal whose radians are
the stored value, so read → write → read gives the same robot. Texts (title, description, source,
configuration descriptions) are one paragraph: their line breaks become spaces. Only data is
parsed (tomllib); nothing is ever evaluated, and every text written is escaped.
"""

from __future__ import annotations

import math
import re
import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from kinematics import NamedConfiguration, Robot
from kinematics.conventions import FRAMES, TASKS
from kinematics.errors import RobotDefinitionError
from kinematics.files import decode_utf8, read_user_file
from kinematics.parts import CONVENTIONS, JOINT_TYPES
from kinematics.transforms import matrix_to_rpy, rpy_to_matrix

from . import texts
from .texts import TEXT_LANGUAGES
from .toml_values import check_numbers, check_table, key_text, number_text, one_of, string_text

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = [
    "MAX_ROBOT_FILE_BYTES",
    "TEXT_LANGUAGES",
    "MotionPreset",
    "RobotFile",
    "read",
    "loads",
    "dumps",
    "validated",
    "meta",
]

MAX_ROBOT_FILE_BYTES = 1024 * 1024  # a robot file is a table of a few dozen numbers

# key -> type; float means "a finite int or float" (not a bool).
_TOP = {"name": str, "title": str, "description": str, "source": str, "convention": str, "joints": list}
_TOP_OPTIONAL = {
    "planar": bool,
    "task": str,
    "base": dict,
    "tool": dict,
    "configurations": list,
    "motions": list,  # [[motions]]: resolved-rate presets (a start, a tool twist held)
    "symbols": dict,  # [symbols]: course names of the symbolic parameters, kinematics.Robot.param_names
    "translations": dict,  # [translations.pl]: title and description in another language
}
_JOINT = {"joint": str, "a": float, "alpha": float, "d": float, "theta": float}
_JOINT_OPTIONAL = {"name": str, "qlim": list}
_CONF = {"name": str, "q": list}
_CONF_OPTIONAL = {"description": str, "singular": str, "translations": dict}
_FRAME_OPTIONAL = {"xyz": list, "rpy": list}
_MOTION = {"name": str, "start": str, "twist": list}
_MOTION_OPTIONAL = {"frame": str, "description": str, "speed": float, "rates": list, "translations": dict}


@dataclass(frozen=True, eq=False)
class MotionPreset:
    """A resolved-rate demonstration of a robot file's ``[[motions]]`` table, in SI units.

    Attributes:
        name: What the user picks ("straight line into the wrist singularity").
        description: What it shows.
        q: The start configuration (n,) [rad | m] (a named configuration of the file).
        twist: The tool twist held, [v; ω] (6,) [m/s; rad/s] (the file gives ω in deg/s).
        frame: Axes of the twist: "base" or "tool".
        speed: Playback speed to watch it at (1: real time; the course's TRR example runs into its
            singularity in a tenth of a second, so it is shown at 0.1).
        rates: The joint rates of the worked example this twist comes from (n,) [rad/s | m/s] (the
            file gives revolute rates in deg/s), or ``None``: the course's q̇ for v = J q̇.
        start: The name of the configuration ``q`` is ("" for a preset made in code: the writer
            then looks for a configuration with exactly this ``q``).
        translations: The description in other languages, {"pl": {"description": "…"}}.
    """

    name: str
    description: str
    q: np.ndarray
    twist: np.ndarray
    frame: str
    speed: float = 1.0
    rates: np.ndarray | None = None
    start: str = ""
    translations: Mapping[str, Mapping[str, str]] = field(default_factory=dict)


@dataclass(frozen=True, eq=False)
class RobotFile:
    """Everything a robot file holds: the robot (DH table, base, tool, configurations, symbols,
    planar, task, texts) and its motion presets."""

    robot: Robot
    motions: tuple[MotionPreset, ...] = ()


# ---------------------------------------------------------------------- reading
def read(path: Path) -> RobotFile:
    """The robot file ``path`` (a regular UTF-8 ``.toml`` file of at most 1 MB), checked and built.

    Raises:
        RobotDefinitionError: the message names the file and the key, row or entry.
    """
    return loads(read_text(path), path.name)


def read_text(path: Path) -> str:
    """The text of the robot file ``path``, or RobotDefinitionError (missing, too large, not UTF-8)."""
    if not path.exists() and not path.is_symlink():
        raise RobotDefinitionError(f"{path}: no such robot file")
    data = read_user_file(path, "robot file", RobotDefinitionError, MAX_ROBOT_FILE_BYTES)
    return decode_utf8(data, f"{path.name}", RobotDefinitionError)


def parse(text: str, file_name: str) -> dict[str, Any]:
    """The checked TOML document of a robot file's ``text`` (``file_name``: for messages and the
    stem the ``name`` key must equal)."""
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise RobotDefinitionError(f"{file_name}: not valid TOML: {exc}") from None
    except RecursionError:
        raise RobotDefinitionError(f"{file_name}: not valid TOML: nested too deeply") from None
    except ValueError as exc:  # an integer of more digits than Python converts (4300 by default)
        digits = re.search(r"value has (\d+) digits", str(exc))
        raise RobotDefinitionError(
            f"{file_name}: an integer of {digits.group(1)} digits; write a number within float range, "
            "e.g. 1.5e3"
            if digits
            else f"{file_name}: not valid TOML: {exc}"
        ) from None
    return validated(doc, file_name)


def loads(text: str, file_name: str) -> RobotFile:
    """The robot and motions of a robot file's ``text``, named ``file_name`` (``"puma560.toml"``)."""
    doc = parse(text, file_name)
    revolute = [j["joint"] == "revolute" for j in doc["joints"]]
    rows = []
    for j, rev in zip(doc["joints"], revolute, strict=True):
        row = {**j, "alpha": math.radians(j["alpha"]), "theta": math.radians(j["theta"])}
        if "qlim" in j:
            row["qlim"] = tuple(_to_si(v, rev) for v in j["qlim"])
        rows.append(row)
    confs = []
    for c in doc.get("configurations", []):
        q = [_to_si(v, rev) for v, rev in zip(c["q"], revolute, strict=True)]
        text_, tr = _text(c.get("description", "")), texts.read_translations(c)
        confs.append(
            NamedConfiguration(c["name"], np.array(q, dtype=float), text_, c.get("singular", ""), tr)
        )
    base, tool = _frame(doc, "base"), _frame(doc, "tool")
    try:
        robot = Robot.from_dh(
            rows,
            doc["convention"],
            base,
            tool,
            doc["name"],
            configurations=confs,
            param_names=_symbols(doc, file_name),
            **meta(doc),
        )
    except RobotDefinitionError as exc:
        raise RobotDefinitionError(f"{file_name}: {exc}") from None
    return RobotFile(robot, _motions(doc, revolute))


def _to_si(v: float, revolute: bool) -> float:
    return math.radians(v) if revolute else float(v)


def _motions(doc: dict[str, Any], revolute: list[bool]) -> tuple[MotionPreset, ...]:
    starts = {c["name"]: c["q"] for c in doc.get("configurations", [])}
    out = []
    for m in doc.get("motions", []):
        q = np.array([_to_si(v, rev) for v, rev in zip(starts[m["start"]], revolute, strict=True)])
        twist = np.array([float(v) for v in m["twist"][:3]] + [math.radians(v) for v in m["twist"][3:]])
        rates = None
        if "rates" in m:
            rates = np.array([_to_si(v, rev) for v, rev in zip(m["rates"], revolute, strict=True)])
        text_, frame, speed = (
            _text(m.get("description", "")),
            m.get("frame", "base"),
            float(m.get("speed", 1.0)),
        )
        tr = texts.read_translations(m)
        out.append(MotionPreset(m["name"], text_, q, twist, frame, speed, rates, m["start"], tr))
    return tuple(out)


def _symbols(doc: dict[str, Any], file: str) -> dict[str, str]:
    """The optional ``[symbols]`` table: default parameter name → course name (``a1 = "l1"``).

    Its values must be strings here; :class:`kinematics.Robot` checks the names themselves.
    """
    table = doc.get("symbols", {})
    for key, value in table.items():
        if not isinstance(value, str):
            raise RobotDefinitionError(
                f"{doc['name']}.toml, [symbols] key {key!r}: expected a string, got {value!r}"
            )
    return dict(table)


def meta(doc: dict[str, Any]) -> dict[str, Any]:
    """Title, description, source (one paragraph each), planar, task and the title's and description's
    translations of a checked document (what :func:`robots.info` tells besides the name and convention)."""
    words = {k: _text(doc[k]) for k in ("title", "description", "source")}
    more = {"planar": doc.get("planar", False), "task": doc.get("task", "auto")}
    return words | more | {"translations": texts.read_translations(doc)}


def _text(s: str) -> str:
    """One paragraph: the line breaks of a TOML multi-line string become spaces."""
    return " ".join(s.split())


def _frame(doc: dict[str, Any], side: str) -> np.ndarray:
    table = doc.get(side, {})
    T = np.eye(4)
    T[:3, :3] = rpy_to_matrix(*(math.radians(v) for v in table.get("rpy", (0, 0, 0))))
    T[:3, 3] = table.get("xyz", (0, 0, 0))
    return T


# ---------------------------------------------------------------------- validating
def validated(doc: object, f: str) -> dict[str, Any]:
    """``doc`` (a parsed TOML document of the file named ``f``) if it is a robot file, else
    RobotDefinitionError naming the file, the table or row and the key."""
    check_table(doc, _TOP, _TOP_OPTIONAL, f)
    assert isinstance(doc, dict)
    stem = f[: -len(".toml")] if f.lower().endswith(".toml") else f
    if doc["name"] != stem:
        raise RobotDefinitionError(f"{f}, key 'name': {doc['name']!r} must equal the file stem {stem!r}")
    one_of(doc["convention"], CONVENTIONS, f"{f}, key 'convention'")
    one_of(doc.get("task", "auto"), TASKS, f"{f}, key 'task'")
    texts.check_translations(doc, texts.TOP_KEYS, f)
    if not doc["joints"]:
        raise RobotDefinitionError(f"{f}, key 'joints': expected at least one [[joints]] row")
    for i, j in enumerate(doc["joints"]):
        where = f"{f}, joints row {i + 1}"
        check_table(j, _JOINT, _JOINT_OPTIONAL, where)
        one_of(j["joint"], JOINT_TYPES, f"{where}, key 'joint'")
        if "qlim" in j:
            check_numbers(j["qlim"], 2, f"{where}, key 'qlim' (lower, upper)")
    for side in ("base", "tool"):
        if side in doc:
            check_table(doc[side], {}, _FRAME_OPTIONAL, f"{f}, [{side}]")
            for key in ("xyz", "rpy"):
                if key in doc[side]:
                    check_numbers(doc[side][key], 3, f"{f}, [{side}] key {key!r}")
    seen: set[str] = set()
    for i, c in enumerate(doc.get("configurations", [])):
        where = f"{f}, configurations entry {i + 1}"
        check_table(c, _CONF, _CONF_OPTIONAL, where)
        if c["name"] in seen:
            raise RobotDefinitionError(f"{where}, key 'name': duplicate configuration name {c['name']!r}")
        seen.add(c["name"])
        texts.check_translations(c, texts.ENTRY_KEYS, where)
        check_numbers(c["q"], len(doc["joints"]), f"{where} ({c['name']!r}), key 'q' (one value per joint)")
    for i, m in enumerate(doc.get("motions", [])):
        where = f"{f}, motions entry {i + 1}"
        check_table(m, _MOTION, _MOTION_OPTIONAL, where)
        one_of(m["start"], tuple(seen), f"{where}, key 'start' (a configuration name)")
        texts.check_translations(m, texts.MOTION_KEYS, where)
        check_numbers(m["twist"], 6, f"{where}, key 'twist' (vx vy vz in m/s, ωx ωy ωz in deg/s)")
        one_of(m.get("frame", "base"), FRAMES, f"{where}, key 'frame'")
        if "rates" in m:
            check_numbers(
                m["rates"], len(doc["joints"]), f"{where}, key 'rates' (m/s or deg/s, one per joint)"
            )
        if not 0.05 <= m.get("speed", 1.0) <= 2.0:
            raise RobotDefinitionError(f"{where}, key 'speed': expected 0.05 to 2, got {m['speed']!r}")
    return doc


# ---------------------------------------------------------------------- writing
def dumps(
    robot: Robot, motions: Sequence[MotionPreset] = (), name: str | None = None, header: Sequence[str] = ()
) -> str:
    """``robot`` (and its ``motions``) as a robot file, to be saved as ``{name}.toml``.

    Args:
        robot: A robot with a DH table.
        motions: Its resolved-rate presets; each starts at one of the robot's configurations.
        name: The file stem, written as the ``name`` key (default: the robot's name).
        header: Comment lines put first.

    Raises:
        RobotDefinitionError: the robot has no DH table, or a motion's start is not one of its
            configurations.
    """
    if robot.dh is None or robot.convention is None:
        raise RobotDefinitionError(f"{robot.name!r} has no DH table: save it as a URDF")
    stem = robot.name if name is None else name
    revolute = [r.joint == "revolute" for r in robot.dh]
    out = [f"# {' '.join(line.split())}" for line in header]
    out += [f"{k} = {string_text(v)}" for k, v in _texts(robot, stem)]
    out.append(f"planar = {'true' if robot.planar else 'false'}")
    out += [f"task = {string_text(robot.task)}", ""]
    out += _frame_lines(robot.base, "base") + _frame_lines(robot.tool, "tool")
    if robot.param_names:
        out += ["[symbols]", *(f"{key_text(k)} = {string_text(v)}" for k, v in robot.param_names.items()), ""]
    out += texts.translation_tables(robot.translations)
    for r in robot.dh:
        out.append("[[joints]]")
        out += [f"name = {string_text(r.name)}"] if r.name else []
        out += [f"joint = {string_text(r.joint)}", f"a = {number_text(r.a)}"]
        out += [f"alpha = {_degrees(r.alpha)}", f"d = {number_text(r.d)}", f"theta = {_degrees(r.theta)}"]
        if r.qlim is not None:
            out.append(f"qlim = {_values(r.qlim, [r.joint == 'revolute'] * 2)}")
        out.append("")
    for c in robot.configurations:
        out += ["[[configurations]]", f"name = {string_text(c.name)}", f"q = {_values(c.q, revolute)}"]
        out += [f"description = {string_text(c.description)}", f"singular = {string_text(c.singular)}"]
        out += [*texts.translation_lines(c.translations), ""]
    for m in motions:
        out += ["[[motions]]", f"name = {string_text(m.name)}", f"start = {string_text(_start(robot, m))}"]
        out += [f"twist = {_values(m.twist, [False] * 3 + [True] * 3)}", f"frame = {string_text(m.frame)}"]
        out += [f"speed = {number_text(m.speed)}"]
        out += [f"rates = {_values(m.rates, revolute)}"] if m.rates is not None else []
        out += [f"description = {string_text(m.description)}", *texts.translation_lines(m.translations), ""]
    return "\n".join(out)


def _texts(robot: Robot, stem: str) -> list[tuple[str, str]]:
    fields = (robot.title, robot.description, robot.source, robot.convention or "standard")
    return list(zip(("name", "title", "description", "source", "convention"), (stem, *fields), strict=True))


def _start(robot: Robot, m: MotionPreset) -> str:
    names = [c.name for c in robot.configurations]
    if m.start in names:
        return m.start
    same = [c.name for c in robot.configurations if np.array_equal(c.q, m.q)]
    if not same:
        raise RobotDefinitionError(
            f"motion {m.name!r}: its start is not a named configuration of {robot.name!r}; "
            f"a robot file starts a motion at one of {', '.join(map(repr, names)) or '(none)'}"
        )
    return same[0]


def _frame_lines(T: np.ndarray, side: str) -> list[str]:
    if np.array_equal(T, np.eye(4)):
        return []
    xyz = _values(T[:3, 3], [False] * 3)
    rpy = _values(matrix_to_rpy(T[:3, :3]), [True] * 3)
    return [f"[{side}]", f"xyz = {xyz}", f"rpy = {rpy}", ""]


def _values(values: Sequence[float] | np.ndarray, angle: Sequence[bool]) -> str:
    """A TOML array: angles [rad] in degrees, other values as they are."""
    cells = (_degrees(v) if a else number_text(v) for v, a in zip(values, angle, strict=True))
    return f"[{', '.join(cells)}]"


def _degrees(rad: float) -> str:
    """``rad`` in degrees, as the shortest decimal whose :func:`math.radians` is ``rad`` again."""
    rad = float(rad)
    deg = math.degrees(rad)
    for digits in range(1, 18):
        cand = float(f"{deg:.{digits}g}")
        if math.radians(cand) == rad:
            return number_text(cand)
    lo = hi = deg
    for _ in range(4):  # within a few ulps of degrees(rad)
        lo, hi = math.nextafter(lo, -math.inf), math.nextafter(hi, math.inf)
        for cand in (lo, hi):
            if math.radians(cand) == rad:
                return number_text(cand)
    return number_text(deg)  # no decimal maps back exactly: the nearest one (off by one ulp at most)
