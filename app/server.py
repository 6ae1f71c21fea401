"""Start the Jacobian Lab server: one viser server, one
:class:`~app.tab.session.ClientSession` per browser tab.

Example::

    from app.server import serve
    lab = serve(robot="panda", port=0, block=False)   # prints the URL
    ...
    lab.stop()
"""

from __future__ import annotations

import logging
import multiprocessing
import os
import socket
import sys
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path

import viser

from .core.i18n import CODES, is_language
from .services.catalog import RobotCatalog
from .services.classroom import Classroom, presenter_link
from .services.classroom_relay import RelayedClassroom, RoomChannel
from .services.lifecycle import check_listen_address, wait_for_stop
from .services.ratelimit import RoomLimits
from .services.renderer import Renderer
from .services.symbolic_service import SymbolicService
from .tab.session import ClientSession
from .viser_adapter import (
    allow_origins,
    client_address,
    client_header,
    install_fast_prop_casts,
    install_icon_cache,
    install_input_checks,
    install_loop_safe_events,
    install_message_limits,
    install_panel_ledger,
    install_shared_frames,
    listen_on,
    quiet_banner,
    share_owner,
    trusted_proxies,
    welcome_tabs,
)

__all__ = ["serve", "Lab"]

log = logging.getLogger(__name__)


class Lab:
    """A running Jacobian Lab: the viser server, the robot catalogue and the client sessions.

    Args:
        robot: Library robot (or robot file path) shown first; default
            :data:`app.services.catalog.DEFAULT_ROBOT`.
        urdf: URDF file shown first (listed in the dropdown beside the library).
        host: Address to listen on (127.0.0.1: this machine only; 0.0.0.0: the classroom network).
        port: Port; 0 picks a free one. A busy port makes viser try the next one.
        base_link, tip_link: The chain of a URDF to show (default: chosen by the loader).
        presenter_token: With a token, classroom mode: the tab that types it presents and every
            other tab follows (see :mod:`app.services.classroom`).
        allow_origin: Origins (``https://host[:port]``) of pages that may embed the lab and connect
            to it; by default only the lab's own page may (:mod:`app.viser_adapter.handshake`).
        symbolic: The service that computes the symbolic J, J⁻¹, steps and exports (default: a new
            :class:`~app.services.symbolic_service.SymbolicService` with worker processes). The lab
            closes it on :meth:`stop`. Tests pass an immediate in-process fake.
        listen_socket: A listening socket to accept on instead of binding ``host`` and ``port``
            (shared by the worker processes of ``jacobian-lab serve --workers N``).
        xacro_args: ``NAME -> VALUE`` arguments of a ``.xacro`` file given as ``urdf`` or ``robot``.
        package_dirs, package_path: ROS packages of that file by name (``--package NAME=DIR``) and
            folders holding packages (``--package-path DIR``), see :func:`robots.load`.
        room_pipe: A worker's end of its pipe to the parent of ``serve --workers N --presenter``: classroom
            mode whose token, presenter and follower count the parent keeps for every worker
            (:mod:`app.services.classroom_relay`); ``presenter_token`` is then not given.
        language: The room's language (``en``, ``pt``, ``es``, ``pl``): every tab speaks it unless it
            chose its own (``?lang=``, the Language menu); "" (default): each tab its browser's.
        trusted_proxy: Addresses or networks of reverse proxies whose ``X-Forwarded-For`` names the
            client (``--trusted-proxy``); any other peer's header is ignored.

    Raises:
        UnknownRobotError, RobotDefinitionError: the robot or file cannot be loaded
            (checked before the server starts).
    """

    def __init__(
        self,
        robot: str | None = None,
        urdf: str | None = None,
        host: str = "127.0.0.1",
        port: int = 8080,
        base_link: str | None = None,
        tip_link: str | None = None,
        presenter_token: str | None = None,
        allow_origin: Sequence[str] = (),
        symbolic: SymbolicService | None = None,
        listen_socket: socket.socket | None = None,
        xacro_args: Mapping[str, str] | None = None,
        room_pipe: object = None,
        language: str = "",
        trusted_proxy: Sequence[str] = (),
        package_dirs: Mapping[str, str] | None = None,
        package_path: Sequence[str] = (),
    ) -> None:
        if language and not is_language(language):  # before anything starts
            raise ValueError(f"no language {language!r}: choose one of {', '.join(CODES)}")
        self.trusted_proxies = trusted_proxies(trusted_proxy)
        files = [urdf] if urdf else []
        if robot and _is_path(robot):
            files.append(robot)
            robot = None
        self.catalog = RobotCatalog(
            files,
            base_link=base_link,
            tip_link=tip_link,
            xacro_args=xacro_args,
            package_dirs=package_dirs,
            package_path=package_path,
        )
        self.default_robot = robot or self.catalog.default()
        self.catalog.load(self.default_robot)  # fail before starting the server
        if listen_socket is None:
            check_listen_address(host, port)  # a clear error now, instead of a server that never listens
        self.allowed_origins = allow_origins(allow_origin)  # pages of other sites may not connect
        install_message_limits()  # what one websocket message and one tab may cost
        self.room = install_input_checks(RoomLimits())  # every value a tab sends, checked as it enters
        install_fast_prop_casts()
        install_panel_ledger()  # followers showing the same panel hold the same GUI ids (one frame for all)
        install_loop_safe_events()  # the renderer thread's sends never touch the event loop's waiters
        install_icon_cache()  # a class of tabs connecting at once would read viser's icon archive per icon
        install_shared_frames()  # a scene frame replayed to a room is serialised once, not once per tab
        self.symbolic = symbolic if symbolic is not None else SymbolicService()
        self.symbolic.on_restart(self._symbolic_restarted)
        self.host = host
        self.language = language
        if listen_socket is not None:  # one of several worker processes accepting on one socket
            port = listen_socket.getsockname()[1]
            listen_on(listen_socket)
        try:
            with quiet_banner():  # the address is printed once by serve() (or the supervisor)
                self.server = viser.ViserServer(host=host, port=port, verbose=False)
        finally:
            listen_on(None)
        self.server.scene.set_up_direction("+z")
        self.server.initial_camera.position = (1.3, -1.5, 0.9)
        self.server.initial_camera.look_at = (0.2, 0.0, 0.1)
        self.sessions: dict[int, ClientSession] = {}
        self.renderer = Renderer()
        self.classroom: Classroom | None = None
        if room_pipe is not None:
            channel = RoomChannel(room_pipe)
            self.classroom = RelayedClassroom(channel, self.catalog, address_of=self._address)
            channel.start()
        elif presenter_token:
            self.classroom = Classroom(presenter_token, address_of=self._address)
        self._gone: set[int] = set()
        self._lock = threading.Lock()
        self._session_hooks: list[Callable[[ClientSession], None]] = []
        self.server.on_client_connect(self._connect)
        self.server.on_client_disconnect(self._disconnect)
        if listen_socket is not None:
            welcome_tabs()  # built: the shared socket's tabs are served from now on

    @property
    def port(self) -> int:
        """The port actually bound."""
        return self.server.get_port()

    @property
    def url(self) -> str:
        """The address to open in a browser."""
        host = self.host
        if host in ("0.0.0.0", "::", ""):
            host = socket.gethostname()
        elif ":" in host:
            host = f"[{host}]"
        return f"http://{host}:{self.port}"

    def _connect(self, client: viser.ClientHandle) -> None:
        share_owner(client)  # every tab's scene one owner: a frame drawn for one tab is valid for all
        try:
            session = ClientSession(
                client,
                self.catalog,
                self.symbolic,
                self.default_robot,
                renderer=self.renderer,
                classroom=self.classroom,
                language=self.language,
                accept_language=client_header(self.server, client.client_id, "Accept-Language"),
                user_agent=client_header(self.server, client.client_id, "User-Agent"),
            )
        except Exception as exc:  # this client sees the error; the server and other clients carry on
            log.error("client %s: cannot start a session", client.client_id, exc_info=exc)
            try:
                client.add_notification(
                    "Jacobian Lab could not start", f"{type(exc).__name__}: {exc}", color="red"
                )
            except Exception:
                pass
            return
        with self._lock:
            # Closed while its session was being built: viser may already have dropped it.
            gone = client.client_id in self._gone or client.client_id not in self.server.get_clients()
            self._gone.discard(client.client_id)
            if not gone:
                self.sessions[client.client_id] = session
            open_tabs = len(self.sessions)
        log.info("tab %d connected (%d open in process %d)", client.client_id, open_tabs, os.getpid())
        if gone:  # the tab closed while its session was being built
            session.close()
            return
        if self.classroom is not None:
            self.classroom.join(client.client_id, session.following)
            self.classroom.questions.join(client.client_id, session.following)
        for hook in list(self._session_hooks):
            try:
                hook(session)
            except Exception as exc:  # one hook's error never stops the tab
                log.error("client %s: a session hook failed", client.client_id, exc_info=exc)

    def open_sessions(self) -> list[ClientSession]:
        """The sessions of the tabs open now."""
        with self._lock:
            return list(self.sessions.values())

    def on_session(self, hook: Callable[[ClientSession], None]) -> None:
        """Call ``hook(session)`` for every tab's session once it is running (a notebook follows them)."""
        self._session_hooks.append(hook)

    def _disconnect(self, client: viser.ClientHandle) -> None:
        with self._lock:
            session = self.sessions.pop(client.client_id, None)
            if session is None:
                self._gone.add(client.client_id)
        if session is not None:
            if self.classroom is not None:
                self.classroom.closed(client.client_id)
                self.classroom.questions.leave(client.client_id)
            session.close()

    def _address(self, client_id: int) -> str:
        return client_address(self.server, client_id, self.trusted_proxies)

    def _symbolic_restarted(self, notice: str) -> None:
        """Tell every tab that the symbolic worker stopped and was restarted (its request is retried)."""
        with self._lock:
            sessions = list(self.sessions.values())
        for session in sessions:
            session.notices.notify(session.notices.tr.gettext("Symbolic worker restarted"), notice)

    def session(self, timeout: float = 10.0) -> ClientSession:
        """The most recent client's session, waiting up to ``timeout`` seconds for one (for tests)."""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            with self._lock:
                if self.sessions:
                    return self.sessions[max(self.sessions)]
            time.sleep(0.02)
        raise TimeoutError("no client connected")

    def stop(self) -> None:
        """Stop the server, every tab's ticker and the symbolic workers."""
        with self._lock:
            sessions = list(self.sessions.values())
            self.sessions.clear()
        for session in sessions:
            session.close()
        self.renderer.close()
        with quiet_banner():
            self.server.stop()
        self.symbolic.close()


def _is_path(text: str) -> bool:
    return Path(text).suffix.lower() in (".toml", ".urdf", ".xacro") or "/" in text or "\\" in text


def serve(
    robot: str | None = None,
    urdf: str | None = None,
    host: str = "127.0.0.1",
    port: int = 8080,
    block: bool = True,
    base_link: str | None = None,
    tip_link: str | None = None,
    presenter_token: str | None = None,
    allow_origin: Sequence[str] = (),
    xacro_args: Mapping[str, str] | None = None,
    language: str = "",
    trusted_proxy: Sequence[str] = (),
    package_dirs: Mapping[str, str] | None = None,
    package_path: Sequence[str] = (),
) -> Lab:
    """Start the browser app and print its URL.

    Args:
        robot: Library robot shown first (default: the PUMA 560).
        urdf: A URDF file shown first instead (also listed in the robot dropdown).
        host: Address to listen on; 127.0.0.1 serves this machine only.
        port: Port (0 picks a free one).
        block: Serve until Ctrl-C (then stop and return); ``False`` returns the running :class:`Lab`.
        base_link, tip_link: The chain of a URDF to show (default: chosen by the loader).
        presenter_token: Classroom mode with this presenter token (see :class:`Lab`).
        allow_origin: Origins of pages that may embed the lab (see :class:`Lab`).
        language: The room's language (see :class:`Lab`).
        trusted_proxy: Reverse proxies whose ``X-Forwarded-For`` is read (see :class:`Lab`).
        xacro_args, package_dirs, package_path: A xacro file's arguments and the packages of the
            URDF or xacro file (see :class:`Lab`).

    From a script of your own, call it under ``if __name__ == "__main__":`` (the symbolic
    worker process imports the main script, as every "spawn" worker does).
    """
    if multiprocessing.parent_process() is not None:
        # The symbolic worker is started with "spawn", which imports the main script again.
        raise RuntimeError(
            "serve() was called while a worker process imported the main script: "
            "call it under `if __name__ == '__main__':`"
        )
    logging.basicConfig(level=logging.INFO, format="%(levelname)s %(name)s: %(message)s")
    logging.getLogger("websockets").setLevel(logging.WARNING)
    # The renderer and viser's event loop share the interpreter lock: hand it over every 1 ms instead of
    # 5 ms, so a redraw never holds back the sending of another tab's finished one for long.
    sys.setswitchinterval(0.001)
    lab = Lab(
        robot=robot,
        urdf=urdf,
        host=host,
        port=port,
        base_link=base_link,
        tip_link=tip_link,
        presenter_token=presenter_token,
        allow_origin=allow_origin,
        xacro_args=xacro_args,
        language=language,
        trusted_proxy=trusted_proxy,
        package_dirs=package_dirs,
        package_path=package_path,
    )
    print(f"Jacobian Lab: open {lab.url} in a browser (robot: {lab.default_robot})", flush=True)
    if presenter_token:
        link = presenter_link(lab.url, presenter_token)
        print(
            f"Classroom mode: open {link} in the tab you present from (keep the link off the "
            "projector; it fills in the presenter token, masked, and drops it from the address bar). "
            "Every other tab follows that one.",
            flush=True,
        )
    if not block:
        return lab
    wait_for_stop(lab.stop)  # Ctrl-C, SIGTERM or SIGHUP: stop the server and its worker, once
    return lab
