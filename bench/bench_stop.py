"""How long ``jacobian-lab serve`` takes to stop on SIGTERM, with a room connected and a symbolic computation
running, phase by phase (issue 26, item 4).

Each run starts ``jacobian-lab serve`` as a user does (one worker per core, the parent, its one symbolic
process; ``--workers`` to choose), connects ``--tabs`` tabs over viser's websocket protocol (the load
bench's :class:`bench_app_load.Tab`) and waits until each has drawn its robot; they move a slider every
~200 ms from then on. One more tab then ticks
"Course letters" (the Panda's J with l₁, d₃ … and its det: seconds in the symbolic process); once the
symbolic process is seen computing (its CPU time grows), the server gets SIGTERM. From then on /proc is
read every 5 ms: when each worker, the symbolic process and multiprocessing's resource tracker are gone,
when the parent exits, and when nothing of the tree is left. A run is "over" when something is still
there 3 s after the signal (the target).

Usage::

    python bench/bench_stop.py                 # 20 runs, 60 tabs, the Panda
    python bench/bench_stop.py --runs 3 --tabs 10

Printed per run: each phase's time after the signal [s] (``-``: that process was not there); then the
median and the highest of each, and how many runs stopped within 3 s.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import random
import re
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import viser
import websockets

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_app_load import CAMERA, UPDATE, Tab, explore  # noqa: E402

from bench.common import _stat, decode, encode, tree  # noqa: E402

TARGET = 3.0
"""Seconds within which every process of the server must be gone (issue 26)."""

LETTERS = "Course letters"
"""The label the checkbox of the course's letters starts with (app/core/options.py)."""


def start(robot: str, workers: int | None, log: Path) -> tuple[subprocess.Popen, int, set[int]]:
    """``jacobian-lab serve`` of this checkout on a free port, its log appended to ``log``; its port and
    its worker processes (as it prints them)."""
    root = Path(__file__).resolve().parents[1]
    command = [sys.executable, "-u", "-m", "app.cli.main", "serve", "--robot", robot, "--port", "0"]
    command += ["--workers", str(workers)] if workers else []
    proc = subprocess.Popen(
        command,
        stdout=subprocess.PIPE,
        stderr=log.open("a"),
        text=True,
        env=dict(os.environ, PYTHONPATH=str(root)),
        cwd=root,
    )
    assert proc.stdout is not None
    for line in proc.stdout:
        match = re.search(r"open http://127\.0\.0\.1:(\d+) .*processes: ([\d ]+)\)", line)
        if match:
            return proc, int(match.group(1)), set(map(int, match.group(2).split()))
    proc.kill()
    raise RuntimeError(f"the server did not start; see {log}")


def roles(pid: int, workers: set[int]) -> dict[int, str]:
    """The server's processes: ``parent``, ``worker``, ``symbolic``, ``tracker`` (multiprocessing's
    resource tracker), or ``other``."""
    found = {}
    for p in tree(pid):
        try:
            command = Path(f"/proc/{p}/cmdline").read_bytes()
        except OSError:
            continue
        if p == pid:
            found[p] = "parent"
        elif b"resource_tracker" in command:
            found[p] = "tracker"
        elif p in workers:
            found[p] = "worker"
        elif b"spawn_main" in command:
            found[p] = "symbolic"
        else:
            found[p] = "other"
    return found


def cpu(pid: int) -> int:
    fields = _stat(pid)
    return int(fields[11]) + int(fields[12]) if fields else -1


async def tick_letters(url: str) -> websockets.ClientConnection:
    """One more tab: its "Course letters" checkbox ticked (a symbolic computation of seconds)."""
    ws = await websockets.connect(url, subprotocols=[f"viser-v{viser.__version__}"], max_size=None)
    await ws.send(CAMERA)
    async for frame in ws:
        for m in decode(frame):
            if m["type"] == "GuiCheckboxMessage" and m["props"]["label"].startswith(LETTERS):
                await ws.send(encode_update(m["uuid"], True))
                return ws
    raise RuntimeError("no course-letters checkbox arrived")


def encode_update(uuid: str, value: object) -> bytes:
    return encode(UPDATE(uuid, {"value": value}))


async def one_run(robot: str, workers: int | None, tabs: int, log: Path) -> dict[str, float]:
    proc, port, pids = start(robot, workers, log)
    url = f"ws://127.0.0.1:{port}"
    try:
        clients = [Tab() for _ in range(tabs)]
        for tab in clients:
            await tab.connect(url)
        await asyncio.wait_for(asyncio.gather(*(t.drawn.wait() for t in clients)), 300)
        rng = random.Random(1)
        moving = [asyncio.create_task(explore(t, time.perf_counter() + 600, rng)) for t in clients]
        await asyncio.sleep(2.0)  # the room in use
        asker = await tick_letters(url)
        known = roles(proc.pid, pids)
        symbolic = [p for p, r in known.items() if r == "symbolic"]
        busy = False
        end = time.monotonic() + 30
        while symbolic and not busy and time.monotonic() < end:  # computing: its CPU time grows
            before = [cpu(p) for p in symbolic]
            await asyncio.sleep(0.05)
            busy = any(cpu(p) > b >= 0 for p, b in zip(symbolic, before, strict=True))
        known = roles(proc.pid, pids)
        t0 = time.perf_counter()
        os.kill(proc.pid, signal.SIGTERM)
        gone: dict[int, float] = {}
        exited = np.nan
        while len(gone) < len(known) and time.perf_counter() - t0 < 30:
            now = time.perf_counter() - t0
            if np.isnan(exited) and proc.poll() is not None:
                exited = now
            for p in known:
                fields = _stat(p)
                if p not in gone and (fields is None or fields[0] in ("Z", "X")):
                    gone[p] = now
            await asyncio.sleep(0.005)
        if proc.poll() is None:
            proc.wait(30)
        for tab in clients:
            tab.leaving = True
        for task in moving:
            task.cancel()
        await asyncio.gather(*(t.ws.close() for t in clients), asker.close(), return_exceptions=True)

        def last(role: str) -> float:
            times = [gone.get(p, np.inf) for p, r in known.items() if r == role]
            return max(times) if times else np.nan

        return {
            "busy": float(busy),
            "workers": last("worker"),
            "symbolic": last("symbolic"),
            "tracker": last("tracker"),
            "parent": min(exited, last("parent")) if np.isfinite(exited) else last("parent"),
            "all": max(gone.get(p, np.inf) for p in known),
            "processes": float(len(known)),
        }
    finally:
        if proc.poll() is None:
            for p in tree(proc.pid):
                os.kill(p, signal.SIGKILL)
            proc.wait(10)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=20)
    parser.add_argument("--tabs", type=int, default=60)
    parser.add_argument("--robot", default="panda")
    parser.add_argument("--workers", type=int, default=None, help="default: one per core, as `serve` does")
    args = parser.parse_args()
    log = Path(tempfile.mkdtemp(prefix="bench-stop-")) / "server.log"
    phases = ("workers", "symbolic", "tracker", "parent", "all")
    print(f"{args.runs} runs, {args.tabs} tabs, {args.robot}; seconds after SIGTERM until gone (log: {log})")
    print("run  computing  " + "  ".join(f"{p:>8}" for p in phases) + "  processes")
    results = []
    for run in range(1, args.runs + 1):
        r = asyncio.run(one_run(args.robot, args.workers, args.tabs, log))
        results.append(r)
        cells = "  ".join(f"{r[p]:8.2f}" if np.isfinite(r[p]) else f"{'-':>8}" for p in phases)
        print(f"{run:3d}  {'yes' if r['busy'] else 'no':>9}  {cells}  {int(r['processes']):9d}", flush=True)
    for name, fn in (("median", np.nanmedian), ("max", np.nanmax)):
        cells = "  ".join(f"{fn([r[p] for r in results]):8.2f}" for p in phases)
        print(f"{name:>14}  {cells}")
    within = sum(1 for r in results if r["all"] <= TARGET)
    print(f"stopped within {TARGET:g} s, nothing left: {within} of {len(results)} runs")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
