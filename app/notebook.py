"""Jacobian Lab in a Jupyter notebook: the live app in a cell, and a recorded demo with no server.

Example (one cell)::

    from app.notebook import show
    lab = show("puma560")          # the live app in the cell, served from this kernel
    lab.q, lab.J                   # what the cell shows, read from Python
    lab.set_q([0, 0.3, 0, 0, 0, 0])  # ... and set from Python: the cell's arm moves
    show("trr", lang="es")         # the panel in the Argentinian course's Spanish

:func:`show` starts a :class:`~app.server.Lab` on 127.0.0.1 and a free port in the kernel's own
process (stopped with the kernel, or by :meth:`NotebookLab.stop`) and displays it in an ``<iframe>``.
The framed page is the lab's own (``http://127.0.0.1:PORT``), so its websocket passes the Host and
Origin checks of :mod:`app.viser_adapter.handshake` unchanged: the notebook's page never connects to
the lab itself. Under JupyterHub (``JUPYTERHUB_SERVICE_PREFIX`` set) the cell frames the lab through
``jupyter-server-proxy`` at ``{prefix}proxy/{port}/`` on the notebook's own origin (:func:`proxied_url`).
When the notebook reaches the lab through another proxy (a remote VS Code), give the address the
browser uses as ``url`` and the notebook's origin as ``allow_origin``: that origin is then allowed
explicitly, and every other page still refused.

The cell keeps a still picture of its 3-D view (:meth:`NotebookLab.capture`) and frames the lab only
once it answers: a saved or reopened notebook with no lab shows that picture and a line on how to
start it again (:mod:`app.notebook_frame`).

:func:`show_recording` embeds a recorded demo (:func:`app.demo.record.record`) in a cell: the cell holds
the recording, and viser's player page is written once beside the notebook (:mod:`app.demo.player`).
"""

from __future__ import annotations

import atexit
import html
import os
import threading
import warnings
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any
from urllib.parse import urlsplit

import numpy as np

from kinematics import Robot

from .core.actions import SetConfiguration
from .core.reducer import reduce
from .core.snapshot import Snapshot, compute
from .core.state import LabState
from .demo.player import cell_html as player_cell
from .demo.player import server_player_url, write_player
from .demo.record import Recording, embedded_page, quiet
from .notebook_frame import cell_html, jpeg
from .server import Lab
from .tab.session import ClientSession

__all__ = [
    "NotebookLab",
    "show",
    "show_recording",
    "RecordingView",
    "DEFAULT_HEIGHT",
    "proxied_url",
    "hub_origin",
]

DEFAULT_HEIGHT = 620
"""Height of the cell's view [px]: the panel and the 3-D view side by side at a notebook's width."""


class NotebookLab:
    """A running lab shown in a notebook cell, with the library's state API.

    ``state``, ``snapshot``, ``q`` and ``J`` are what the cell shows: the latest state any of its tabs
    drew (a slider moved in the cell counts), or, before any tab connected, the notebook's own.
    :meth:`set_q` moves every tab of the lab (and any tab that connects later starts there).
    """

    def __init__(
        self, lab: Lab, height: int = DEFAULT_HEIGHT, url: str | None = None, lang: str = ""
    ) -> None:
        self.lab = lab
        self.height = int(height)
        self.url = url or f"http://127.0.0.1:{lab.port}/"
        self.lang = lang
        self.picture: bytes | None = None
        """The 3-D view as the cell's browser last rendered it (JPEG): the dead frame's still picture."""
        self._display: Any = None  # IPython's handle of the cell's output, updated with each picture
        name = lab.default_robot
        self._lock = threading.Lock()
        self._state = LabState.initial(name, lab.catalog.load(name))
        self._snapshot: Snapshot | None = None
        self._set = False  # whether set_q was called (a new tab then starts at the notebook's q)
        self._stopped = False
        lab.on_session(self._follow)
        atexit.register(self.stop)  # the kernel's end stops the server and its symbolic workers

    # ------------------------------------------------------------------ what the cell shows
    @property
    def state(self) -> LabState:
        """The frozen state on screen (:class:`~app.core.state.LabState`)."""
        with self._lock:
            return self._state

    @property
    def snapshot(self) -> Snapshot:
        """Everything computed from :attr:`state` (J, κ, the singularity report, the ellipsoids …)."""
        with self._lock:
            state, snap = self._state, self._snapshot
        if snap is None:
            snap = compute(state)
            with self._lock:
                if self._state is state:
                    self._snapshot = snap
        return snap

    @property
    def robot(self) -> Robot:
        return self.state.robot

    @property
    def q(self) -> np.ndarray:
        """Joint values (n,) [rad | m]."""
        return np.array(self.state.q, dtype=float)

    @property
    def J(self) -> np.ndarray:
        """Geometric Jacobian (6, n), rows [v; ω] in base axes."""
        return np.array(self.snapshot.J_base, dtype=float)

    def set_q(self, q: Sequence[float] | np.ndarray, wait: float = 5.0) -> np.ndarray:
        """Move the arm to ``q`` (n,) [rad | m] in every tab (clamped to the sliders like a drag), and
        wait up to ``wait`` seconds for the tabs to draw it; returns the joint values now shown.

        Raises:
            ValueError: ``q`` is not n finite numbers for the robot on screen.
        """
        values = np.asarray(q, dtype=float).reshape(-1)
        n = self.state.robot.dof
        if values.shape != (n,) or not np.isfinite(values).all():
            raise ValueError(f"q must be {n} finite numbers for {self.state.robot.name}, got {q!r}")
        action = SetConfiguration(tuple(float(v) for v in values))
        with self._lock:
            self._state, self._snapshot, self._set = reduce(self._state, action), None, True
        sessions = self.lab.open_sessions()
        for session in sessions:
            session.dispatch(action)
        for session in sessions:
            try:
                session.settle(wait)
            except TimeoutError:
                pass  # a slow tab draws it later; the notebook's state already says it
        # the cell's picture follows, in the background: a tab that is not rendering (hidden) cannot hold
        # set_q up
        threading.Thread(target=self.capture, args=(wait,), daemon=True).start()
        return self.q

    def capture(self, wait: float = 10.0) -> bytes | None:
        """Keep the 3-D view as an open tab renders it now as the cell's still picture (and update the
        cell's output with it); returns it (None: no tab answered within ``wait`` seconds)."""
        for session in self.lab.open_sessions():
            try:
                rgb = session.client.get_render(self.height, int(self.height * 16 / 9), timeout=wait)
            except Exception:  # a tab that closed or never rendered: the next one, or none
                continue
            picture = jpeg(rgb)
            if picture is None:
                return None
            self.picture = picture
            if self._display is not None:
                self._display.update(self._bundle(), raw=True)
            return picture
        return None

    def _follow(self, session: ClientSession) -> None:
        """A tab connected: it starts at the notebook's q (if set), and what it draws becomes the state."""
        with self._lock:
            start = self._state.q if self._set and self._state.robot is session.state.robot else None
        if start is not None:
            session.dispatch(SetConfiguration(tuple(float(v) for v in start)))
        session.subscribe(self._drawn)
        threading.Thread(target=self._first_picture, args=(session,), daemon=True).start()

    def _first_picture(self, session: ClientSession) -> None:
        try:
            session.settle(10.0)
        except TimeoutError:
            pass
        if not self._stopped:
            self.capture()

    def _drawn(self, state: LabState, snapshot: Snapshot) -> None:
        with self._lock:
            self._state, self._snapshot = state, snapshot

    # ------------------------------------------------------------------ the cell
    def _repr_html_(self) -> str:
        """The lab's iframe, swapped in when the lab answers; else the still picture and how to start
        it again (:mod:`app.notebook_frame`)."""
        title = f"Jacobian Lab: {self.state.robot.name}"
        return cell_html(self.url, title, self.height, self.picture, self.lang)

    def _ipython_display_(self) -> None:
        """Shown in a notebook: an output with a display id, so that each new picture updates it."""
        from IPython.display import display

        self._display = display(self._bundle(), raw=True, display_id=True)

    def _bundle(self) -> dict[str, str]:
        return {"text/html": self._repr_html_(), "text/plain": repr(self)}

    def __repr__(self) -> str:
        state = "stopped" if self._stopped else f"serving {self.url}"
        return f"<Jacobian Lab: {self.state.robot.name}, {state}>"

    def stop(self, wait: float = 5.0) -> None:
        """Stop the server and its symbolic workers; first keep the cell's last picture (waiting up to
        ``wait`` seconds for an open tab to render it): the cell then shows that picture and how to start
        the lab again."""
        if self._stopped:
            return
        self.capture(wait)  # the last picture of what the cell showed, kept in its output
        self._stopped = True
        atexit.unregister(self.stop)
        with quiet():  # viser's "Server stopped"
            self.lab.stop()


def proxied_url(port: int, environ: Mapping[str, str] | None = None) -> str | None:
    """The lab's address as a browser behind JupyterHub reaches it: ``jupyter-server-proxy``'s
    ``{JUPYTERHUB_SERVICE_PREFIX}proxy/{port}/``, a path on the notebook's own origin (None outside
    JupyterHub). The proxy passes the browser's ``Host`` and ``Origin`` on, and its websocket too."""
    env = os.environ if environ is None else environ
    prefix = env.get("JUPYTERHUB_SERVICE_PREFIX", "").strip()
    if not prefix:
        return None
    prefix = "/" + prefix.strip("/") + "/" if prefix.strip("/") else "/"
    return f"{prefix}proxy/{int(port)}/"


def hub_origin(environ: Mapping[str, str] | None = None) -> str | None:
    """The origin of JupyterHub's public address (``JUPYTERHUB_PUBLIC_URL``, set by JupyterHub ≥ 4
    when it knows it), whose pages a proxied lab must accept; None when not set or not a web address."""
    env = os.environ if environ is None else environ
    parts = urlsplit(env.get("JUPYTERHUB_PUBLIC_URL", "").strip())
    if parts.scheme not in ("http", "https") or not parts.netloc:
        return None
    return f"{parts.scheme}://{parts.netloc}"


def show(
    robot: str | None = None,
    urdf: str | None = None,
    *,
    height: int = DEFAULT_HEIGHT,
    port: int = 0,
    url: str | None = None,
    allow_origin: Sequence[str] = (),
    base_link: str | None = None,
    tip_link: str | None = None,
    xacro_args: Mapping[str, str] | None = None,
    lang: str = "",
) -> NotebookLab:
    """Start the app for ``robot`` (a library name or robot file) or ``urdf`` in this kernel and show
    it in the cell (the returned :class:`NotebookLab` displays itself as the cell's value).

    Args:
        height: Height of the cell's view [px].
        port: Port on 127.0.0.1 (0: a free one).
        url: The lab's address as the notebook's browser reaches it (default: under JupyterHub
            ``{JUPYTERHUB_SERVICE_PREFIX}proxy/PORT/`` through ``jupyter-server-proxy``, else
            ``http://127.0.0.1:PORT/``).
        allow_origin: Origins of pages allowed to connect besides the lab's own (a notebook behind a
            proxy: its own origin; under JupyterHub ``JUPYTERHUB_PUBLIC_URL``'s is added), as
            ``jacobian-lab serve --allow-origin``.
        base_link, tip_link, xacro_args: The chain of a URDF and a xacro file's arguments.
        lang: The language of the cell's panel (``"en"``, ``"pt"``, ``"es"``, ``"pl"``; default: the
            notebook browser's): the lab's room language, and the cell's address says it
            (``?lang=es``), as ``jacobian-lab serve --lang``.

    Raises:
        UnknownRobotError, RobotDefinitionError: the robot cannot be loaded.
        ValueError: ``lang`` is not one of the app's languages (the message lists them).
    """
    hub = hub_origin() if url is None and proxied_url(port) is not None else None
    if hub is not None:
        allow_origin = (*allow_origin, hub)
    with quiet():  # viser's banner: the cell shows the lab instead
        lab = Lab(
            robot=robot,
            urdf=urdf,
            host="127.0.0.1",
            port=port,
            base_link=base_link,
            tip_link=tip_link,
            allow_origin=allow_origin,
            xacro_args=xacro_args,
            language=lang,
        )
    address = url or proxied_url(lab.port) or f"http://127.0.0.1:{lab.port}/"
    if lang:
        address += ("&" if "?" in address else "?") + f"lang={lang}"
    return NotebookLab(lab, height=height, url=address, lang=lang)


class RecordingView:
    """A recorded demo as a cell's value: the recording, played by the player page written beside the
    notebook (:mod:`app.demo.player`); ``inline`` (no player written): the whole page in an
    ``<iframe srcdoc>``."""

    def __init__(
        self, recording: Recording, height: int = 480, player_url: str | None = None, inline: bool = False
    ) -> None:
        self.recording = recording
        self.height = int(height)
        self.player_url = player_url
        self.inline = inline

    def html(self) -> str:
        """The self-contained page (player and recording; save it as ``demo.html``: it plays from the
        file)."""
        return embedded_page(self.recording)

    def _repr_html_(self) -> str:
        if self.inline:
            page = html.escape(self.html(), quote=True)
            return (
                f'<iframe srcdoc="{page}" width="100%" height="{self.height}" '
                'style="border:1px solid #ddd;display:block" '
                f'title="{html.escape(self.recording.title, quote=True)}"></iframe>'
            )
        return player_cell(self.recording, self.height, self.player_url)

    def __repr__(self) -> str:
        r = self.recording
        return f"<recorded demo: {r.title}, {r.frames} frames, {r.duration:.1f} s>"


def show_recording(
    recording: Recording,
    height: int = 480,
    folder: str | os.PathLike[str] | None = None,
    inline: bool | None = None,
    environ: Mapping[str, str] | None = None,
) -> RecordingView:
    """Embed ``recording`` in the cell (the returned view displays itself as the cell's value).

    Writes the player into ``folder/jacobian-lab-player/`` (``folder``: the kernel's working directory,
    the notebook's folder) unless it is there already; the cell holds the recording alone. ``inline``:
    the whole page in the cell instead (819 kB more), for a front end that serves no file beside the
    notebook; ``None`` chooses it in VS Code and Colab (:func:`serves_no_files`). A folder that cannot
    be written gets the whole page too, with a warning.
    """
    if inline if inline is not None else serves_no_files(environ):
        return RecordingView(recording, height, inline=True)
    where = Path.cwd() if folder is None else Path(folder)
    try:
        write_player(where)
    except OSError as exc:
        warnings.warn(
            f"the demo's player cannot be written into {where} ({exc.strerror or exc}): the cell holds the "
            "whole player (819 kB more in the notebook)",
            stacklevel=2,
        )
        return RecordingView(recording, height, inline=True)
    return RecordingView(recording, height, server_player_url(where))


def serves_no_files(environ: Mapping[str, str] | None = None) -> bool:
    """The kernel runs under a front end whose outputs cannot frame a file beside the notebook: VS
    Code (its webview, ``VSCODE_PID``/``VSCODE_CWD`` in the kernel's environment) or Google Colab."""
    env = os.environ if environ is None else environ
    return "VSCODE_PID" in env or "VSCODE_CWD" in env or "COLAB_RELEASE_TAG" in env
