"""The app in a subprocess of its own session, and /proc scans of its processes (Linux), for tests."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

from fakes import POLL_TIMEOUT
from locations import ROOT


def proc_stat(pid: int) -> list[str] | None:
    """Fields of /proc/PID/stat after the command name (state, ppid, pgrp, session, ...), or None."""
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except (FileNotFoundError, ProcessLookupError):
        return None


def alive(pid: int) -> bool:
    fields = proc_stat(pid)
    return fields is not None and fields[0] not in ("Z", "X")


def session_processes(sid: int) -> list[int]:
    """Live processes of session ``sid`` (the server and every descendant, even re-parented ones)."""
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            fields = proc_stat(int(entry.name))
            if fields is not None and fields[0] not in ("Z", "X") and int(fields[3]) == sid:
                found.append(int(entry.name))
    return found


def children(pid: int) -> list[int]:
    """Live direct children of ``pid``."""
    return [
        p
        for p in session_processes(os.getsid(pid))
        if p != pid and (proc_stat(p) or ["", "0"])[1] == str(pid)
    ]


def cmdline(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode()
    except FileNotFoundError:
        return ""


class Server:
    """The app in a subprocess of its own session, with its log in a file: ``code`` run by ``python -c``,
    or ``argv``, the command line's arguments as a user types them after ``jacobian-lab`` (run as
    ``python -m app.cli.main``, the console script's entry point), in the folder ``cwd``."""

    def __init__(
        self, tmp_path: Path, code: str = "", argv: list[str] | None = None, cwd: Path = ROOT
    ) -> None:
        self.log = tmp_path / "server.log"
        command = ["-m", "app.cli.main", *argv] if argv is not None else ["-c", code]
        with open(self.log, "wb") as log:
            self.proc = subprocess.Popen(
                [sys.executable, "-u", *command],
                stdout=subprocess.PIPE,
                stderr=log,
                text=True,
                cwd=cwd,
                env=dict(os.environ, PYTHONPATH=str(ROOT)),
                start_new_session=True,
            )
        self.out: list[str] = []
        assert self.proc.stdout is not None
        match = None
        for line in self.proc.stdout:  # until the URL is printed (or the process ends)
            self.out.append(line)
            match = re.search(r"open http://[^\s/]+:(\d+) in a browser", line)
            if match:
                break
        if not match:
            self.proc.kill()
            raise AssertionError(f"no URL printed: {self.out}; log: {self.log.read_text()[-2000:]}")
        self.port = int(match.group(1))
        self.pid = self.proc.pid
        # Keep reading what it prints (a full pipe would block the server).
        threading.Thread(target=lambda: self.out.extend(self.proc.stdout), daemon=True).start()

    def url(self) -> str:
        return f"ws://127.0.0.1:{self.port}"

    def workers(self) -> list[int]:
        return [p for p in children(self.pid) if "spawn_main" in cmdline(p)]

    def cleanup(self) -> None:
        for pid in session_processes(self.pid):
            os.kill(pid, signal.SIGKILL)
        self.proc.wait(POLL_TIMEOUT)


def rss_bytes(pid: int, field: str = "VmRSS") -> int:
    """Resident memory of process ``pid`` [bytes]: now (``VmRSS``) or its peak so far (``VmHWM``)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith(field + ":"):
            return int(line.split()[1]) * 1024
    raise ValueError(f"no {field} for process {pid}")


def tree_pss_bytes(pid: int) -> int:
    """PSS of process ``pid``'s session (a :class:`Server` and every process it started) [bytes]: a
    page shared by k processes counts 1/k in each, so the sum is what the server costs the machine."""
    total = 0
    for p in session_processes(os.getsid(pid)):
        try:
            text = Path(f"/proc/{p}/smaps_rollup").read_text()
        except OSError:  # the process just ended
            continue
        total += sum(int(line.split()[1]) for line in text.splitlines() if line.startswith("Pss:"))
    return total * 1024


class TreeMemory:
    """The whole tree's PSS sampled in a thread every ``every`` seconds while a test runs."""

    def __init__(self, pid: int, every: float = 0.2) -> None:
        self.pid, self.every = pid, every
        self.samples: list[tuple[float, int]] = []
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True, name="tree-memory")

    def __enter__(self) -> TreeMemory:
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join(10)

    def _run(self) -> None:
        start = time.monotonic()
        while not self._stop.wait(self.every):
            self.samples.append((time.monotonic() - start, tree_pss_bytes(self.pid)))

    def peak(self) -> int:
        return max((b for _, b in self.samples), default=0)


def printed_presenter_link(server: Server) -> str:
    """The presenter link ``serve`` printed ("open LINK in the tab …"), polled from its output."""
    from fakes import poll

    said = poll(
        lambda: next(
            (m for line in list(server.out) if (m := re.search(r"open (\S+) in the tab", line))), None
        ),
        what="the presenter link printed",
    )
    return said.group(1)
