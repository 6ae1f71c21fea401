"""Classroom latency: a presenter's slider move → every follower's redrawn 3-D view, measured by
websocket clients of the running app.

Starts ``app.server.serve`` with a presenter token in a separate process (or, with ``--workers N``,
``jacobian-lab serve --workers N --presenter-token``: the followers then land on every worker), connects
one presenter (it types the token into "Presenter token", as a teacher would) and N followers (viser's
websocket protocol, no rendering), then moves the presenter's q2 slider every ``--period`` seconds. Each
sample is the time from sending the presenter's new value to one follower receiving the frame that
carries its redrawn arm (the batched update of ``/lab/arm/cylinders``): N samples per move. Also printed:
how the followers spread over the workers, the CPU of the server's whole process tree per presenter
move (``bench/common.py``), this client's CPU and the load average before and after. The followers'
websockets share a few event-loop threads (``--client-threads``) and this process's heap is frozen out of
the garbage collector once the room has joined: the samples time the app, not this process's own pauses.
Every tab reports its page loaded, as a browser's page script does (it shows the first tab).

Usage::

    python bench/bench_classroom.py                   # 30 and 60 followers, Panda
    python bench/bench_classroom.py --followers 10 30 --moves 40
    python bench/bench_classroom.py --followers 60 --workers 1 2   # one process and two, side by side
    python bench/bench_classroom.py --followers 60 150 300 --workers 2 --app-root /tmp/base   # before/after
    python bench/bench_classroom.py --followers 150 --workers 2 --screens 1 4 8   # a hall of mixed phones
    python bench/bench_classroom.py --followers 150 --workers 2 --orbit --period 0.1   # the presenter orbits

``--app-root DIR`` adds, for every run, the same run against the app of another checkout (a baseline), one
after the other, so the two are measured on the same machine at nearly the same load. Each row also gives
the server's CPU per move divided by the followers (the cost one follower adds), and the memory (PSS) of
the server's process tree once the room has joined.

Targets (issue 32): 300 followers at p95 ≤ 200 ms, none missed; ≤ 0.2 ms of server CPU per follower per move.
"""

from __future__ import annotations

import argparse
import collections
import gc
import json
import math
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]
from wsclient import ClientLoop, ViserWsClient  # noqa: E402  (a test helper, not part of the app)

from app.viser_adapter import message_class  # noqa: E402
from bench.common import cpu_seconds, memory  # noqa: E402

ARM_NODE = "/lab/arm/cylinders"
TOKEN = "bench-token"


def start_server(
    robot: str, workers: int | None, log: Path, app_root: Path = ROOT
) -> tuple[subprocess.Popen, int]:
    """The app (of ``app_root``) with a presenter token: one process (``workers`` None) or
    ``serve --workers N``."""
    code = f"from app.server import serve; serve(robot={robot!r}, port=0, presenter_token={TOKEN!r})"
    command = ["-c", code]
    if workers is not None:
        command = ["-m", "app.cli.main", "serve", "--robot", robot, "--port", "0", "--workers", str(workers)]
        command += ["--presenter-token", TOKEN]
    proc = subprocess.Popen(
        [sys.executable, "-u", *command],
        stdout=subprocess.PIPE,
        stderr=log.open("w"),
        text=True,
        cwd=str(app_root),
        env=dict(os.environ, PYTHONUNBUFFERED="1", PYTHONPATH=str(app_root)),
    )
    end = time.monotonic() + 60
    assert proc.stdout is not None
    while time.monotonic() < end:
        match = re.search(r"open http://[^:]+:(\d+)", proc.stdout.readline())
        if match:
            return proc, int(match.group(1))
        if proc.poll() is not None:
            break
    proc.kill()
    raise RuntimeError("the server did not start")


PAGE_LOADED = '{"kind": "load", "address": "", "resume": "", "tab": ""}'
"""What a browser's page reports once connected (app/views/panel/page.py): it shows the first tab."""


SCREENS = [(390, 844), (412, 915), (360, 800), (375, 667), (430, 932), (393, 873), (414, 896), (1280, 720)]
"""Windows [CSS px] followers report with ``--screens K`` (follower i the (i mod K)-th): phones upright
(Android and iPhone sizes), then a laptop. Labels are placed per screen, so followers of K screens share
K drawings per worker, not one."""


def view_report(width: int, height: int) -> str:
    """What a page reports of its window (app/views/panel/page.py), a phone's with touch."""
    return json.dumps({"kind": "view", "width": width, "height": height, "touch": width < 600})


def gui(ws: ViserWsClient, kind: str, label_start: str) -> str:
    _, msg = ws.wait_for(
        lambda m: m["type"] == kind and str(m["props"].get("label", "")).startswith(label_start), timeout=60
    )
    return msg["uuid"]


def is_arm_update(m: dict) -> bool:
    return m["type"] == "SceneNodeUpdateMessage" and m["name"] == ARM_NODE


def is_camera_update(m: dict) -> bool:
    return m["type"] == "SetCameraPositionMessage"


def turn_camera(ws: ViserWsClient, i: int) -> float:
    """The presenter's browser reports its camera turned ``i`` × 3° about the vertical (a drag); returns
    the send time."""
    a = math.radians(3.0 * (i + 1))
    position = (3.0 * math.cos(a), 3.0 * math.sin(a), 1.5)
    message = message_class("ViewerCameraMessage")(
        wxyz=(1.0, 0.0, 0.0, 0.0), position=position, fov=1.0, near=0.01, far=100.0,
        image_height=600, image_width=800, look_at=(0.0, 0.0, 0.3), up_direction=(0.0, 0.0, 1.0),
    )  # fmt: skip
    t = time.perf_counter()
    ws.send(message)
    return t


def spread(log: Path) -> list[int]:
    """Tabs connected per server process (from the log), most first."""
    pids = re.findall(r"tab \d+ connected \(\d+ open in process (\d+)\)", log.read_text())
    return sorted(collections.Counter(pids).values(), reverse=True)


def quiet_tree(pid: int, limit: float = 0.1, patience: float = 120.0) -> float:
    """Wait until the server's tree spends under ``limit`` of a core over a second (the room joined, the
    symbolic J computed); return the seconds waited (``patience`` at most)."""
    start = time.perf_counter()
    while time.perf_counter() - start < patience:
        before = cpu_seconds(pid)
        time.sleep(1.0)  # a sample of the tree's CPU over one second (a measurement, not a wait for a state)
        if cpu_seconds(pid) - before < limit:
            break
    return time.perf_counter() - start


def run(
    robot: str,
    followers: int,
    moves: int,
    period: float,
    workers: int | None,
    log: Path,
    app_root: Path,
    screens: int = 0,
    orbit: bool = False,
    client_threads: int = 0,
) -> dict:
    proc, port = start_server(robot, workers, log, app_root)
    url = f"ws://127.0.0.1:{port}"
    clients: list[ViserWsClient] = []
    loops = [ClientLoop() for _ in range(client_threads)] if client_threads else []
    try:
        presenter = ViserWsClient(url)
        presenter.start()
        clients.append(presenter)
        slider = gui(presenter, "GuiSliderMessage", "q2 ")
        presenter.set_value(gui(presenter, "GuiTextMessage", "page"), PAGE_LOADED)
        presenter.set_value(gui(presenter, "GuiTextMessage", "Presenter token"), TOKEN)
        presenter.wait_for(
            lambda m: m["type"] == "GuiUpdateMessage" and "You are presenting" in str(m.get("updates")),
            timeout=60,
        )
        room = []
        for i in range(followers):
            c = ViserWsClient(url, shared=loops[i % len(loops)] if loops else None)
            c.start(timeout=60)
            page = gui(c, "GuiTextMessage", "page")
            c.set_value(page, PAGE_LOADED)  # as its page script does
            if screens:  # and its window
                c.set_value(page, view_report(*SCREENS[i % screens]))
            clients.append(c)
            room.append(c)
        for c in room:  # each follower has drawn the presenter's arm once
            c.wait_for(is_arm_update, timeout=120)
        time.sleep(1.0)  # let the joining burst settle ...
        quiet = quiet_tree(proc.pid)  # ... and the symbolic J's computation (not a move's work)
        pss, _rss, _count = memory(proc.pid)
        # This process keeps every message its followers received: a full collection of that heap took up
        # to ~280 ms, during which no follower's frame was read (a whole move's samples late). What the
        # room has made so far is frozen out of the collector: its pauses are the clients', not the app's.
        gc.collect()
        gc.freeze()
        samples, missed = [], 0
        cpu0, own0, t0 = cpu_seconds(proc.pid), time.process_time(), time.perf_counter()
        for i in range(moves):
            marks = [c.mark() for c in room]
            value = float(-30.0 + (i % 60))
            sent = turn_camera(presenter, i) if orbit else presenter.set_value(slider, value)
            arrived = is_camera_update if orbit else is_arm_update
            for c, mark in zip(room, marks, strict=True):
                try:
                    received, _ = c.wait_for(arrived, after=mark, timeout=10)
                    samples.append((received - sent) * 1e3)
                except TimeoutError:
                    missed += 1
            time.sleep(max(0.0, period - (time.perf_counter() - sent)))
        wall = time.perf_counter() - t0
        cpu = cpu_seconds(proc.pid) - cpu0
        return {
            "samples": np.array(samples),
            "missed": missed,
            "cpu_per_move": cpu / moves * 1e3,
            "cpu": cpu / wall * 100,
            "client": (time.process_time() - own0) / wall * 100,
            "spread": spread(log),
            "pss": pss,
            "quiet": quiet,
        }
    finally:
        gc.unfreeze()
        for c in clients:
            c.close()
        for loop in loops:
            loop.close()
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robot", default="panda")
    parser.add_argument("--followers", type=int, nargs="+", default=[30, 60])
    parser.add_argument("--moves", type=int, default=30)
    parser.add_argument("--period", type=float, default=0.2, help="seconds between presenter moves")
    parser.add_argument(
        "--workers",
        type=int,
        nargs="+",
        default=None,
        help="serve with `jacobian-lab serve --workers N` for each N (default: one process)",
    )
    parser.add_argument(
        "--app-root", type=Path, default=None, help="also run the app of this checkout (a baseline) beside it"
    )
    parser.add_argument(
        "--screens",
        type=int,
        nargs="+",
        default=[0],
        help="followers report windows of K distinct screens (SCREENS), for each K; 0: none reported",
    )
    parser.add_argument(
        "--orbit",
        action="store_true",
        help="the presenter turns the camera instead (3° a move; each follower's camera update is timed)",
    )
    parser.add_argument(
        "--repeat",
        type=int,
        default=1,
        help="run every setting R times, the apps taking turns, and print each app's medians",
    )
    parser.add_argument(
        "--client-threads",
        type=int,
        default=4,
        help="the followers' websockets share this many event-loop threads (0: one thread each, as before"
        " 2026-12-06: hundreds of threads taking turns at this process's interpreter lock delay the samples)",
    )
    parser.add_argument("--log", type=Path, default=Path("/tmp/bench-classroom.log"), help="the server's log")
    args = parser.parse_args()
    what = "turns the camera 3°" if args.orbit else "moves q2"
    print(
        f"robot {args.robot}; presenter {what} every {args.period:g} s; {os.cpu_count()} CPUs; followers' "
        f"websockets on {args.client_threads or 'one each of their'} client thread(s)"
    )
    print(f"load average before: {' '.join(Path('/proc/loadavg').read_text().split()[:3])}")
    print(
        "app       screens workers followers  spread   p50 ms   p95 ms   max ms  missed  CPU %  ms/move"
        "  ms/follower/move  tree MB  client %  quiet s"
        "   (presenter slider → each follower's redrawn arm; CPU and memory (PSS): the server's process tree)"
    )
    roots = [("this", ROOT)] + ([("baseline", args.app_root.resolve())] if args.app_root else [])
    workers_ = args.workers or [None]
    runs = [
        (n, w, k, a)
        for n in args.followers
        for w in workers_
        for k in args.screens
        for _ in range(args.repeat)
        for a in roots
    ]
    results: dict[tuple, list[dict]] = collections.defaultdict(list)
    for n, workers, k, (app, root) in runs:
        r = run(
            args.robot,
            n,
            args.moves,
            args.period,
            workers,
            args.log,
            root,
            k,
            args.orbit,
            args.client_threads,
        )
        results[(n, workers, k, app)].append(r)
        s = r["samples"]
        p50, p95 = np.percentile(s, [50, 95]) if len(s) else (np.nan, np.nan)
        mx = s.max() if len(s) else np.nan
        spread_ = "+".join(str(k) for k in r["spread"])
        print(
            f"{app:9} {k or '-':>7} {workers or '-':>7} {n:9d} {spread_:>7} {p50:8.1f} {p95:8.1f} {mx:8.1f} "
            f"{r['missed']:7d} {r['cpu']:6.0f} {r['cpu_per_move']:8.1f} {r['cpu_per_move'] / n:17.3f} "
            f"{r['pss']:8.0f} {r['client']:9.0f} {r['quiet']:8.0f}",
            flush=True,
        )
    if args.repeat > 1:  # each app's medians over its runs (a busy moment in one run weighs less)
        print("medians     screens workers followers   p50 ms   p95 ms   max ms  missed  ms/follower/move")
        for (n, workers, k, app), rs in results.items():
            p50s = [np.percentile(r["samples"], 50) for r in rs if len(r["samples"])]
            p95s = [np.percentile(r["samples"], 95) for r in rs if len(r["samples"])]
            maxes = [r["samples"].max() for r in rs if len(r["samples"])]
            per = [r["cpu_per_move"] / n for r in rs]
            print(
                f"{app:11} {k or '-':>7} {workers or '-':>7} {n:9d} {np.median(p50s):8.1f} "
                f"{np.median(p95s):8.1f} {np.median(maxes):8.1f} {sum(r['missed'] for r in rs):7d} "
                f"{np.median(per):17.3f}",
                flush=True,
            )
    print(f"load average after: {' '.join(Path('/proc/loadavg').read_text().split()[:3])}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
