"""Record what a tab does (the presenter's demonstration) and hand it back as a demo that needs no
server: a zip of the folder :func:`app.demo.record.write_demo` writes.

A :class:`TabRecorder` subscribes to a session: every committed (state, snapshot) is kept with the
time it was drawn, up to :data:`MAX_SECONDS`. When stopped, the frames are resampled to a steady
:data:`FPS` (the state on screen at each tick) and drawn into a ``.viser`` recording by the same code
as ``jacobian-lab record``. Only the last robot's frames are kept (the scene of a recording is one
robot's).
"""

from __future__ import annotations

import io
import time
import zipfile
from collections.abc import Callable

from ..core.i18n import Translator
from ..core.snapshot import Snapshot
from ..core.state import LabState
from ..demo.record import demo_files, record_frames

__all__ = ["TabRecorder", "FPS", "MAX_SECONDS", "demo_zip"]

FPS = 30.0
MAX_SECONDS = 120.0
"""A recording stops growing after this long (about 3,600 frames)."""


class TabRecorder:
    """Frames of one tab, from :meth:`start` to :meth:`stop`.

    Args:
        subscribe: The session's ``subscribe`` (called with (state, snapshot) after every change).
        clock: Monotonic clock [s] (a fake one in tests).
    """

    def __init__(
        self,
        subscribe: Callable[[Callable[[LabState, Snapshot], None]], Callable[[], None]],
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self._subscribe = subscribe
        self._clock = clock
        self._unsubscribe: Callable[[], None] | None = None
        self.frames: list[tuple[float, LabState, Snapshot]] = []
        self._t0 = 0.0

    @property
    def recording(self) -> bool:
        return self._unsubscribe is not None

    def start(self, state: LabState, snapshot: Snapshot | None) -> None:
        """Start from what is on screen now."""
        self.frames = []
        self._t0 = self._clock()
        if snapshot is not None:
            self.frames.append((0.0, state, snapshot))
        self._unsubscribe = self._subscribe(self._take)

    def _take(self, state: LabState, snapshot: Snapshot) -> None:
        if self.frames and self.frames[-1][1] is state:
            return  # the same state drawn again (a redraw): nothing new to show
        t = self._clock() - self._t0
        if t <= MAX_SECONDS:
            self.frames.append((t, state, snapshot))

    def stop(self) -> list[tuple[LabState, Snapshot]]:
        """Stop; the frames resampled at :data:`FPS` (the last robot's only; at least one frame)."""
        if self._unsubscribe is not None:
            self._unsubscribe()
            self._unsubscribe = None
        frames = self.frames
        if not frames:
            return []
        robot = frames[-1][1].robot
        start = max((k for k, f in enumerate(frames) if f[1].robot is not robot), default=-1) + 1
        frames = frames[start:]
        t_first, t_last = frames[0][0], frames[-1][0]
        ticks = int((t_last - t_first) * FPS) + 1
        out, k = [], 0
        for i in range(ticks):
            t = t_first + i / FPS
            while k + 1 < len(frames) and frames[k + 1][0] <= t + 1e-9:
                k += 1
            out.append((frames[k][1], frames[k][2]))
        if k + 1 < len(frames):  # the recording ends on what was on screen when it stopped
            out.append((frames[-1][1], frames[-1][2]))
        return out


def demo_zip(frames: list[tuple[LabState, Snapshot]], title: str, tr: Translator | None = None) -> bytes:
    """A zip of the demo folder (index.html, the viser client page, recording.viser) of ``frames``, its
    3-D words in ``tr``'s language (the tab's)."""
    states = [s for s, _ in frames]
    snaps = [p for _, p in frames]
    recording = record_frames(title, states[-1].robot, states, snaps, FPS, tr)
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in demo_files(recording).items():
            z.writestr(f"jacobian-lab-demo/{name}", data)
    return buffer.getvalue()
