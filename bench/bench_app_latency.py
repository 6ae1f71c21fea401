"""Round-trip latency of the browser app: slider change → redrawn scene, measured by a websocket client.

Starts ``jacobian-lab serve`` (the app's own entry point, ``app.server.serve``)
in a separate process with the Panda, connects as a browser would (viser's
websocket protocol, no rendering), finds the ``q2`` slider, then moves it
again and again. Each sample is the time from sending the slider's new
value to receiving the frame that carries the redrawn arm (the batched
update of ``/lab/arm/cylinders``; scene and readouts travel in one atomic
batch). The next change is sent only when the previous one came back, like
a slider dragged at the speed the app can follow.

Usage::

    python bench/bench_app_latency.py                 # Panda, 300 samples
    python bench/bench_app_latency.py --robot puma560 --samples 500

    python bench/bench_app_latency.py --animating 2   # while two other tabs play a motion

Target: p95 < 50 ms on a 2-core machine. With ``--animating K``, K other tabs first pick the
robot's first resolved-rate preset, slow it to 0.1× (so it plays throughout) and press Play: the
explorer's motions run on each tab's own ticker, and this measures what they cost the tab whose
slider moves.
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

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from wsclient import ViserWsClient  # noqa: E402  (a test helper, not part of the app)

ARM_NODE = "/lab/arm/cylinders"


def start_server(robot: str) -> tuple[subprocess.Popen, int]:
    code = f"from app.server import serve; serve(robot={robot!r}, port=0)"
    proc = subprocess.Popen(
        [sys.executable, "-u", "-c", code],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
        env=dict(os.environ, PYTHONUNBUFFERED="1"),
    )
    end = time.monotonic() + 60
    assert proc.stdout is not None
    while time.monotonic() < end:
        line = proc.stdout.readline()
        match = re.search(r"open http://[^:]+:(\d+)", line)
        if match:
            return proc, int(match.group(1))
        if proc.poll() is not None:
            break
    proc.kill()
    raise RuntimeError("the server did not start")


def find_slider(ws: ViserWsClient, prefix: str) -> str:
    _, msg = ws.wait_for(
        lambda m: m["type"] == "GuiSliderMessage" and m["props"]["label"].startswith(prefix + " "), timeout=30
    )
    return msg["uuid"]


def start_animating(ws: ViserWsClient) -> None:
    """In this tab: the first preset, speed 0.1, Play (the Motion tab's controls, as a browser sends them)."""
    _, preset = ws.wait_for(
        lambda m: m["type"] == "GuiDropdownMessage" and m["props"]["label"] == "Preset", timeout=30
    )
    _, speed = ws.wait_for(
        lambda m: m["type"] == "GuiSliderMessage" and m["props"]["label"] == "Speed", timeout=30
    )
    _, play = ws.wait_for(
        lambda m: m["type"] == "GuiButtonGroupMessage" and "Play" in m["props"]["options"], timeout=30
    )
    ws.set_value(preset["uuid"], preset["props"]["options"][1])
    time.sleep(0.3)
    ws.set_value(speed["uuid"], 0.1)
    time.sleep(0.3)
    ws.set_value(play["uuid"], "Play")


def is_arm_update(m: dict) -> bool:
    return m["type"] == "SceneNodeUpdateMessage" and m["name"] == ARM_NODE


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robot", default="panda")
    parser.add_argument("--samples", type=int, default=300)
    parser.add_argument("--warmup", type=int, default=20)
    parser.add_argument("--animating", type=int, default=0, help="other tabs playing a motion meanwhile")
    args = parser.parse_args()

    proc, port = start_server(args.robot)
    others: list[ViserWsClient] = []
    try:
        for _ in range(args.animating):
            other = ViserWsClient(f"ws://127.0.0.1:{port}")
            other.start()
            others.append(other)
            start_animating(other)
        with ViserWsClient(f"ws://127.0.0.1:{port}") as ws:
            uuid = find_slider(ws, "q2")
            ws.wait_for(is_arm_update, timeout=30)  # the first drawing
            time.sleep(1.0)  # let the initial burst (scene, GUI, symbolic note) settle
            samples = []
            for i in range(args.warmup + args.samples):
                value = -30.0 + (i % 60)  # sweep the shoulder like a drag, 1° per step
                mark = ws.mark()
                sent = ws.set_value(uuid, float(value))
                received, _ = ws.wait_for(is_arm_update, after=mark, timeout=10)
                if i >= args.warmup:
                    samples.append((received - sent) * 1e3)
    finally:
        for other in others:
            other.close()
        proc.terminate()
        try:
            proc.wait(10)
        except subprocess.TimeoutExpired:
            proc.kill()

    s = np.array(samples)
    p50, p95, p99 = np.percentile(s, [50, 95, 99])
    busy = f", {args.animating} other tab(s) animating" if args.animating else ""
    print(f"robot {args.robot}{busy}, {len(s)} slider changes, round trip slider → redrawn scene [ms]:")
    print(f"  p50 {p50:6.1f}   p95 {p95:6.1f}   p99 {p99:6.1f}   max {s.max():6.1f}   mean {s.mean():6.1f}")
    print(f"  machine: {os.cpu_count()} CPUs; target p95 < 50 ms: {'met' if p95 < 50 else 'MISSED'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
