"""``jacobian-lab serve --workers N``: one address, N server processes, a parent that supervises them.

A single Python process draws every tab under one interpreter lock, so one server saturates one core
(about 3.5 ms of CPU per slider change: 60 tabs moving a slider five times a second need more than a
core). Here the parent holds the port and starts N worker processes ("spawn", so it works the same on
Linux, macOS and Windows). Each worker runs a whole :class:`~app.server.Lab` that *accepts on a socket
the parent gives it* instead of binding its own port (:mod:`app.cli.sockets`): on Linux a socket of its
own in one ``SO_REUSEPORT`` group, the kernel spreading the new connections evenly over the workers
(a restarted worker's new socket takes its share at once); elsewhere one listening socket shared by
every worker (on Windows passed with ``socket.share`` by multiprocessing), the operating system handing
each connection to a worker waiting in ``accept``. A tab's websocket stays with the worker that
accepted it for its whole life (viser's page is the same from any worker).

The parent:

* prints the address once every worker is ready, and which worker is which process;
* restarts a worker that dies (its tabs lose their connection; viser's page reconnects by itself and
  lands on a live worker, as a new tab);
* keeps the symbolic pool of every worker (:class:`~app.services.symbolic_hub.SymbolicHub`);
* on Ctrl-C, SIGTERM or SIGHUP stops every worker and the symbolic processes at once (SIGTERM, one
  deadline for all, then a kill), and ends multiprocessing's resource tracker before it exits; a worker
  or symbolic process whose parent is gone (``kill -9``) exits by itself.

Classroom mode (a presenter token) spans every worker: the parent keeps the room
(:class:`~app.services.room.RoomHub`: the token and its tries, who presents, the follower counts) and
talks to each worker over a pipe of its own (:mod:`app.services.classroom_relay`), relaying the
presenter's states, camera and tab to the other workers. Only the parent knows the token.
"""

from __future__ import annotations

import logging
import os
import socket
import sys
from typing import Any

from app.services.catalog import DEFAULT_ROBOT
from app.services.classroom import presenter_link
from app.services.lifecycle import install_stop_signals

from .sockets import listening_socket, port_socket
from .supervision import KILL_WAIT, READY_TIMEOUT, STOP_GRACE, WORKER_CAP, WorkerPool

__all__ = [
    "WORKER_CAP",
    "READY_TIMEOUT",
    "STOP_GRACE",
    "KILL_WAIT",
    "default_workers",
    "listening_socket",
    "serve_workers",
    "WorkerPool",
]


def default_workers() -> int:
    """One worker per core this process may use, at most :data:`WORKER_CAP`."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:  # macOS, Windows
        cores = os.cpu_count() or 1
    return max(1, min(cores, WORKER_CAP))


def serve_workers(
    workers: int, lab_options: dict[str, Any], host: str, port: int, presenter_token: str | None = None
) -> int:
    """Serve the app from ``workers`` processes on one address until a stop signal, then end this
    process (status 0) once every worker, the symbolic processes and the resource tracker are gone.

    Raises:
        ValueError: the address cannot be listened on.
        RuntimeError: a worker could not start (e.g. the robot cannot be loaded).
    """
    logging.basicConfig(level=logging.INFO, format="%(levelname)s %(name)s: %(message)s")
    sock = port_socket(host, port)
    pool = WorkerPool(sock, workers, dict(lab_options, host=host), presenter_token)
    stopping: list[str] = []
    signals = install_stop_signals(lambda: stopping.append("stop"))
    try:
        pool.start()
        shown = host if host not in ("0.0.0.0", "::", "") else socket.gethostname()
        shown = f"[{shown}]" if ":" in shown else shown
        robot = lab_options.get("robot") or lab_options.get("urdf") or DEFAULT_ROBOT
        pids = " ".join(str(p) for p in pool.pids())
        print(f"Jacobian Lab: open http://{shown}:{pool.port} in a browser (robot: {robot}; {workers} worker "
              f"processes: {pids})", flush=True)  # fmt: skip
        if presenter_token:
            link = presenter_link(f"http://{shown}:{pool.port}", presenter_token)
            print(
                f"Classroom mode: open {link} in the tab you present from (keep the link off the "
                "projector; it fills in the presenter token, masked, and drops it from the address bar). "
                "Every other tab follows that one, in every worker.",
                flush=True,
            )
        pool.supervise(lambda: bool(stopping))
    finally:
        signals.restore()
        pool.stop()
    # Everything is stopped: end now, as a worker does. The interpreter's shutdown of this process's
    # threads (pipes, the symbolic pool's) took up to 3 s more on a busy machine, with nothing to do.
    logging.shutdown()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)
