"""What the benches share: the CPU time and thread hand-offs of a server and all its processes, from
/proc (Linux), and viser's frames decoded and messages encoded."""

from __future__ import annotations

import os
import re
from pathlib import Path

import msgspec.msgpack
import zstandard

__all__ = ["tree", "cpu_seconds", "switches", "decode", "encode"]

CLK_TCK = os.sysconf("SC_CLK_TCK")


def _stat(pid: int) -> list[str] | None:
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:  # the process just ended
        return None


def tree(pid: int) -> list[int]:
    """``pid`` and every live descendant (the workers of ``serve --workers``, symbolic workers)."""
    parents: dict[int, int] = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit() and (fields := _stat(int(entry.name))) is not None:
            parents[int(entry.name)] = int(fields[1])
    found, frontier = [pid], [pid]
    while frontier:
        frontier = [p for p, parent in parents.items() if parent in frontier]
        found += frontier
    return found


def cpu_seconds(pid: int) -> float:
    """User + system CPU time so far of process ``pid`` and its live descendants [s] (a descendant that
    ended during the run leaves its time in its parent's children counters, not counted here)."""
    total = 0
    for p in tree(pid):
        if (fields := _stat(p)) is not None:
            total += int(fields[11]) + int(fields[12])
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


def decode(frame: bytes) -> list[dict]:
    """The messages of one server frame (binary buffers left out: only types and names are needed)."""
    raw_size = int.from_bytes(frame[:8], "little")
    size = int.from_bytes(frame[8:16], "little")
    inner = zstandard.ZstdDecompressor().decompress(frame[16 : 16 + size], max_output_size=raw_size)
    return msgspec.msgpack.decode(inner)["messages"]


def encode(message) -> bytes:
    return msgspec.msgpack.encode(message.as_serializable_dict())
