"""The DH table a student edits in the browser (the Build tab), as plain values, and what it becomes.

A :class:`Table` holds the rows as typed on screen: lengths in metres, angles and revolute
limits in DEGREES (radians exist only inside the :class:`~kinematics.Robot` it builds). It is
pure data with pure functions, so the editor view only keeps one and the tests need no browser:

* :func:`build` checks every field and builds the robot with :meth:`kinematics.Robot.from_dh`;
  a bad value raises :class:`TableError` naming the row and the field ("row 2, α [°]");
* :func:`from_robot` opens a library robot's DH table (its base and tool transforms kept);
* :func:`robot_toml` writes a robot file with :func:`robots.dumps` (the one writer of the format,
  lossless), loadable by :func:`robots.load`; :func:`robot_file` gives the downloads (TOML, URDF);
* :func:`edited_state` is the reducer's rule for :class:`~app.core.actions.EditRobot`: the display
  choices and the values of the joints that were kept stay as they were.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

import robots
from kinematics import NamedConfiguration, Robot
from kinematics.analysis import is_planar_chain, task_rows
from kinematics.errors import RobotDefinitionError
from kinematics.parts import CONVENTIONS, JOINT_TYPES
from kinematics.urdf import to_urdf

from .i18n import N_, Translator, translations
from .numbers import NumberError, parse_number
from .ranges import joint_ranges
from .state import LabState, default_options, frozen

__all__ = [
    "BUILT_NAME",
    "FIELDS",
    "ROBOT_FILE_FORMATS",
    "Row",
    "Table",
    "TableError",
    "build",
    "edited_state",
    "empty",
    "from_robot",
    "robot_file",
    "robot_toml",
]

BUILT_NAME = "(built in the browser)"
"""How a robot built in the Build tab is listed in the tab's robot dropdown."""
FILE_STEM = "built_robot"
"""Name (and file stem) of a downloaded robot file."""
ROBOT_FILE_FORMATS = ("Robot file (TOML)", "URDF")
"""Download labels answered from the robot itself (the symbolic J ones go to the symbolic worker)."""

FIELDS = {
    "joint": N_("joint type"),
    "a": "a [m]",
    "alpha": "α [°]",
    "d": "d [m]",
    "theta": N_("θ offset [°]"),
    "lo": N_("lower limit"),
    "hi": N_("upper limit"),
    "rows": N_("rows"),
    "convention": N_("convention"),
    "table": N_("table"),
}
"""Field of a row → its name on screen, in English (the message of a bad value names it, translated)."""


class TableError(ValueError):
    """A value of the table that cannot make a robot: ``row`` (from 1; 0: the whole table), ``field``;
    its message in ``tr``'s language."""

    def __init__(self, row: int, field: str, message: str, tr: Translator | None = None) -> None:
        _ = (tr or translations()).gettext
        name = _(FIELDS[field]) if field in FIELDS else field
        if row:
            text = _("Row {row}, {field}: {message}").format(row=row, field=name, message=message)
        else:
            text = _("{field}: {message}").format(field=name, message=message)
        super().__init__(text)
        self.row, self.field = row, field


@dataclass(frozen=True)
class Row:
    """One row as shown: ``a``, ``d`` [m]; ``alpha``, ``theta`` [°]; limits [°] (revolute) or [m] (prismatic).

    Values are what the user typed (they may be anything until :func:`build` checks them).
    """

    joint: str = "revolute"
    a: object = 0.0
    alpha: object = 0.0
    d: object = 0.0
    theta: object = 0.0
    lo: object = -180.0
    hi: object = 180.0
    name: str = ""

    def with_kind(self, joint: str) -> Row:
        """The row with joint type ``joint``; the limits reset to that type's defaults when it changes."""
        if joint == self.joint:
            return self
        lo, hi = (-180.0, 180.0) if joint == "revolute" else (0.0, 0.5)
        return dataclasses.replace(self, joint=joint, lo=lo, hi=hi)


@dataclass(frozen=True, eq=False)
class Table:
    """A DH table as edited: rows, convention, and what it keeps of the robot it started from: the
    base and tool transforms, and its named configurations while the rows keep their number and
    joint types (only "home": the Puma starts at its home, not at the middle of its limits; the
    singular configurations of the original would no longer be true once a number changes)."""

    rows: tuple[Row, ...]
    convention: str = "standard"
    base: np.ndarray | None = None
    tool: np.ndarray | None = None
    source: str = ""
    configurations: tuple[NamedConfiguration, ...] = ()
    kinds: tuple[str, ...] = ()


def empty() -> Table:
    """One revolute row of 0.5 m (the "empty table" to start from)."""
    return Table((Row(a=0.5),))


def from_robot(robot: Robot) -> Table:
    """The DH table of ``robot`` on screen (degrees), with its base and tool transforms.

    Raises:
        RobotDefinitionError: the robot has no DH table (a URDF robot).
    """
    if robot.dh is None or robot.convention is None:
        raise RobotDefinitionError(f"{robot.name!r} is not a DH robot: it has no DH table to edit")
    rows = []
    for r in robot.dh:
        rev = r.joint == "revolute"
        lo, hi = r.qlim if r.qlim is not None else ((-math.pi, math.pi) if rev else (0.0, 1.0))
        lo, hi = (math.degrees(lo), math.degrees(hi)) if rev else (lo, hi)
        rows.append(Row(r.joint, r.a, math.degrees(r.alpha), r.d, math.degrees(r.theta), lo, hi, r.name))
    kinds = tuple(r.joint for r in robot.dh)
    home = tuple(c for c in robot.configurations if c.name == "home")  # a start; the others' claims
    return Table(tuple(rows), robot.convention, robot.base, robot.tool, robot.name, home, kinds)


MAX_LENGTH = 100.0
"""Largest |a|, |d| or prismatic limit the editor takes [m]: a lab arm, not a 1400 m one."""
MAX_ANGLE = 3600.0
"""Largest |α|, |θ| or revolute limit the editor takes [°]."""


def _number(value: object, row: int, field: str, unit: str, tr: Translator | None = None) -> float:
    bound = MAX_ANGLE if unit == "°" else MAX_LENGTH
    try:
        return parse_number(value, bound, unit, tr)
    except NumberError as exc:
        raise TableError(row, field, str(exc), tr) from None


def rows_si(table: Table, tr: Translator | None = None) -> list[dict[str, object]]:
    """The rows as :meth:`Robot.from_dh` takes them (radians), every field checked; numbers typed as
    ``tr``'s language writes them (a decimal comma in pt, es, pl), refusals in its words.

    Raises:
        TableError: the first bad field (row and field named).
    """
    tr = tr or translations()
    _ = tr.gettext
    out: list[dict[str, object]] = []
    for i, r in enumerate(table.rows, start=1):
        if r.joint not in JOINT_TYPES:
            message = _("expected revolute or prismatic, got {value}").format(value=repr(str(r.joint)[:30]))
            raise TableError(i, "joint", message, tr)
        limit_unit = "°" if r.joint == "revolute" else "m"
        units = {"a": "m", "alpha": "°", "d": "m", "theta": "°", "lo": limit_unit, "hi": limit_unit}
        v = {k: _number(getattr(r, k), i, k, u, tr) for k, u in units.items()}
        if v["lo"] > v["hi"]:
            message = _("the lower limit {lo} is above the upper limit {hi}").format(
                lo=tr.decimal(f"{v['lo']:g}"), hi=tr.decimal(f"{v['hi']:g}")
            )
            raise TableError(i, "lo", message, tr)
        rev = r.joint == "revolute"
        qlim = (math.radians(v["lo"]), math.radians(v["hi"])) if rev else (v["lo"], v["hi"])
        row: dict[str, object] = {
            "joint": r.joint,
            "a": v["a"],
            "alpha": math.radians(v["alpha"]),
            "d": v["d"],
            "theta": math.radians(v["theta"]),
            "qlim": qlim,
        }
        if r.name:
            row["name"] = r.name
        out.append(row)
    return out


MAX_ROWS = 24
"""Most rows of a table built in the browser (each row costs a slider, scene nodes and symbolic work
for every redraw; real arms have at most a dozen joints)."""


def build(table: Table, tr: Translator | None = None) -> Robot:
    """The robot of ``table`` (named :data:`FILE_STEM`), its numbers read in ``tr``'s language.

    Raises:
        TableError: a bad field, more than :data:`MAX_ROWS` rows, or a table :meth:`Robot.from_dh`
            rejects (its message kept).
    """
    tr = tr or translations()
    _ = tr.gettext
    if len(table.rows) > MAX_ROWS:
        message = _("a table has at most {most} rows, this one has {rows}")
        raise TableError(0, "rows", message.format(most=MAX_ROWS, rows=len(table.rows)), tr)
    if table.convention not in CONVENTIONS:
        message = _("expected standard or modified, got {value}").format(value=repr(table.convention))
        raise TableError(0, "convention", message, tr)
    rows = rows_si(table, tr)
    same_joints = tuple(r.joint for r in table.rows) == table.kinds
    try:
        robot = Robot.from_dh(
            rows,
            table.convention,
            table.base,
            table.tool,
            FILE_STEM,
            title="Robot built in the browser",
            description="A DH table edited in the Build tab"
            + (f" (from {table.source})." if table.source else "."),
            source="Jacobian Lab, Build tab",
            configurations=table.configurations if same_joints else (),
        )
        if is_planar_chain(robot):  # all axes along base z: its task is the planar rows, as the library's
            robot = dataclasses.replace(robot, planar=True)
        return robot
    except RobotDefinitionError as exc:
        text = str(exc)
        row = next((i + 1 for i in range(len(rows)) if f"DH row {i + 1}," in text), 0)
        field = next((k for k in ("alpha", "theta", "qlim", "a", "d") if f"key '{k}'" in text), "table")
        raise TableError(row, "lo" if field == "qlim" else field, text, tr) from None


# ---------------------------------------------------------------------- robot files
FILE_HEADER = (
    "A robot built in the Jacobian Lab (Build tab). Lengths in metres; alpha, theta,",
    "revolute limits and base/tool rpy in DEGREES (the format of robots/data/puma560.toml).",
)


def robot_toml(robot: Robot, name: str = FILE_STEM) -> str:
    """``robot`` as a robot file of the library (:func:`robots.dumps`), saved as ``{name}.toml``.

    Raises:
        RobotDefinitionError: the robot has no DH table.
    """
    return robots.dumps(robot, name=name, header=FILE_HEADER)


def robot_file(robot: Robot, label: str) -> tuple[str, bytes] | None:
    """The download ``label`` of ``robot`` as (file name, bytes); ``None`` for a label not in
    :data:`ROBOT_FILE_FORMATS` (the symbolic J exports)."""
    if label == "Robot file (TOML)":
        return f"{FILE_STEM}.toml", robot_toml(robot).encode("utf-8")
    if label == "URDF":
        stem = "".join(c if c.isalnum() or c in "-_" else "_" for c in robot.name)[:40] or "robot"
        return f"{stem}.urdf", to_urdf(robot).encode("utf-8")
    return None


# ---------------------------------------------------------------------- the reducer's rule
def edited_state(state: LabState, name: str, robot: Robot, keep: tuple[int | None, ...]) -> LabState:
    """The state after the table was edited into ``robot`` (listed as ``name``).

    ``keep[i]``: the joint of the current robot whose value row ``i`` keeps (``None``: a new row,
    at the new robot's home). Values are kept only when the tab already shows the robot being
    edited and the joint type is unchanged, clamped to the new slider. The display choices stay
    unless the task rows changed; the applied force and the desired twist stay.
    """
    old = state.robot
    same = state.robot_name == name
    q = np.array(robot.home, dtype=float)
    ranges = joint_ranges(robot)
    for i, k in enumerate(keep[: robot.dof]):
        if same and k is not None and 0 <= k < old.dof and old.joints[k].kind == robot.joints[i].kind:
            q[i] = ranges[i].clamp_si(float(state.q[k]))
    keep_options = same and old.dof == robot.dof and task_rows(old) == task_rows(robot)
    options = state.options if keep_options else default_options(robot, state.options)
    fresh = LabState.initial(name, robot, options)
    return fresh.replace(
        q=frozen(q),
        options=options,
        v_desired=state.v_desired,
        wrench=state.wrench,
        configuration="home" if np.array_equal(q, robot.home) and fresh.configuration else "",
    )
