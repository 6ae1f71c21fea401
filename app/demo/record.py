"""Demos that need no server: a motion into a singularity, recorded as a ``.viser`` file.

:func:`plan` chooses the motion (a robot file's first ``[[motions]]`` preset, else a smooth path from
home to its first named singular configuration, else home → the nearest singularity), :func:`play`
runs it on the app's own reducer (one :class:`~app.core.actions.Step` per frame), :func:`record` draws
every frame with the app's :class:`~app.views.scene.SceneView` on a private in-process viser server and
returns viser's recording, and :func:`write_demo` writes a folder any static web server can serve:
``index.html`` (sends the browser to the player), ``viser-client.html`` (viser's own client page,
one self-contained file), ``recording.viser`` and ``joint_rates.csv``.

Only the 3-D scene is recorded (viser records no GUI panel), so κ, the status and the joint rates
q̇ are drawn as a scene label above the arm, with a title label above it; the initial camera frames
every frame of the motion. The folder also keeps every frame's q and q̇ as numbers
(``joint_rates.csv``).
"""

from __future__ import annotations

import contextlib
import io
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import numpy as np
import viser

import robots
from kinematics import Robot
from kinematics.singularity import nearest

from ..core.actions import ApplyPreset, FollowPath, Play, Step
from ..core.i18n import Translator, translations
from ..core.motion_rules import resample
from ..core.reducer import reduce
from ..core.robot_texts import robot_title
from ..core.snapshot import Snapshot, compute
from ..core.state import LabState
from ..core.words import kind_word, status_words
from ..views.camera import FROM_ABOVE, View, facing, framing, in_view
from ..views.fmt import number
from ..views.scene import SceneView
from ..views.scene.geometry import finite
from .folder import CLIENT_PAGE, RATES, RECORDING, demo_files, embedded_page, write_demo
from .rates import rates_readout

__all__ = [
    "Demo",
    "Recording",
    "record_frames",
    "demo_files",
    "embedded_page",
    "quiet",
    "UnknownPreset",
    "plan",
    "check_preset",
    "play",
    "record",
    "write_demo",
    "readout",
    "RATES",
    "CLIENT_PAGE",
    "RECORDING",
    "DEFAULT_SECONDS",
    "DEFAULT_FPS",
    "LEAD",
]

DEFAULT_SECONDS = 15.0
DEFAULT_FPS = 30.0
LEAD = 1e-3
"""Time [s] of frame 0 in the file (the scene before it is the last frame; see :func:`record`)."""
ASPECT = 16 / 9
"""The canvas the initial camera is framed for (a projector, a course page's wide embed)."""


class UnknownPreset(ValueError):
    """``--preset`` names no preset of the robot (the message lists them)."""


@dataclass(frozen=True)
class Demo:
    """A motion ready to play.

    Attributes:
        title: What the title label says ("Unimation PUMA 560 — straight line into the wrist …").
        start: The state at the first frame, playing.
        kind: "preset", "configuration" (home → a named singular one) or "nearest".
    """

    title: str
    start: LabState
    kind: str


@dataclass(frozen=True, eq=False)
class Recording:
    """A recorded demo.

    Attributes:
        data: The ``.viser`` file's bytes.
        title: The demo's title.
        states: The state drawn at every frame (the first one at t = 0).
        fps: Frames per second (the recording sleeps 1/fps between frames).
        language: The code of the language its labels speak (``"en"``, ``"pt"``, ``"es"``, ``"pl"``).
    """

    data: bytes
    title: str
    states: tuple[LabState, ...]
    fps: float
    language: str = "en"

    @property
    def frames(self) -> int:
        return len(self.states)

    @property
    def duration(self) -> float:
        """Length of the motion [s] (the file is :data:`LEAD` longer)."""
        return (len(self.states) - 1) / self.fps


def plan(
    name: str, robot: Robot, preset: str | None = None, frames: int = 240, tr: Translator | None = None
) -> Demo:
    """The demo of ``robot`` (listed as ``name``, a library name or a robot file path).

    Args:
        preset: Name of a ``[[motions]]`` preset (default: the first one, if any).
        frames: Frames of a path demo (home → a singularity takes the whole recording).
        tr: The language of its title and of why it stops (English when None).

    Raises:
        UnknownPreset: ``preset`` is not one of the robot's presets.
    """
    tr = tr or translations()
    title = robot_title(robot, tr)
    state = LabState.initial(name, robot)
    presets = check_preset(name, robot, preset)
    if presets:
        p = next(p for p in presets if preset is None or p.name == preset)
        applied = reduce(
            state,
            ApplyPreset(p.name, tuple(map(float, p.q)), tuple(map(float, p.twist)), p.frame, p.speed),
        )
        return Demo(f"{title} — {p.name}", reduce(applied, Play(True, "resolved_rate")), "preset")
    steps = max(int(frames) - 1, 1)
    singular = next((c for c in robot.configurations if c.singular), None)
    if singular is not None:
        path = _eased(np.array([robot.home, singular.q], float), steps)
        kind = kind_word(singular.singular, tr)
        found = tr.gettext("at {configuration}: {kind} singularity").format(
            configuration=singular.name, kind=kind
        )
        heading = tr.gettext("{robot} — home → {configuration} ({kind} singularity)").format(
            robot=title, configuration=singular.name, kind=kind
        )
        return Demo(heading, reduce(state, FollowPath(_rows(path), found)), "configuration")
    result = nearest(robot, robot.home)
    kinds = " + ".join(kind_word(k, tr) for k in result.report.kinds) or tr.pgettext("status", "singular")
    path = _eased(np.asarray(result.path, float), steps)
    heading = tr.gettext("{robot} — home → the nearest singularity ({kinds})").format(
        robot=title, kinds=kinds
    )
    found = tr.gettext("nearest singularity: {kinds}").format(kinds=kinds)
    return Demo(heading, reduce(state, FollowPath(_rows(path), found)), "nearest")


def check_preset(name: str, robot: Robot, preset: str | None) -> tuple[robots.MotionPreset, ...]:
    """The robot's ``[[motions]]`` presets (none for a URDF), once ``preset`` is known to be one of them.

    Raises:
        UnknownPreset: ``preset`` is not one of them (the message lists their names).
    """
    presets = robots.motions(name) if not robot.urdf_path else ()
    names = [p.name for p in presets]
    if preset is not None and preset not in names:
        have = ", ".join(repr(n) for n in names) if names else "none"
        raise UnknownPreset(f"{robot.name} has no preset {preset!r}; its presets: {have}")
    return presets


def _rows(path: np.ndarray) -> tuple[tuple[float, ...], ...]:
    return tuple(tuple(float(x) for x in row) for row in path)


def _eased(path: np.ndarray, steps: int) -> np.ndarray:
    """``path`` (k, n) resampled to ``steps`` + 1 configurations, evenly in joint-space length, eased in
    and out (slow start, slow arrival), so a path of a few Newton iterates plays smoothly."""
    eased = resample(path, steps + 1, eased=True)
    return eased if eased is not None else np.repeat(np.asarray(path, float)[:1], steps + 1, axis=0)


def play(demo: Demo, seconds: float, fps: float) -> tuple[LabState, ...]:
    """The states of the demo's frames: Step(1/fps) on the app's reducer until the motion stops or
    ``seconds`` have passed (the frame where it stops is kept: it says why)."""
    frames = max(int(round(seconds * fps)), 1)
    state = demo.start
    out = [state]
    while state.playing and len(out) <= frames:
        state = reduce(state, Step(1.0 / fps))
        out.append(state)
    return tuple(out)


def readout(snap: Snapshot, state: LabState, tr: Translator | None = None) -> str:
    """The label under the title: "near singular: wrist   κ = 104" (and why the motion stopped), in
    ``tr``'s language."""
    tr = tr or translations()
    r = snap.report
    words = status_words(state.robot, r.status, tuple(r.kinds), state.configuration, tr)
    text = f"{words}   κ = {number(r.condition, tr=tr)}"
    return f"{text}   ·   {tr.gettext(state.stopped)}" if state.stopped and not state.playing else text


class _Labels:
    """The title and the live readout, one above the other above the arm (screen-size text)."""

    def __init__(self, scene: viser.SceneApi, title: str, at: np.ndarray) -> None:
        position = finite(at).astype(float)
        self.title = scene.add_label(
            "/demo/title", title, position=position, anchor="bottom-center", font_screen_scale=1.3
        )
        self.readout = scene.add_label(
            "/demo/readout", "", position=position, anchor="top-center", font_screen_scale=1.3
        )


@contextlib.contextmanager
def quiet() -> Iterator[None]:
    """Nothing printed inside: viser prints its URL and "Server stopped" with ``rich``, which writes to
    stdout in a terminal and straight into the cell's output in a notebook (past ``redirect_stdout``)."""
    import rich

    console = rich.get_console()  # viser's server thread prints "Server stopped": not a thread-local capture
    was, console.quiet = console.quiet, True
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            yield
    finally:
        console.quiet = was


def record(
    name: str,
    robot: Robot,
    preset: str | None = None,
    seconds: float = DEFAULT_SECONDS,
    fps: float = DEFAULT_FPS,
    tr: Translator | None = None,
) -> Recording:
    """Play the demo of ``robot`` (see :func:`plan`) and record its 3-D scene, frame by frame; its
    labels (title, status, κ, joint rates) in ``tr``'s language (English when None).

    A private viser server (127.0.0.1, a free port, no client ever connects) holds the scene; it is
    stopped before returning.
    """
    if not (np.isfinite(seconds) and seconds > 0 and np.isfinite(fps) and fps > 0):
        raise ValueError("seconds and fps must be positive numbers")
    demo = plan(name, robot, preset, frames=max(int(round(seconds * fps)), 1) + 1, tr=tr)
    states = play(demo, seconds, fps)
    return record_frames(demo.title, robot, states, [compute(s) for s in states], fps, tr)


def record_frames(
    title: str,
    robot: Robot,
    states: Sequence[LabState],
    snaps: Sequence[Snapshot],
    fps: float,
    tr: Translator | None = None,
) -> Recording:
    """Record the 3-D scene of ``states`` (drawn from ``snaps``), one frame every 1/``fps`` seconds:
    the demo of :func:`record`, or what a tab did (:class:`app.tab.recorder.TabRecorder`). Every state
    must be of ``robot``."""
    if not states or len(states) != len(snaps):
        raise ValueError("a recording needs one snapshot per state, and at least one state")
    with quiet():
        server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        view = SceneView(server, robot, root="/demo/lab", tr=tr)
        extents = []
        for snap, state in zip(snaps, states, strict=True):  # a dry run: what every frame draws
            view.update(snap, state)
            extents.append(view.extent)
        points = np.concatenate(extents)
        points = points[np.isfinite(points).all(axis=1)]
        size = view.size
        lo, hi = points.min(axis=0), points.max(axis=0)
        top = np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, hi[2] + 0.12 * size])
        labels = _Labels(server.scene, title, top)
        _frame_camera(server, np.vstack([points, top]), 0.18 * size, robot.planar)
        serializer = server.get_scene_serializer()
        # The file starts from the scene as the dry run left it (the last frame) and turns it into
        # frame 0 at LEAD: viser's player loops, and on its second pass only the changes after t = 0
        # bring the arm, its colours and the lost-direction glyphs back from the end to the start.
        for k, (snap, state) in enumerate(zip(snaps, states, strict=True)):
            serializer.insert_sleep(LEAD if k == 0 else 1.0 / fps)
            view.update(snap, state)
            rates = rates_readout(state, tr)  # a second line (viser's labels keep line breaks)
            labels.readout.text = readout(snap, state, tr) + (f"\n{rates}" if rates else "")
        data = serializer.serialize()
    finally:
        with quiet():
            server.stop()
    return Recording(data, title, tuple(states), float(fps), tr.code if tr is not None else "en")


def _frame_camera(server: viser.ViserServer, points: np.ndarray, pad: float, planar: bool) -> None:
    """The initial camera: looking across the plane the motion lies in (from above for a planar arm),
    everything in view on a 16:9 canvas."""
    camera = server.initial_camera
    guess = View(np.array([1.3, -1.5, 0.9]), np.zeros(3), np.array([0.0, 0, 1]), float(camera.fov), ASPECT)
    direction = FROM_ABOVE if planar else facing(points)
    position, look_at = framing(guess, points, direction, pad=pad)
    # framing() fits a bounding sphere (safe for any later view); a recording's frames are all known,
    # so move in until they fill the 16:9 view (to ``margin`` of its half-angles; pad kept as a margin).
    far = float(np.linalg.norm(position - look_at))
    near, margin = 0.0, 0.8
    offset = (position - look_at) / far
    for _ in range(30):
        mid = (near + far) / 2
        test = View(look_at + offset * mid, look_at, np.array([0.0, 0, 1]), guess.fov, ASPECT)
        if in_view(test, points, margin).all():
            far = mid
        else:
            near = mid
    position = look_at + offset * far
    camera.up = (0.0, 0.0, 1.0)
    camera.position = finite(position).astype(float)
    camera.look_at = finite(look_at).astype(float)
