"""A classroom of tabs: slider change → redrawn scene latency with N tabs exploring at once.

Starts the app (the Panda; one process, or ``jacobian-lab serve --workers N`` with ``--workers``) for
every run, then connects N tabs from this process over viser's websocket protocol (no rendering), each
as a browser does: a camera message first, then its joint sliders and its first drawing. After
``--warmup`` seconds of unmeasured exploring, every tab moves its ``q2`` slider every ~200 ms (±50 ms)
for ``--seconds``. A sample is the time from sending a change to the first frame after it that carries
that tab's scene-node messages. Each tab reports its page loaded as the page script of a browser
does (no robot, q or tab in its address: it shows the first tab). Also printed: changes left
unanswered, the CPU of the server's whole process tree (``bench/common.py``) and of this client,
with the load average. ``--hostile`` adds a tab flooding slider changes; ``--limits`` installs
:func:`app.viser_adapter.install_message_limits` first.

``--memory`` adds the memory of the server's whole process tree (``bench/common.py``: the sum of PSS
from /proc/PID/smaps_rollup, and of RSS for comparison, in MB): idle (the first tab alone, once its
symbolic J has arrived) and the highest PSS read once a second over the window, with how many
processes. ``--kill-worker-at S`` (``--workers`` 2 or more) SIGKILLs, S seconds into the window, the
worker serving the most tabs (the workers are the serve process's spawned children, see
``bench.common.worker_pids``; which tabs each serves is read from its TCP connections); every tab
reconnects as viser's page does (at once, then every second, to the same address, as a new tab) and
goes on moving once drawn again. Then printed: the other tabs' p95 before the kill and in the 5 s
after, when the killed worker's tabs were drawn again and had a change answered (from the kill), how
many never came back (10 s after the window), the worker processes before and after (the new one
serving or not, from the server's log), how many of 20 new tabs opened at once after the window (once
the new worker serves) reach the restarted worker, and, after SIGTERM to the server, which of its
processes are still running. With ``--workers``, every run also prints how many tabs each worker serves
at the window's end.

Usage::

    python bench/bench_app_load.py                       # 10, 30, 60 tabs, 20 s each
    python bench/bench_app_load.py --tabs 60 --workers 1 2   # one process and two, side by side
    python bench/bench_app_load.py --tabs 30 --timeline --profile /tmp/prof   # where the time goes
    python bench/bench_app_load.py --tabs 60 --workers 1 2 4 --memory          # memory idle and loaded
    python bench/bench_app_load.py --tabs 60 --workers 2 4 --seconds 20 --kill-worker-at 5

Printed per run: p50/p95/p99/max latency, the server's CPU (% of one core), its CPU per slider change
[ms] and voluntary context switches per change; ``--timeline`` adds the p95 of every second,
``--profile`` samples the server with py-spy (``bench/profile_stacks.py``).

Target (issues 7 and 17): 60 tabs, p95 < 50 ms on a 2-core machine.
"""

from __future__ import annotations

import argparse
import asyncio
import multiprocessing
import os
import random
import re
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import viser
import websockets

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from app.viser_adapter import message_class  # noqa: E402
from bench.common import (  # noqa: E402
    cpu_seconds,
    decode,
    encode,
    identities,
    memory,
    peer_ports,
    still_running,
    switches,
    tree,
    worker_pids,
)


def start_server(
    robot: str,
    limits: bool,
    port: int = 0,
    root: Path | None = None,
    log: Path | None = None,
    workers: int | None = None,
    floor: int = 0,
) -> tuple[subprocess.Popen, int]:
    """The app (from the checkout ``root``, default this one) in its own process on ``port``; its port.

    ``workers``: None serves from one process with ``app.server.serve`` (as every version can); a number
    runs ``jacobian-lab serve --workers N``; ``floor`` (a number of messages per change): the bare viser
    server of ``bench/viser_floor.py`` instead of the app. The server's log (stderr) goes to ``log``
    (appended) when given, else nowhere."""
    pre = "from app.viser_adapter import install_message_limits; install_message_limits(); " if limits else ""
    code = (
        pre
        + f"from app.server import serve; serve(robot={robot!r}, host='127.0.0.1', port={port}, block=True)"
    )
    command = ["-c", code]
    if workers is not None:
        command = ["-m", "app.cli.main", "serve", "--robot", robot, "--port", str(port)]
        command += ["--workers", str(workers)]
    root = root or Path(__file__).resolve().parents[1]
    if floor:  # viser alone, sending what the app sends per change (bench/viser_floor.py)
        command = [
            str(Path(__file__).with_name("viser_floor.py")),
            "--port",
            str(port),
            "--messages",
            str(floor),
        ]
    env = dict(os.environ, PYTHONUNBUFFERED="1", PYTHONPATH=str(root))
    proc = subprocess.Popen(
        [sys.executable, "-u", *command],
        stdout=subprocess.PIPE,
        stderr=log.open("a") if log is not None else subprocess.DEVNULL,
        text=True,
        env=env,
        cwd=root,  # `python -c` and `-m` put the working folder first on sys.path: the app of `root`
    )
    assert proc.stdout is not None
    for line in proc.stdout:
        match = re.search(r"open http://127\.0\.0\.1:(\d+)", line)
        if match:
            return proc, int(match.group(1))
    proc.kill()
    raise RuntimeError("the server did not start")


CAMERA = encode(
    message_class("ViewerCameraMessage")(
        (1.0, 0.0, 0.0, 0.0), (2.0, -2.0, 1.5), 1.0, 0.01, 100.0, 600, 800, (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)
    )
)
UPDATE = message_class("GuiUpdateMessage")
PAGE_LOADED = '{"kind": "load", "address": "", "resume": "", "tab": ""}'
"""What a browser's page reports once connected (app/views/panel/page.py): no robot, q or tab in its
address, so it shows the first tab."""


RETRY = 1.0
"""Seconds between a closed tab's tries to reconnect (viser's client: at once, then every second, each
try given until the next one to open)."""


@dataclass
class Tab:
    """One simulated browser tab. With ``rejoin``, a tab whose connection closes reconnects to the same
    address as viser's page does (``RETRY``), sends its camera, reports its page loaded again (with no
    robot, q or tab in its address: a browser's page would report what the app wrote there) and goes
    on moving its slider once it has drawn its scene again."""

    ws: object = None
    url: str = ""
    rejoin: bool = False
    leaving: bool = False  # closed by the bench: no reconnecting
    task: asyncio.Task | None = None
    closed_at: float = 0.0  # when its connection closed (rejoin)
    back_at: float = 0.0  # when it drew its scene again after reconnecting
    answered_at: float = 0.0  # when the first change after reconnecting was answered
    lost: int = 0  # changes left unanswered when its connection closed
    slider: str | None = None
    report: str | None = None  # the panel's hidden input the page script reports through
    drawn: asyncio.Event = field(default_factory=asyncio.Event)
    pending: list[float] = field(default_factory=list)
    samples: list[float] = field(default_factory=list)
    sent_at: list[float] = field(default_factory=list)  # when each sample's change was sent
    symbolic_at: float = 0.0  # when the symbolic J (MathML) arrived
    sent: int = 0
    closed: bool = False
    measuring: bool = False
    error: str = ""

    async def connect(self, url: str, open_timeout: float = 60) -> None:
        self.url = url
        self.ws = await websockets.connect(
            url,
            subprotocols=[f"viser-v{viser.__version__}"],
            max_size=None,
            compression=None,
            open_timeout=open_timeout,
        )
        await self.ws.send(CAMERA)
        self.task = asyncio.get_running_loop().create_task(self.receive())

    async def receive(self) -> None:
        try:
            async for frame in self.ws:
                now = time.perf_counter()
                scene = False
                msgs = decode(frame)
                for m in msgs:
                    if m["type"] == "GuiSliderMessage" and m["props"]["label"].startswith("q2 "):
                        self.slider = m["uuid"]
                    if m["type"] == "GuiTextMessage" and m["props"]["label"] == "page" and not self.report:
                        self.report = m["uuid"]  # as a browser's page script: say the page loaded
                        await self.ws.send(encode(UPDATE(self.report, {"value": PAGE_LOADED})))
                    scene = scene or str(m.get("name", "")).startswith("/")
                    if not self.symbolic_at and "<math" in str(m.get("updates", {}).get("content", "")):
                        self.symbolic_at = now
                if (
                    scene
                    and self.slider is not None
                    and any(str(m.get("name", "")).startswith("/lab/") for m in msgs)
                ):
                    self.drawn.set()  # its own scene (not only the server's shared nodes) and its slider
                    if self.closed_at and not self.back_at:
                        self.back_at = now
                    if self.measuring:
                        if self.back_at and self.pending and not self.answered_at:
                            self.answered_at = now
                        self.samples += [(now - t) * 1e3 for t in self.pending]
                        self.sent_at += self.pending
                    self.pending.clear()
        except websockets.ConnectionClosed:
            pass
        except Exception as exc:  # a frame this client cannot read: say so instead of waiting forever
            self.error = f"{type(exc).__name__}: {exc}"
        if self.rejoin and not self.leaving and not self.error:
            self.task = asyncio.get_running_loop().create_task(self.reconnect())
        else:
            self.closed = True

    async def reconnect(self) -> None:
        """As viser's page: try at once, then every ``RETRY`` s, to the same address, as a new tab."""
        self.closed_at = self.closed_at or time.perf_counter()  # the first close (the kill) counts
        self.lost += len(self.pending)
        self.pending.clear()
        self.drawn.clear()
        self.slider = self.report = None
        while not self.leaving:
            tried = time.perf_counter()
            try:
                await self.connect(self.url, open_timeout=RETRY)
                return
            except (OSError, TimeoutError, websockets.InvalidHandshake, websockets.ConnectionClosed):
                await asyncio.sleep(max(0.0, RETRY - (time.perf_counter() - tried)))

    async def close(self) -> None:
        self.leaving = True
        await self.ws.close()

    async def change(self, value: float) -> None:
        self.pending.append(time.perf_counter())
        self.sent += 1
        await self.ws.send(encode(UPDATE(self.slider, {"value": value})))


async def explore(tab: Tab, end: float, rng: random.Random) -> None:
    """Move q2 every ~200 ms (±50 ms) until ``end``, like a student dragging it (not while the tab is
    reconnecting: until it has drawn its scene again)."""
    i = rng.randrange(60)
    while time.perf_counter() < end and not tab.closed:
        if tab.drawn.is_set():
            try:
                await tab.change(float(-30 + i % 60))
            except websockets.ConnectionClosed:
                pass  # its receiving task reconnects it (or ends it)
            i += 1
        await asyncio.sleep(rng.uniform(0.15, 0.25))


async def flood(url: str, seconds: float, out: multiprocessing.Queue, go) -> tuple[int, bool]:
    """One tab sending slider changes as fast as it can for ``seconds`` from ``go`` on; (sent, closed)."""
    tab = Tab()
    await tab.connect(url)
    await asyncio.wait_for(tab.drawn.wait(), 120)
    out.put("ready")
    await asyncio.to_thread(go.wait, 300)
    end = time.perf_counter() + seconds
    i = 0
    while time.perf_counter() < end and not tab.closed:
        try:
            await tab.change(float(-30 + i % 60))
        except websockets.ConnectionClosed:
            break
        i += 1
        if i % 50 == 0:
            await asyncio.sleep(0)
    closed = tab.closed
    await tab.ws.close()
    return tab.sent, closed


def flood_process(url: str, seconds: float, out: multiprocessing.Queue, go) -> None:
    """The hostile tab, in a process of its own (so that it does not slow the measuring client)."""
    out.put(asyncio.run(flood(url, seconds, out, go)))


AFTER_KILL = 5.0
"""Seconds after the kill over which the latency of the other tabs is reported."""

FRESH = 20
"""New tabs opened at once after the window of a ``--kill-worker-at`` run (how many reach the restarted
worker)."""


@dataclass
class WorkerKill:
    """``--kill-worker-at``: SIGKILL the worker of ``serve --workers`` serving the most tabs ``at`` s into
    the measured window; which tabs it served is read from the TCP connections each worker holds."""

    pid: int  # the serve process
    port: int
    at: float
    workers: int  # how many it serves with
    before: list[int] = field(default_factory=list)  # the worker pids at the kill
    spread: list[int] = field(default_factory=list)  # tabs per worker at the kill
    killed: int = 0
    killed_at: float = 0.0
    dead: set[int] = field(default_factory=set)  # the indices of the tabs the killed worker served

    async def fire(self, clients: list[Tab], t0: float) -> None:
        await asyncio.sleep(max(0.0, t0 + self.at - time.perf_counter()))
        self.before = await asyncio.to_thread(worker_pids, self.pid, self.port)
        if len(self.before) != self.workers:
            raise RuntimeError(f"{len(self.before)} worker processes found, {self.workers} expected")
        served = {w: await asyncio.to_thread(peer_ports, w, self.port) for w in self.before}
        self.spread = [len(served[w]) for w in self.before]
        self.killed = max(self.before, key=lambda w: len(served[w]))
        ports = {tab.ws.local_address[1]: i for i, tab in enumerate(clients)}
        self.dead = {ports[p] for p in served[self.killed] if p in ports}
        self.killed_at = time.perf_counter()
        os.kill(self.killed, signal.SIGKILL)

    async def fresh_tabs(self, url: str, log: Path | None, count: int = FRESH) -> tuple[int, int]:
        """After the window, once the restarted worker serves: ``count`` new tabs opening at once; how
        many of them it took, of how many (0, 0: it never served)."""
        new: list[int] = []
        end = time.perf_counter() + 60
        while not new and log is not None and time.perf_counter() < end:
            serving = set(map(int, re.findall(r"\(pid (\d+)\) serving", log.read_text())))
            after = await asyncio.to_thread(worker_pids, self.pid, self.port)
            new = [w for w in after if w not in self.before and w in serving]
            await asyncio.sleep(0.2)
        if not new:
            return 0, 0
        tabs = [Tab() for _ in range(count)]
        await asyncio.gather(*(t.connect(url) for t in tabs))
        await asyncio.wait_for(asyncio.gather(*(t.drawn.wait() for t in tabs)), 120)
        theirs = await asyncio.to_thread(peer_ports, new[0], self.port)
        took = sum(1 for t in tabs if t.ws.local_address[1] in theirs)
        for t in tabs:
            await t.close()
        return took, count

    def report(self, clients: list[Tab], t0: float, log: Path | None) -> dict:
        """What the room saw: the other tabs' latency before and after, when the killed worker's tabs
        were back, and whether the supervisor started a worker again (``log``: the server's log)."""
        k = self.killed_at

        def others(lo: float, hi: float) -> float:
            """p95 [ms] of the changes sent from ``lo`` to ``hi`` by the tabs of the other workers."""
            live = [t for i, t in enumerate(clients) if i not in self.dead]
            s = [x for t in live for x, w in zip(t.samples, t.sent_at, strict=True) if lo <= w < hi]
            return float(np.percentile(s, 95)) if s else np.nan

        dead = [clients[i] for i in self.dead]
        back = np.array([t.back_at - k for t in dead if t.back_at]) * 1e3
        answered = np.array([t.answered_at - k for t in dead if t.answered_at]) * 1e3
        after = worker_pids(self.pid, self.port)
        serving = set(map(int, re.findall(r"\(pid (\d+)\) serving", log.read_text()))) if log else set()
        return {
            "spread": self.spread,
            "dead": len(dead),
            "p95_before": others(t0, k),
            "p95_after": others(k, k + AFTER_KILL),
            "back_max": back.max() if len(back) else np.nan,
            "back_p95": np.percentile(back, 95) if len(back) else np.nan,
            "answered_max": answered.max() if len(answered) else np.nan,
            "never_back": sum(1 for t in dead if not t.back_at),
            "lost": sum(t.lost for t in dead),
            "others_closed": sum(1 for i, t in enumerate(clients) if i not in self.dead and t.closed_at),
            "workers_before": len(self.before),
            "workers_after": len(after),
            "new": [w for w in after if w not in self.before],
            "new_serving": [w for w in after if w not in self.before and w in serving],
            "spread_after": [len(peer_ports(w, self.port)) for w in after],
        }


@dataclass
class MemoryWatch:
    """``--memory``: the server tree's PSS and RSS (``bench/common.py``) with one tab, and at the highest
    PSS read once a second over the measured window."""

    pid: int
    idle: tuple[float, float, int] = (np.nan, np.nan, 0)
    peak: tuple[float, float, int] = (0.0, 0.0, 0)

    async def settle_idle(self, tab: Tab) -> None:
        """Once the one tab has its symbolic J (its worker's symbolic process started), or after 60 s."""
        end = time.perf_counter() + 60
        while not tab.symbolic_at and time.perf_counter() < end:
            await asyncio.sleep(0.1)
        await asyncio.sleep(1.0)
        self.idle = await asyncio.to_thread(memory, self.pid)

    async def watch(self, end: float) -> None:
        while time.perf_counter() < end:
            now = await asyncio.to_thread(memory, self.pid)
            if now[0] > self.peak[0]:
                self.peak = now
            await asyncio.sleep(1.0)


async def run(
    tabs: int,
    seconds: float,
    hostile: bool,
    port: int,
    pid: int,
    seed: int,
    warmup: float,
    profile: Path | None = None,
    together: bool = False,
    kill: WorkerKill | None = None,
    watch: MemoryWatch | None = None,
    log: Path | None = None,
) -> dict:
    url = f"ws://127.0.0.1:{port}"
    rng = random.Random(seed)
    clients = [Tab(rejoin=kill is not None) for _ in range(tabs)]
    if hostile:  # connects while the others do
        ctx = multiprocessing.get_context("spawn")
        out, go = ctx.Queue(), ctx.Event()
        flooder = ctx.Process(target=flood_process, args=(url, seconds, out, go))
        flooder.start()
    start = time.perf_counter()

    async def arrive(tab: Tab) -> None:
        await tab.connect(url)
        await asyncio.wait_for(tab.drawn.wait(), 300)

    if watch is not None:  # the first tab alone, for the idle figure
        await arrive(clients[0])
        await watch.settle_idle(clients[0])
    rest = clients[1:] if watch is not None else clients
    if together:  # every tab opens the page at the same moment (a class told "open the link now")
        await asyncio.gather(*(arrive(tab) for tab in rest))
    else:  # one after another, each once the previous one is drawn
        for tab in rest:
            await arrive(tab)
    connected = time.perf_counter()
    # Warm up (unmeasured): the first changes also meet one-off work (the symbolic J arriving).
    await asyncio.gather(*(explore(tab, time.perf_counter() + warmup, rng) for tab in clients))
    await asyncio.sleep(0.3)
    if hostile:
        assert await asyncio.to_thread(out.get, True, 120) == "ready"
    for tab in clients:
        tab.pending.clear()
        tab.sent = 0  # count the measured changes only
        tab.measuring = True
    spy = start_profile(pid, seconds, profile, tabs) if profile is not None else None
    cpu0, t0, own0, sw0 = cpu_seconds(pid), time.perf_counter(), time.process_time(), switches(pid)
    end = t0 + seconds
    if hostile:
        go.set()
    side = [kill.fire(clients, t0)] if kill is not None else []
    side += [watch.watch(end)] if watch is not None else []
    await asyncio.gather(*(explore(tab, end, rng) for tab in clients), *side)
    # Give late answers up to 5 s to arrive (and the killed worker's tabs 10 s to be back).
    deadline = time.perf_counter() + (10.0 if kill is not None else 5.0)

    def waiting() -> bool:
        away = kill is not None and any(not clients[i].back_at for i in kill.dead)
        return away or any(t.pending for t in clients)

    while waiting() and time.perf_counter() < deadline:
        await asyncio.sleep(0.02)
    wall = time.perf_counter() - t0
    cpu_s, switched = cpu_seconds(pid) - cpu0, switches(pid) - sw0
    cpu, own = cpu_s / wall * 100, (time.process_time() - own0) / wall * 100
    if spy is not None:
        await asyncio.to_thread(spy.wait, 60)
    samples = np.array([s for t in clients for s in t.samples])
    when = np.array([w - t0 for t in clients for w in t.sent_at])
    result: dict = {
        "changes": sum(t.sent for t in clients),
        "unanswered": sum(len(t.pending) for t in clients),
        "silent": [  # tabs with changes left unanswered: why (no q2 slider seen, closed, unreadable frame)
            f"tab {i}: {len(t.pending)} unanswered, slider {'seen' if t.slider else 'never seen'}, "
            f"{'closed' if t.closed else 'open'}{', ' + t.error if t.error else ''}"
            for i, t in enumerate(clients)
            if t.pending
        ],
        "samples": samples,
        "when": when,
        "connected": connected - t0,
        "first": start - t0,
        "symbolic": [t.symbolic_at - t0 for t in clients if t.symbolic_at],
        "cpu": cpu,
        "cpu_per_change": cpu_s / max(sum(t.sent for t in clients), 1) * 1e3,
        "switches_per_change": switched / max(sum(t.sent for t in clients), 1),
        "client_cpu": own,
    }
    workers = await asyncio.to_thread(worker_pids, pid, port)  # none when one process serves
    result["spread"] = [len(await asyncio.to_thread(peer_ports, w, port)) for w in workers]
    if kill is not None:
        result["kill"] = kill.report(clients, t0, log)
        result["kill"]["fresh"] = await kill.fresh_tabs(url, log)
    if watch is not None:
        result["memory"] = (watch.idle, watch.peak)
    if hostile:
        result["flood_sent"], result["flood_closed"] = await asyncio.to_thread(out.get, True, 60)
        flooder.join(10)
    for tab in clients:
        await tab.close()
    return result


def start_profile(pid: int, seconds: float, folder: Path, tabs: int) -> subprocess.Popen:
    """py-spy sampling the server ``pid`` for ``seconds`` (idle threads left out), writing collapsed
    stacks to ``folder/server-<tabs>.txt`` (``pip install py-spy``; read them with
    ``bench/profile_stacks.py``). Sampling costs the server a little CPU of its own."""
    folder.mkdir(parents=True, exist_ok=True)
    out = folder / f"server-{tabs}.txt"
    cmd = ["py-spy", "record", "-p", str(pid), "-d", str(int(seconds)), "-r", "100", "-f", "raw"]
    cmd += ["--gil", "--nonblocking", "-o", str(out)]  # only the thread holding the GIL: what queues
    return subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def stop_server(proc: subprocess.Popen) -> tuple[list[str], list[str]]:
    """SIGTERM the server and wait for it to exit (SIGKILL after 15 s); the processes of its tree (as
    it was just before) still running once it has exited, and 5 s later."""
    known = identities(tree(proc.pid))
    proc.terminate()
    try:
        proc.wait(15)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait(5)
    at_exit = still_running(known)
    end = time.monotonic() + 5.0
    while still_running(known) and time.monotonic() < end:
        time.sleep(0.1)
    return at_exit, still_running(known)


def kill_lines(k: dict, at: float, left: tuple[list[str], list[str]]) -> list[str]:
    """The ``--kill-worker-at`` report of one run, in words."""
    new = ", ".join(f"{w} ({'serving' if w in k['new_serving'] else 'not serving yet'})" for w in k["new"])
    return [
        f"kill at {at:g} s: SIGKILL to the worker serving {k['dead']} tabs "
        f"(tabs per worker {'+'.join(map(str, k['spread']))}); {k['lost']} of its changes lost",
        f"other tabs: p95 {k['p95_before']:.1f} ms before the kill, {k['p95_after']:.1f} ms in the "
        f"{AFTER_KILL:g} s after; {k['others_closed']} of them closed",
        f"killed worker's tabs: drawn again {k['back_max']:.0f} ms after the kill at most (p95 "
        f"{k['back_p95']:.0f}), first change answered after {k['answered_max']:.0f} ms at most; "
        f"{k['never_back']} never back",
        f"worker processes: {k['workers_before']} before, {k['workers_after']} after"
        + (f"; new: {new}" if new else "; none started again")
        + f"; tabs per worker after: {'+'.join(map(str, k['spread_after']))}",
        f"new tabs after the restart: {k['fresh'][0]} of {k['fresh'][1]} opened at once reached the "
        "restarted worker",
        f"after SIGTERM: {len(left[0])} of its processes running when it exited"
        + (f" ({', '.join(role(p) for p in left[0])})" if left[0] else "")
        + f", {len(left[1])} 5 s later"
        + "".join(f"; {p}" for p in left[1]),
    ]


def role(process: str) -> str:
    """A process of the server's tree (``pid command line``) in a word or two."""
    pid = process.split()[0]
    if "resource_tracker" in process:
        return f"{pid} multiprocessing's resource tracker"
    return f"{pid} {'a spawned worker' if 'spawn_main' in process else process}"


def timeline(when: np.ndarray, samples: np.ndarray, seconds: float) -> str:
    """p95 [ms] of the changes sent in each second of the window (where the slow ones are)."""
    cells = []
    for k in range(int(np.ceil(seconds))):
        s = samples[(when >= k) & (when < k + 1)]
        cells.append(f"{np.percentile(s, 95):.0f}" if len(s) else "-")
    return " ".join(cells)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tabs", type=int, nargs="+", default=[10, 30, 60])
    parser.add_argument("--seconds", type=float, default=20.0, help="measuring window per run [s]")
    parser.add_argument("--robot", default="panda")
    parser.add_argument("--hostile", action="store_true", help="add one tab flooding slider changes")
    parser.add_argument("--limits", action="store_true", help="install the message limits in the server")
    parser.add_argument("--warmup", type=float, default=3.0, help="unmeasured exploring first [s]")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--port", type=int, default=0, help="the server's port (0: a free one)")
    parser.add_argument(
        "--profile", type=Path, default=None, help="py-spy the server over the window into this folder"
    )
    parser.add_argument("--timeline", action="store_true", help="print p95 per second of the window")
    parser.add_argument(
        "--together", action="store_true", help="all tabs connect at once (else one after another)"
    )
    parser.add_argument(
        "--workers",
        type=int,
        nargs="+",
        default=None,
        help="serve with `jacobian-lab serve --workers N` for each N given (side by side; "
        "default: one process through app.server.serve)",
    )
    parser.add_argument("--server-log", type=Path, default=None, help="append the server's log to this file")
    parser.add_argument(
        "--memory",
        action="store_true",
        help="add the server tree's PSS and RSS [MB]: idle (one tab connected, its symbolic J shown) and "
        "the highest under load (read every second of the window)",
    )
    parser.add_argument(
        "--kill-worker-at",
        type=float,
        default=None,
        metavar="SECONDS",
        help="SIGKILL the worker serving the most tabs this far into the window (with --workers); the tabs "
        "reconnect as viser's page does; then say what the room saw and what is left after SIGTERM",
    )
    parser.add_argument(
        "--floor",
        type=int,
        nargs="*",
        default=None,
        metavar="MESSAGES",
        help="add runs against bench/viser_floor.py (viser alone, computing nothing, sending the first "
        "MESSAGES of the app's 14 messages per change; default 14) for each --tabs: what viser itself costs",
    )
    parser.add_argument(
        "--app-root",
        type=Path,
        default=None,
        help="serve the app of this checkout (e.g. to compare a baseline)",
    )
    args = parser.parse_args()
    if not all(1 <= k <= 14 for k in args.floor or []):
        parser.error("--floor takes message counts in [1, 14]")
    if not 1 <= args.seconds <= 120 or not all(1 <= n <= 200 for n in args.tabs):
        parser.error("--seconds must be in [1, 120] and --tabs in [1, 200]")
    kill_at = args.kill_worker_at
    if kill_at is not None and (min(args.workers or [1]) < 2 or not 0 < kill_at < args.seconds):
        parser.error("--kill-worker-at needs --workers 2 or more and a time inside the window (0, --seconds)")

    app = args.app_root or "this checkout"
    print(f"app {app}; robot {args.robot}, {args.seconds:g} s per run, {os.cpu_count()} CPUs; slider → scene")
    print(f"load average before: {Path('/proc/loadavg').read_text().split()[:3]}")
    columns: tuple[str, ...] = (
        "tabs",
        "hostile",
        "changes",
        "unanswered",
        "p50 ms",
        "p95 ms",
        "p99 ms",
        "max ms",
    )
    columns += ("CPU %", "ms/change", "switches", "client %")
    widths: tuple[int, ...] = (5, 8, 8, 10, 8, 8, 8, 8, 6, 9, 8, 8)
    if args.memory:  # [MB], the whole process tree; procs: how many processes idle → under load
        columns += ("idle PSS", "idle RSS", "load PSS", "load RSS", "procs")
        widths += (8, 8, 8, 8, 5)
    header = " ".join(f"{c:>{w}}" for c, w in zip(columns, widths, strict=True))
    print("workers " + header + ("   flood (sent, closed)" if args.hostile else ""))
    runs: list[tuple[int, int | str | None]] = [(n, w) for n in args.tabs for w in (args.workers or [None])]
    if args.floor is not None:
        floors = [f"floor{k}" for k in args.floor or [14]]
        runs = [run for n in args.tabs for run in [r for r in runs if r[0] == n] + [(n, f) for f in floors]]
    for n, workers in runs:
        log = args.server_log
        if args.kill_worker_at is not None and log is None:  # to see the restarted worker serve
            log = Path(tempfile.mkstemp(prefix="bench-app-load-", suffix=".log")[1])
        floor = int(workers[5:]) if isinstance(workers, str) else 0
        count = None if floor or workers is None else int(workers)
        proc, port = start_server(args.robot, args.limits, args.port, args.app_root, log, count, floor)
        kill = WorkerKill(proc.pid, port, kill_at, count) if kill_at is not None and count else None
        try:
            r = asyncio.run(
                run(
                    n,
                    args.seconds,
                    args.hostile,
                    port,
                    proc.pid,
                    args.seed,
                    args.warmup,
                    args.profile,
                    args.together,
                    kill,
                    MemoryWatch(proc.pid) if args.memory else None,
                    log,
                )
            )
        finally:
            left = stop_server(proc)
            if log is not None and log != args.server_log:
                log.unlink()
        s = r["samples"]
        p50, p95, p99 = np.percentile(s, [50, 95, 99]) if len(s) else (np.nan,) * 3
        mx = s.max() if len(s) else np.nan
        line = (
            f"{workers or '-':>7} {n:>5} {('yes' if args.hostile else 'no'):>8} "
            f"{r['changes']:>8} {r['unanswered']:>10} "
            f"{p50:>8.1f} {p95:>8.1f} {p99:>8.1f} {mx:>8.1f} {r['cpu']:>6.0f} {r['cpu_per_change']:>9.2f} "
            f"{r['switches_per_change']:>8.1f} "
            f"{r['client_cpu']:>8.0f}"
        )
        if args.memory:
            (ipss, irss, iprocs), (lpss, lrss, lprocs) = r["memory"]
            line += f" {ipss:>8.0f} {irss:>8.0f} {lpss:>8.0f} {lrss:>8.0f} {f'{iprocs}→{lprocs}':>5}"
        print(
            line
            + (f"   {r['flood_sent']}, {'closed' if r['flood_closed'] else 'open'}" if args.hostile else "")
        )
        for note in r["silent"][:5]:
            print(f"      {note}")
        if r["spread"]:
            print(f"      tabs per worker at the window's end: {'+'.join(map(str, r['spread']))}")
        if kill is not None:
            for note in kill_lines(r["kill"], kill.at, left):
                print(f"      {note}")
        elif left[1]:
            print(f"      after SIGTERM, left 5 s after the server exited: {'; '.join(left[1])}")
        if args.timeline and len(s):
            print(f"      p95 per second: {timeline(r['when'], s, args.seconds)}")
            got = r["symbolic"]
            print(
                f"      (s from the window's start) first tab {r['first']:.1f}, "
                f"all drawn {r['connected']:.1f}, "
                + (f"symbolic J at {min(got):.1f} … {max(got):.1f}" if got else "no symbolic J")
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
