"""The robot library: one TOML file per robot in ``robots/data/`` (``puma560.toml`` is the
commented example of the format), and its loader. Files are in metres and DEGREES (alpha, theta,
revolute limits and configuration entries, base/tool rpy); the loader converts to radians and
builds a :class:`kinematics.Robot`. It only parses data (tomllib); nothing is ever evaluated.
"""

from __future__ import annotations

import functools
import math
import sys
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from kinematics import NamedConfiguration, Robot
from kinematics.errors import RobotDefinitionError, UnknownRobotError
from kinematics.files import decode_utf8, read_user_file
from kinematics.transforms import rpy_to_matrix
from kinematics.urdf import robot_from_urdf

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = ["DATA_DIR", "TASKS", "names", "load", "load_file", "info", "motions", "MotionPreset"]

DATA_DIR = Path(__file__).resolve().parent / "data"
SUFFIXES = (".toml", ".urdf", ".xacro")
MAX_ROBOT_FILE_BYTES = 1024 * 1024  # a robot file is a table of a few dozen numbers
TASKS = ("auto", "full", "linear", "angular", "planar")  # the optional task key: kinematics.Robot.task

# key -> type; float means "a finite int or float" (not a bool).
_TOP = {"name": str, "title": str, "description": str, "source": str, "convention": str, "joints": list}
_TOP_OPTIONAL = {
    "planar": bool,
    "task": str,
    "base": dict,
    "tool": dict,
    "configurations": list,
    "motions": list,  # [[motions]]: resolved-rate presets (a start, a tool twist held), see motions()
    "symbols": dict,  # [symbols]: course names of the symbolic parameters, kinematics.Robot.param_names
}
_JOINT = {"joint": str, "a": float, "alpha": float, "d": float, "theta": float}
_JOINT_OPTIONAL = {"name": str, "qlim": list}
_CONF = {"name": str, "q": list}
_CONF_OPTIONAL = {"description": str, "singular": str}
_FRAME_OPTIONAL = {"xyz": list, "rpy": list}
_MOTION = {"name": str, "start": str, "twist": list}
_MOTION_OPTIONAL = {"frame": str, "description": str, "speed": float, "rates": list}


@dataclass(frozen=True, eq=False)
class MotionPreset:
    """A resolved-rate demonstration of a robot file's ``[[motions]]`` table, in SI units.

    Attributes:
        name: What the user picks ("straight line into the wrist singularity").
        description: What it shows.
        q: The start configuration (n,) [rad | m] (a named configuration of the file, or home).
        twist: The tool twist held, [v; ω] (6,) [m/s; rad/s] (the file gives ω in deg/s).
        frame: Axes of the twist: "base" or "tool".
        speed: Playback speed to watch it at (1: real time; the course's TRR example runs into its
            singularity in a tenth of a second, so it is shown at 0.1).
        rates: The joint rates of the worked example this twist comes from (n,) [rad/s | m/s] (the
            file gives revolute rates in deg/s), or ``None``: the course's q̇ for v = J q̇.
    """

    name: str
    description: str
    q: np.ndarray
    twist: np.ndarray
    frame: str
    speed: float = 1.0
    rates: np.ndarray | None = None


def names() -> list[str]:
    """Names of the robots in the library (the stems of ``robots/data/*.toml``), sorted."""
    return sorted(p.stem for p in DATA_DIR.glob("*.toml"))


def load(
    name_or_path: str | Path,
    base_link: str | None = None,
    tip_link: str | None = None,
    *,
    xacro_args: Mapping[str, str] | None = None,
) -> Robot:
    """A robot by library name (``"puma560"``), or from a ``.toml`` robot file, a ``.urdf`` file or a
    ``.xacro`` file (expanded to a URDF with ``xacro_args``, :mod:`kinematics.urdf.expand`).

    Args:
        name_or_path: Library name or file path.
        base_link, tip_link: For a URDF, the ends of the chain (default: see
            :mod:`kinematics.urdf`); a robot file or library robot has no links to choose.
        xacro_args: ``NAME -> VALUE`` arguments of a xacro file.

    Raises:
        UnknownRobotError: not a library name (nor a file path); the message lists the names.
        RobotDefinitionError: the file is invalid; the message names the file and the key or row.
    """
    path = _resolve(name_or_path)
    if path.parent == DATA_DIR and path.suffix == ".toml":
        _no_links(path, base_link, tip_link)
        return _load_library(path.stem)
    return load_file(path, base_link, tip_link, xacro_args=xacro_args)


def _no_links(path: Path, base_link: str | None, tip_link: str | None) -> None:
    if base_link is not None or tip_link is not None:
        raise RobotDefinitionError(
            f"{path.name}: base_link/tip_link choose a chain in a URDF; a robot file (.toml) is one chain"
        )


def info(name_or_path: str | Path) -> dict:
    """Metadata of a robot file, without building the robot: name, title, description, source,
    convention, planar and task (``"auto"`` unless the file sets it)."""
    path = _resolve(name_or_path)
    doc = _validated(path, _read(path))
    return {"name": doc["name"], "convention": doc["convention"]} | _meta(doc)


def motions(name_or_path: str | Path) -> tuple[MotionPreset, ...]:
    """The resolved-rate presets of a robot file (``[[motions]]``; none for a URDF)."""
    path = _resolve(name_or_path)
    if path.suffix.lower() != ".toml":
        return ()
    doc = _validated(path, _read(path))
    revolute = [j["joint"] == "revolute" for j in doc["joints"]]
    starts = {c["name"]: c["q"] for c in doc.get("configurations", [])}
    out = []
    for m in doc.get("motions", []):
        q = [
            math.radians(v) if rev else float(v) for v, rev in zip(starts[m["start"]], revolute, strict=True)
        ]
        twist = [float(v) for v in m["twist"][:3]] + [math.radians(v) for v in m["twist"][3:]]
        text = _text(m.get("description", ""))
        frame, speed = m.get("frame", "base"), float(m.get("speed", 1.0))
        rates = None
        if "rates" in m:
            rates = np.array(
                [math.radians(v) if rev else float(v) for v, rev in zip(m["rates"], revolute, strict=True)]
            )
        out.append(MotionPreset(m["name"], text, np.array(q), np.array(twist), frame, speed, rates))
    return tuple(out)


def load_file(
    path: str | Path,
    base_link: str | None = None,
    tip_link: str | None = None,
    *,
    xacro_args: Mapping[str, str] | None = None,
) -> Robot:
    """Build a robot from a ``.toml`` robot file, a ``.urdf`` file or a ``.xacro`` file (base and tip
    links: URDF and xacro only; ``xacro_args``: xacro only)."""
    path = Path(path)
    if path.suffix.lower() in (".urdf", ".xacro"):
        return robot_from_urdf(str(path), base_link=base_link, tip_link=tip_link, xacro_args=xacro_args)
    if path.suffix.lower() != ".toml":
        raise RobotDefinitionError(
            f"{path.name}: expected a .toml robot file, a .urdf file or a .xacro file (e.g. arm.urdf.xacro)"
        )
    _no_links(path, base_link, tip_link)
    doc = _validated(path, _read(path))
    rows, revolute = [], [j["joint"] == "revolute" for j in doc["joints"]]
    for j, rev in zip(doc["joints"], revolute, strict=True):
        row = {**j, "alpha": math.radians(j["alpha"]), "theta": math.radians(j["theta"])}
        if "qlim" in j:
            row["qlim"] = tuple(math.radians(v) if rev else float(v) for v in j["qlim"])
        rows.append(row)
    confs = []
    for c in doc.get("configurations", []):
        q = [math.radians(v) if rev else v for v, rev in zip(c["q"], revolute, strict=True)]
        text = _text(c.get("description", ""))
        confs.append(NamedConfiguration(c["name"], np.array(q, dtype=float), text, c.get("singular", "")))
    base, tool, meta = _frame(doc, "base"), _frame(doc, "tool"), _meta(doc)
    names = _symbols(doc, path.name)
    try:
        return Robot.from_dh(
            rows, doc["convention"], base, tool, doc["name"], configurations=confs, param_names=names, **meta
        )
    except RobotDefinitionError as exc:
        raise RobotDefinitionError(f"{path.name}: {exc}") from None


def _symbols(doc: dict, file: str) -> dict[str, str]:
    """The optional ``[symbols]`` table: default parameter name → course name (``a1 = "l1"``).

    Its values must be strings here; :class:`kinematics.Robot` checks the names themselves.
    """
    table = doc.get("symbols", {})
    for key, value in table.items():
        if not isinstance(value, str):
            raise RobotDefinitionError(f"{file}, [symbols] key {key!r}: expected a string, got {value!r}")
    return dict(table)


def _resolve(name_or_path: str | Path) -> Path:
    text = str(name_or_path)
    if isinstance(name_or_path, Path) or any(ch in text for ch in "/\\") or text.lower().endswith(SUFFIXES):
        return Path(name_or_path)
    if text not in names():
        raise UnknownRobotError(f"unknown robot {text!r}; available robots: {', '.join(names())}")
    return DATA_DIR / f"{text}.toml"


@functools.cache
def _load_library(name: str) -> Robot:
    return load_file(DATA_DIR / f"{name}.toml")


def _read(path: Path) -> dict:
    """The TOML document of the robot file ``path`` (a regular UTF-8 file of at most 1 MB)."""
    if not path.exists() and not path.is_symlink():
        raise RobotDefinitionError(f"{path}: no such robot file")
    data = read_user_file(path, "robot file", RobotDefinitionError, MAX_ROBOT_FILE_BYTES)
    text = decode_utf8(data, f"{path.name}", RobotDefinitionError)
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise RobotDefinitionError(f"{path.name}: not valid TOML: {exc}") from None
    except RecursionError:
        raise RobotDefinitionError(f"{path.name}: not valid TOML: nested too deeply") from None
    except ValueError as exc:  # an integer of more digits than Python converts
        raise RobotDefinitionError(f"{path.name}: not valid TOML: {exc}") from None


def _check_table(table: object, required: dict, optional: dict, where: str) -> None:
    if not isinstance(table, dict):
        raise RobotDefinitionError(f"{where}: expected a table, got {table!r}")
    missing = [k for k in required if k not in table]
    if missing:
        raise RobotDefinitionError(f"{where}: missing key(s) {', '.join(map(repr, missing))}")
    unknown = sorted(set(table) - set(required) - set(optional), key=repr)
    if unknown:
        bad, allowed = ", ".join(map(repr, unknown)), ", ".join([*required, *optional])
        raise RobotDefinitionError(f"{where}: unknown key(s) {bad}; allowed: {allowed}")
    for key, kind in (required | optional).items():
        if key in table and kind is float:
            _number(table[key], f"{where}, key {key!r}")
        elif key in table and not isinstance(table[key], kind):
            got = table[key]
            raise RobotDefinitionError(f"{where}, key {key!r}: expected a {kind.__name__}, got {got!r}")


def _number(x: object, where: str) -> None:
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        raise RobotDefinitionError(f"{where}: expected a number, got {_short(x)}")
    try:
        finite = math.isfinite(float(x))
    except OverflowError:  # an integer beyond float range
        finite = False
    if not finite:
        raise RobotDefinitionError(f"{where}: expected a finite number within float range, got {_short(x)}")


def _short(x: object) -> str:
    """``repr(x)`` cut to 60 characters (a 400-digit integer is not a message)."""
    if isinstance(x, int) and x.bit_length() > 200:
        return f"an integer of about {int(x.bit_length() * 0.30103)} digits"
    text = repr(x)
    return text if len(text) <= 60 else text[:57] + "..."


def _one_of(value: str, allowed: tuple[str, ...], where: str) -> None:
    if value not in allowed:
        raise RobotDefinitionError(f"{where}: expected one of {', '.join(allowed)}; got {value!r}")


def _numbers(x: list, length: int, where: str) -> None:
    if len(x) != length:
        raise RobotDefinitionError(f"{where}: expected {length} numbers, got {len(x)}")
    for v in x:
        _number(v, where)


def _validated(path: Path, doc: dict) -> dict:
    f = path.name
    _check_table(doc, _TOP, _TOP_OPTIONAL, f)
    if doc["name"] != path.stem:
        raise RobotDefinitionError(f"{f}, key 'name': {doc['name']!r} must equal the file stem {path.stem!r}")
    _one_of(doc["convention"], ("standard", "modified"), f"{f}, key 'convention'")
    _one_of(doc.get("task", "auto"), TASKS, f"{f}, key 'task'")
    if not doc["joints"]:
        raise RobotDefinitionError(f"{f}, key 'joints': expected at least one [[joints]] row")
    for i, j in enumerate(doc["joints"]):
        where = f"{f}, joints row {i + 1}"
        _check_table(j, _JOINT, _JOINT_OPTIONAL, where)
        _one_of(j["joint"], ("revolute", "prismatic"), f"{where}, key 'joint'")
        if "qlim" in j:
            _numbers(j["qlim"], 2, f"{where}, key 'qlim' (lower, upper)")
    for side in ("base", "tool"):
        if side in doc:
            _check_table(doc[side], {}, _FRAME_OPTIONAL, f"{f}, [{side}]")
            for key in ("xyz", "rpy"):
                if key in doc[side]:
                    _numbers(doc[side][key], 3, f"{f}, [{side}] key {key!r}")
    seen: set[str] = set()
    for i, c in enumerate(doc.get("configurations", [])):
        where = f"{f}, configurations entry {i + 1}"
        _check_table(c, _CONF, _CONF_OPTIONAL, where)
        if c["name"] in seen:
            raise RobotDefinitionError(f"{where}, key 'name': duplicate configuration name {c['name']!r}")
        seen.add(c["name"])
        _numbers(c["q"], len(doc["joints"]), f"{where} ({c['name']!r}), key 'q' (one value per joint)")
    for i, m in enumerate(doc.get("motions", [])):
        where = f"{f}, motions entry {i + 1}"
        _check_table(m, _MOTION, _MOTION_OPTIONAL, where)
        _one_of(m["start"], tuple(seen), f"{where}, key 'start' (a configuration name)")
        _numbers(m["twist"], 6, f"{where}, key 'twist' (vx vy vz in m/s, ωx ωy ωz in deg/s)")
        _one_of(m.get("frame", "base"), ("base", "tool"), f"{where}, key 'frame'")
        if "rates" in m:
            _numbers(m["rates"], len(doc["joints"]), f"{where}, key 'rates' (m/s or deg/s, one per joint)")
        if not 0.05 <= m.get("speed", 1.0) <= 2.0:
            raise RobotDefinitionError(f"{where}, key 'speed': expected 0.05 to 2, got {m['speed']!r}")
    return doc


def _meta(doc: dict) -> dict:
    texts = {k: _text(doc[k]) for k in ("title", "description", "source")}
    return texts | {"planar": doc.get("planar", False), "task": doc.get("task", "auto")}


def _text(s: str) -> str:
    """One paragraph: the line breaks of a TOML multi-line string become spaces."""
    return " ".join(s.split())


def _frame(doc: dict, side: str) -> np.ndarray:
    table = doc.get(side, {})
    T = np.eye(4)
    T[:3, :3] = rpy_to_matrix(*(math.radians(v) for v in table.get("rpy", (0, 0, 0))))
    T[:3, 3] = table.get("xyz", (0, 0, 0))
    return T
