"""The room answers (issue 31): 60 followers answer a question within 2 s of it opening, on the default
``jacobian-lab serve --presenter`` (two workers here), measured by websocket clients of the running app.

One presenter (it types the token, as a teacher would) and N followers connect; the presenter moves its
q2 slider every ``--period`` seconds throughout. Phase 1, ``--moves`` moves with no question: each sample
is the time from the presenter's new value to one follower receiving its redrawn arm (as
``bench_classroom.py``). Phase 2, the same moves while a question is on: the presenter clicks **Ask the
room** ("Is it singular? Which kind?") and every follower clicks one of its choices at a random moment
within 2 s of the question reaching it. Printed side by side: the followers' view p50/p95 in each phase
(and their ratio), the time from the presenter's click to its bars reading "N of N tabs answered" (the
room's counts complete across the workers), the server's CPU per move in each phase, and the load average.

Usage::

    python bench/bench_room_answers.py                      # 60 followers, 2 workers, Puma
    python bench/bench_room_answers.py --followers 60 120 --workers 2

Target: counts complete ≤ 2 s after the last answer is sent (the bars update every 0.25 s), the
followers' view p95 unchanged (< 200 ms) while the room answers.
"""

from __future__ import annotations

import argparse
import os
import sys
import threading
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]
from wsclient import ViserWsClient  # noqa: E402  (a test helper, not part of the app)

from bench.bench_classroom import PAGE_LOADED, TOKEN, gui, is_arm_update, spread, start_server  # noqa: E402
from bench.common import cpu_seconds  # noqa: E402


def _button(ws: ViserWsClient, label: str) -> str:
    _, msg = ws.wait_for(
        lambda m: m["type"] == "GuiButtonMessage" and m["props"].get("label") == label, timeout=60
    )
    return msg["uuid"]


def _moves(presenter, slider, room, moves: int, period: float, start: int) -> tuple[list[float], int]:
    samples, missed = [], 0
    for i in range(moves):
        marks = [c.mark() for c in room]
        sent = presenter.set_value(slider, float(-30.0 + ((start + i) % 60)))
        for c, mark in zip(room, marks, strict=True):
            try:
                received, _ = c.wait_for(is_arm_update, after=mark, timeout=10)
                samples.append((received - sent) * 1e3)
            except TimeoutError:
                missed += 1
        time.sleep(max(0.0, period - (time.perf_counter() - sent)))
    return samples, missed


def run(followers: int, workers: int, moves: int, period: float, log: Path) -> dict:
    proc, port = start_server("puma560", workers, log)
    url = f"ws://127.0.0.1:{port}"
    clients: list[ViserWsClient] = []
    try:
        presenter = ViserWsClient(url)
        presenter.start()
        clients.append(presenter)
        slider = gui(presenter, "GuiSliderMessage", "q2 ")
        ask = _button(presenter, "Ask the room")
        presenter.set_value(gui(presenter, "GuiTextMessage", "page"), PAGE_LOADED)
        presenter.set_value(gui(presenter, "GuiTextMessage", "Presenter token"), TOKEN)
        presenter.wait_for(
            lambda m: m["type"] == "GuiUpdateMessage" and "You are presenting" in str(m.get("updates")),
            timeout=60,
        )
        room, choices = [], []
        for _ in range(followers):
            c = ViserWsClient(url)
            c.start(timeout=60)
            c.set_value(gui(c, "GuiTextMessage", "page"), PAGE_LOADED)
            clients.append(c)
            room.append(c)
            _, folder = c.wait_for(
                lambda m: m["type"] == "GuiFolderMessage" and m["props"].get("label") == "Question",
                timeout=60,
            )
            choices.append((folder["uuid"], [_button(c, str(i)) for i in range(6)]))  # the Question box
        for c in room:
            c.wait_for(is_arm_update, timeout=120)
        time.sleep(1.0)  # the joining burst settles
        cpu0 = cpu_seconds(proc.pid)
        quiet, quiet_missed = _moves(presenter, slider, room, moves, period, 0)
        cpu_quiet = (cpu_seconds(proc.pid) - cpu0) / moves * 1e3
        # Phase 2: the question opens; every follower answers at a random moment within 2 s.
        rng = np.random.default_rng(7)
        marks = [c.mark() for c in room]
        presenter_mark = presenter.mark()
        asked = presenter.set_value(ask, True)
        done = {"last_sent": 0.0}

        def answer(k: int, c: ViserWsClient, mark: int) -> None:
            box, buttons = choices[k]
            c.wait_for(  # its Question box opened: the question reached it
                lambda m: (
                    m["type"] == "GuiUpdateMessage"
                    and m.get("uuid") == box
                    and m.get("updates", {}).get("visible") is True
                ),
                after=mark,
                timeout=60,
            )
            time.sleep(float(rng.uniform(0.0, 2.0)))
            t = c.set_value(buttons[k % 6], True)
            done["last_sent"] = max(done["last_sent"], t)

        threads = [
            threading.Thread(target=answer, args=(k, c, m))
            for k, (c, m) in enumerate(zip(room, marks, strict=True))
        ]
        for t in threads:
            t.start()
        cpu1 = cpu_seconds(proc.pid)
        busy, busy_missed = _moves(presenter, slider, room, moves, period, moves)
        cpu_busy = (cpu_seconds(proc.pid) - cpu1) / moves * 1e3
        for t in threads:
            t.join(60)
        want = f"{followers} of {followers} tabs answered"
        complete, _ = presenter.wait_for(
            lambda m: m["type"] == "GuiUpdateMessage" and want in str(m.get("updates")), after=presenter_mark,
            timeout=60,
        )  # fmt: skip
        return {
            "quiet": np.array(quiet),
            "busy": np.array(busy),
            "missed": quiet_missed + busy_missed,
            "complete_after_ask": complete - asked,
            "complete_after_last": complete - done["last_sent"],
            "cpu_quiet": cpu_quiet,
            "cpu_busy": cpu_busy,
            "spread": spread(log),
        }
    finally:
        for c in clients:
            c.close()
        proc.terminate()
        try:
            proc.wait(10)
        except Exception:
            proc.kill()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--followers", type=int, nargs="+", default=[60])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--moves", type=int, default=20)
    parser.add_argument("--period", type=float, default=0.2)
    parser.add_argument("--log", type=Path, default=Path("/tmp/bench-room-answers.log"))
    args = parser.parse_args()
    print(
        f"Puma 560, serve --workers {args.workers} --presenter; {os.cpu_count()} CPUs; a move every "
        f"{args.period:g} s"
    )
    print(f"load average before: {' '.join(Path('/proc/loadavg').read_text().split()[:3])}")
    print("followers  spread  view p50/p95 ms: no question / answering   p95 ratio  missed")
    print(
        "           counts complete [s] after the ask / after the last answer;  CPU ms/move: none / answering"
    )
    for n in args.followers:
        r = run(n, args.workers, args.moves, args.period, args.log)
        q50, q95 = np.percentile(r["quiet"], [50, 95])
        b50, b95 = np.percentile(r["busy"], [50, 95])
        spread_ = "+".join(map(str, r["spread"]))
        print(
            f"{n:9d} {spread_:>7}  {q50:6.1f} / {q95:6.1f}  {b50:6.1f} / {b95:6.1f}  {b95 / q95:9.2f} "
            f"{r['missed']:7d}"
        )
        after_ask, after_last = r["complete_after_ask"], r["complete_after_last"]
        print(
            f"           {after_ask:6.2f} / {after_last:5.2f}    "
            f"{r['cpu_quiet']:6.1f} / {r['cpu_busy']:6.1f}",
            flush=True,
        )
    print(f"load average after: {' '.join(Path('/proc/loadavg').read_text().split()[:3])}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
