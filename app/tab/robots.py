"""One tab's robots: the shared catalogue plus the robots only this tab has (uploads, the Build tab's).

A :class:`TabCatalog` answers what the session asks a :class:`~app.services.catalog.RobotCatalog`
(``names``, ``load``, ``chains``, ``meshes``, ``presets``, ``load_chain``), with the tab's private
robots listed first. A private robot never reaches the shared catalogue, so other tabs never see
it in their dropdown, until :meth:`TabCatalog.share` puts it there (the seam for a presenter who
hands a student's robot to the room).

An uploaded URDF is read from its bytes only (:func:`kinematics.urdf.robot_from_urdf_string`:
lxml without entities or network, capped to :data:`MAX_UPLOAD_BYTES`): it has no folder, so
no mesh file is ever looked for, inside or outside anything; the arm is drawn as its DH-style
picture.
"""

from __future__ import annotations

import shutil
import tempfile
import threading
import unicodedata
from pathlib import Path

import robots
from kinematics import Robot
from kinematics.errors import UnknownRobotError, UrdfError
from kinematics.text import words
from kinematics.urdf import ChainInfo, robot_from_urdf_string
from kinematics.urdf.expand import xacro_leftover

from ..core.build_table import BUILT_NAME, robot_toml
from ..core.i18n import N_
from ..services.catalog import RobotCatalog
from ..viser_adapter import MAX_UPLOAD_BYTES

__all__ = [
    "TabCatalog",
    "MAX_UPLOAD_BYTES",
    "MAX_PRIVATE_ROBOTS",
    "MAX_UPLOAD_JOINTS",
    "MAX_UPLOAD_DOF",
    "display_name",
]

# Largest URDF a tab may upload [bytes] (real arm URDFs are a few to a few hundred kB): checked
# on the websocket before any part is buffered, and again here.
MAX_PRIVATE_ROBOTS = 8
MAX_UPLOAD_JOINTS = 200
_UNEXPANDED = N_(
    "{file} is unexpanded xacro (it holds {piece}). Expand it first (xacro {stem}.urdf.xacro > {stem}.urdf) "
    "and upload the .urdf, or start the lab with --urdf {stem}.urdf.xacro."
)
"""An uploaded .urdf with xacro left in it that does not parse (pybullet's husky.urdf: ``$(optenv …)``)."""
"""Most ``<joint>`` elements an uploaded URDF may have (real arms with hands have a few dozen)."""
MAX_UPLOAD_DOF = 24
"""Most moving joints of an uploaded robot's chain (each costs a slider and scene nodes per redraw)."""
"""Uploads one tab keeps (the oldest is forgotten first)."""
_SUFFIX = " (uploaded)"


def display_name(text: object, limit: int = 60) -> str:
    """``text`` as one printable line of at most ``limit`` characters (a file or robot name from a
    browser: lone surrogates and control characters replaced, so it can be logged and shown)."""
    # Category C: control and format characters, and lone surrogates (undecodable bytes).
    s = "".join("\ufffd" if unicodedata.category(c)[0] == "C" else c for c in str(text)).strip()
    return (s[: limit - 1] + "…" if len(s) > limit else s) or "unnamed"


class TabCatalog:
    """The robots one tab can choose: its own (uploaded, built) first, then the shared ones.

    Args:
        shared: The server's catalogue (library robots, files named on the command line).
    """

    def __init__(self, shared: RobotCatalog) -> None:
        self.shared = shared
        self._private: dict[str, Robot] = {}
        self._lock = threading.Lock()

    # ------------------------------------------------------------------ what the session asks
    def names(self) -> list[str]:
        """The tab's robot dropdown: its own robots, then the shared ones."""
        with self._lock:
            own = list(self._private)
        return [*own, *self.shared.names()]

    def load(self, name: str) -> Robot:
        with self._lock:
            robot = self._private.get(name)
        return robot if robot is not None else self.shared.load(name)

    def chains(self, name: str) -> list[ChainInfo]:
        return [] if self.is_private(name) else self.shared.chains(name)

    def load_chain(self, name: str, tip_link: str) -> Robot:
        if self.is_private(name):
            raise UnknownRobotError(f"{name!r} was uploaded by this tab: its default chain is the one shown")
        return self.shared.load_chain(name, tip_link)

    def meshes(self, name: str) -> tuple[int, list[str]]:
        return (0, []) if self.is_private(name) else self.shared.meshes(name)

    def presets(self, name: str) -> tuple[robots.MotionPreset, ...]:
        return () if self.is_private(name) else self.shared.presets(name)

    def default(self) -> str:
        return self.shared.default()

    def is_private(self, name: str) -> bool:
        with self._lock:
            return name in self._private

    # ------------------------------------------------------------------ the tab's own robots
    def remember_built(self, robot: Robot) -> str:
        """Keep the Build tab's latest robot under :data:`~app.core.build_table.BUILT_NAME` (so the
        dropdown can go back to it); returns that name."""
        with self._lock:
            self._private[BUILT_NAME] = robot
        return BUILT_NAME

    def add_upload(self, filename: str, content: bytes, refused_size: int = 0) -> str:
        """Read the uploaded URDF ``content`` into this tab's list; returns the name it is listed under.

        Raises:
            UrdfError: too large, not UTF-8, not well-formed XML, no serial chain… (file named).
        """
        shown = display_name(filename)
        if not isinstance(content, (bytes, bytearray)):
            raise UrdfError(f"upload {shown!r}: expected the file's bytes")
        size = max(len(content), refused_size)
        if size > MAX_UPLOAD_BYTES:
            raise UrdfError(
                f"upload {shown!r} is {size / 1e6:.1f} MB; a URDF upload may be at most "
                f"{MAX_UPLOAD_BYTES // (1024 * 1024)} MB"
            )
        if shown.lower().endswith(".xacro") or b"<xacro:" in bytes(content):
            raise UrdfError(
                f"upload {shown!r} is a xacro file: the server never expands an uploaded xacro (it is a "
                "program that may read files); expand it on your machine (xacro arm.urdf.xacro > arm.urdf) "
                "and upload the .urdf, or start the lab with --urdf arm.urdf.xacro"
            )
        joints = bytes(content).count(b"<joint")  # before parsing: an upper bound, cheap
        if joints > MAX_UPLOAD_JOINTS:
            raise UrdfError(
                f"upload {shown!r} has {joints} joints; an uploaded URDF may have at most {MAX_UPLOAD_JOINTS}"
            )
        stem = Path(shown).stem or "upload"
        try:
            robot = robot_from_urdf_string(bytes(content), name=stem)
        except UrdfError as exc:
            left = xacro_leftover(bytes(content))
            if left is not None:  # said in the tab's language (Notices.error)
                raise UrdfError(words(_UNEXPANDED, file=shown, piece=left, stem=stem.split(".")[0])) from None
            raise UrdfError(f"upload {shown!r}: {exc}") from None
        except RecursionError:
            raise UrdfError(f"upload {shown!r}: the XML is nested too deeply") from None
        if robot.dof > MAX_UPLOAD_DOF:
            raise UrdfError(
                f"upload {shown!r}: its chain has {robot.dof} moving joints; "
                f"at most {MAX_UPLOAD_DOF} are shown"
            )
        with self._lock:
            name = display_name(robot.name, 48) + _SUFFIX
            while name in self._private or name in self.shared.names():
                name = name[: -len(_SUFFIX)] + "′" + _SUFFIX
            uploads = [n for n in self._private if n != BUILT_NAME]
            if len(uploads) >= MAX_PRIVATE_ROBOTS:
                del self._private[uploads[0]]
            self._private[name] = robot
        return name

    def keep_shown(self, name: str, robot: Robot) -> bool:
        """List ``robot`` (shown by the presenter under ``name``) in this tab's own robots when the tab
        does not know it, so a follower can go back to it after exploring; returns whether it was new."""
        with self._lock:
            if name in self._private or name in self.shared.names():
                return False
            uploads = [n for n in self._private if n != BUILT_NAME]
            if len(uploads) >= MAX_PRIVATE_ROBOTS:
                del self._private[uploads[0]]
            self._private[name] = robot
            return True

    def share(self, name: str, folder: str | Path | None = None) -> str:
        """Put the tab's robot ``name`` into the shared catalogue (every tab's dropdown) and return its
        shared name: a presenter's "show everyone this robot". Built robots are written as a robot
        file, uploads as a URDF (:func:`kinematics.urdf.to_urdf`), into ``folder`` (default: a new
        temporary folder, left for the server's lifetime).

        Raises:
            UnknownRobotError: ``name`` is not one of this tab's robots.
        """
        robot = self.load(name) if self.is_private(name) else None
        if robot is None:
            raise UnknownRobotError(f"{name!r} is not a robot of this tab")
        where = Path(folder) if folder is not None else Path(tempfile.mkdtemp(prefix="jacobian-lab-shared-"))
        stem = "".join(c if c.isalnum() or c in "-_" else "_" for c in robot.name)[:40] or "robot"
        try:
            if robot.dh is not None:
                path = where / f"{stem}.toml"
                path.write_text(robot_toml(robot, stem), encoding="utf-8")
            else:
                from kinematics.urdf import to_urdf

                path = where / f"{stem}.urdf"
                path.write_text(to_urdf(robot), encoding="utf-8")
            return self.shared.add_file(path)
        except Exception:
            if folder is None:
                shutil.rmtree(where, ignore_errors=True)
            raise
