"""Classroom latency: a presenter's slider move → every follower's redrawn 3-D view, measured by
websocket clients of the running app.

Starts ``app.server.serve`` with a presenter token in a separate process, connects one presenter
(it types the token into "Presenter token", as a teacher would) and N followers (viser's websocket
protocol, no rendering), then moves the presenter's q2 slider every ``--period`` seconds. Each sample
is the time from sending the presenter's new value to one follower receiving the frame that carries
its redrawn arm (the batched update of ``/lab/arm/cylinders``): N samples per move.

Usage::

    python bench/bench_classroom.py                   # 30 and 60 followers, Panda
    python bench/bench_classroom.py --followers 10 30 --moves 40

Target: p95 < 150 ms with 30 followers on a 2-core machine.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]
from wsclient import ViserWsClient  # noqa: E402  (a test helper, not part of the app)

ARM_NODE = "/lab/arm/cylinders"
TOKEN = "bench-token"


def start_server(robot: str) -> tuple[subprocess.Popen, int]:
    code = f"from app.server import serve; serve(robot={robot!r}, port=0, presenter_token={TOKEN!r})"
    proc = subprocess.Popen(
        [sys.executable, "-u", "-c", code],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
        cwd=str(ROOT),
        env=dict(os.environ, PYTHONUNBUFFERED="1"),
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


def gui(ws: ViserWsClient, kind: str, label_start: str) -> str:
    _, msg = ws.wait_for(
        lambda m: m["type"] == kind and str(m["props"].get("label", "")).startswith(label_start), timeout=60
    )
    return msg["uuid"]


def is_arm_update(m: dict) -> bool:
    return m["type"] == "SceneNodeUpdateMessage" and m["name"] == ARM_NODE


def run(robot: str, followers: int, moves: int, period: float) -> np.ndarray:
    proc, port = start_server(robot)
    url = f"ws://127.0.0.1:{port}"
    clients: list[ViserWsClient] = []
    try:
        presenter = ViserWsClient(url)
        presenter.start()
        clients.append(presenter)
        slider = gui(presenter, "GuiSliderMessage", "q2 ")
        presenter.set_value(gui(presenter, "GuiTextMessage", "Presenter token"), TOKEN)
        presenter.wait_for(
            lambda m: m["type"] == "GuiUpdateMessage" and "You are presenting" in str(m.get("updates")),
            timeout=60,
        )
        room = []
        for _ in range(followers):
            c = ViserWsClient(url)
            c.start(timeout=60)
            clients.append(c)
            room.append(c)
        for c in room:  # each follower has drawn the presenter's arm once
            c.wait_for(is_arm_update, timeout=120)
        time.sleep(1.0)  # let the joining burst settle
        samples = []
        for i in range(moves):
            marks = [c.mark() for c in room]
            sent = presenter.set_value(slider, float(-30.0 + (i % 60)))
            for c, mark in zip(room, marks, strict=True):
                received, _ = c.wait_for(is_arm_update, after=mark, timeout=30)
                samples.append((received - sent) * 1e3)
            time.sleep(max(0.0, period - (time.perf_counter() - sent)))
        return np.array(samples)
    finally:
        for c in clients:
            c.close()
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
    args = parser.parse_args()
    print(f"robot {args.robot}; presenter moves q2 every {args.period:g} s; {os.cpu_count()} CPUs")
    print("followers   p50 ms   p95 ms   max ms   (presenter slider → each follower's redrawn arm)")
    for n in args.followers:
        s = run(args.robot, n, args.moves, args.period)
        p50, p95 = np.percentile(s, [50, 95])
        print(f"{n:9d} {p50:8.1f} {p95:8.1f} {s.max():8.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
