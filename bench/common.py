"""What the benches share: the CPU time, thread hand-offs and memory of a server and all its processes,
its worker processes and their connections, from /proc (Linux), and viser's frames decoded and messages
encoded."""

from __future__ import annotations

import os
import re
from pathlib import Path

import msgspec.msgpack
import zstandard

__all__ = [
    "tree",
    "cpu_seconds",
    "switches",
    "memory",
    "rollup_kb",
    "worker_pids",
    "peer_ports",
    "identities",
    "still_running",
    "decode",
    "encode",
]

CLK_TCK = os.sysconf("SC_CLK_TCK")


def _stat(pid: int) -> list[str] | None:
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:  # the process just ended
        return None


def _parents() -> dict[int, int]:
    """Every live process: its parent's pid."""
    parents: dict[int, int] = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit() and (fields := _stat(int(entry.name))) is not None:
            parents[int(entry.name)] = int(fields[1])
    return parents


def tree(pid: int) -> list[int]:
    """``pid`` and every live descendant (the workers of ``serve --workers``, symbolic workers)."""
    parents = _parents()
    found, frontier = [pid], [pid]
    while frontier:
        frontier = [p for p, parent in parents.items() if parent in frontier]
        found += frontier
    return found


def cpu_seconds(pid: int) -> float:
    """User + system CPU time so far of process ``pid`` and its live descendants, with that of the
    children they have waited for [s]: a worker that ends during a run (killed, then joined by the
    server) still counts in a difference of two readings. (A process whose parent ended before it is
    waited for by another process: its time is lost.)"""
    total = 0
    for p in tree(pid):
        if (fields := _stat(p)) is not None:
            total += sum(int(f) for f in fields[11:15])  # utime stime cutime cstime
    return total / CLK_TCK


def switches(pid: int) -> int:
    """Voluntary context switches of every thread of process ``pid`` and its descendants so far."""
    total = 0
    for status in (s for p in tree(pid) for s in Path(f"/proc/{p}/task").glob("*/status")):
        try:
            text = status.read_text()
        except OSError:  # a thread that just ended
            continue
        total += int(re.search(r"^voluntary_ctxt_switches:\s*(\d+)", text, re.M).group(1))
    return total


def rollup_kb(text: str) -> dict[str, int]:
    """The ``Name: N kB`` lines of a /proc/PID/smaps_rollup text, by name [kB] (its first line, the
    address range, is not one of them)."""
    found: dict[str, int] = {}
    for line in text.splitlines():
        match = re.fullmatch(r"(\w+):\s+(\d+) kB", line.strip())
        if match:
            found[match.group(1)] = int(match.group(2))
    return found


def memory(pid: int) -> tuple[float, float, int]:
    """(PSS, RSS) [MB] summed over process ``pid`` and its live descendants, and how many processes.

    PSS (proportional set size) shares each page among the processes mapping it, so the sum is what the
    tree costs the machine; the RSS sum counts the pages the processes share (the interpreter, libraries,
    what a spawned worker inherits) once per process."""
    pss = rss = count = 0
    for p in tree(pid):
        try:
            fields = rollup_kb(Path(f"/proc/{p}/smaps_rollup").read_text())
        except OSError:  # the process just ended
            continue
        pss, rss, count = pss + fields.get("Pss", 0), rss + fields.get("Rss", 0), count + 1
    return pss / 1024, rss / 1024, count


def worker_pids(pid: int, port: int) -> list[int]:
    """The worker processes of ``jacobian-lab serve --workers N`` (N ≥ 2) running as ``pid`` on ``port``:
    its children that multiprocessing spawned (``spawn_main`` in their command line) and that hold a
    socket listening on ``port`` (on Linux each worker its own, in one ``SO_REUSEPORT`` group, once it
    serves; elsewhere the one they share). Its other children: multiprocessing's resource tracker
    (``resource_tracker``) and the one symbolic process it runs for all workers (spawned too, but it holds
    no listening socket). (With ``--workers 1`` the server serves from its own process.)"""
    found = []
    for child in (p for p, parent in _parents().items() if parent == pid):
        try:
            if b"spawn_main" in Path(f"/proc/{child}/cmdline").read_bytes() and _listens(child, port):
                found.append(child)
        except OSError:
            continue
    return sorted(found)


def _socket_inodes(pid: int) -> set[str]:
    inodes = set()
    for fd in Path(f"/proc/{pid}/fd").iterdir():
        try:
            link = os.readlink(fd)
        except OSError:
            continue
        if link.startswith("socket:["):
            inodes.add(link[8:-1])
    return inodes


def _listens(pid: int, port: int) -> bool:
    """Whether process ``pid`` holds a socket listening on TCP ``port`` (state 0A in /proc/net/tcp)."""
    inodes = _socket_inodes(pid)
    for table in ("tcp", "tcp6"):
        try:
            rows = Path(f"/proc/{pid}/net/{table}").read_text().splitlines()[1:]
        except OSError:
            continue
        for row in rows:
            cells = row.split()
            if int(cells[1].rsplit(":", 1)[1], 16) == port and cells[3] == "0A" and cells[9] in inodes:
                return True
    return False


def peer_ports(pid: int, port: int) -> set[int]:
    """The remote ports of the TCP connections that process ``pid`` holds on its local ``port`` (the
    tabs it serves: each tab's own port, ``local_address`` on the client side)."""
    try:
        inodes = _socket_inodes(pid)
    except OSError:
        return set()
    found = set()
    for table in ("tcp", "tcp6"):
        try:
            rows = Path(f"/proc/{pid}/net/{table}").read_text().splitlines()[1:]
        except OSError:
            continue
        for row in rows:  # sl local_address rem_address st tx:rx tr:tm retrnsmt uid timeout inode
            cells = row.split()
            local, remote = int(cells[1].rsplit(":", 1)[1], 16), int(cells[2].rsplit(":", 1)[1], 16)
            if local == port and remote and cells[9] in inodes:
                found.add(remote)
    return found


def identities(pids: list[int]) -> dict[int, str]:
    """Each live process of ``pids``: its start time (clock ticks after boot), which tells it from a later
    process given the same pid."""
    return {p: fields[19] for p in pids if (fields := _stat(p)) is not None}


def still_running(known: dict[int, str]) -> list[str]:
    """The processes of ``known`` (from :func:`identities`) still running (a zombie is not), each as
    ``pid command line``."""
    left = []
    for p, start in known.items():
        fields = _stat(p)
        if fields is not None and fields[19] == start and fields[0] != "Z":
            try:
                command = Path(f"/proc/{p}/cmdline").read_bytes().replace(b"\0", b" ").decode()
            except OSError:
                continue
            left.append(f"{p} {command.strip()}")
    return left


def decode(frame: bytes) -> list[dict]:
    """The messages of one server frame (binary buffers left out: only types and names are needed)."""
    raw_size = int.from_bytes(frame[:8], "little")
    size = int.from_bytes(frame[8:16], "little")
    inner = zstandard.ZstdDecompressor().decompress(frame[16 : 16 + size], max_output_size=raw_size)
    return msgspec.msgpack.decode(inner)["messages"]


def encode(message) -> bytes:
    return msgspec.msgpack.encode(message.as_serializable_dict())
