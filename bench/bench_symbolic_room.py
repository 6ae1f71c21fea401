"""One tab's legal uploads against the room's memory (issue 26 item 1), measured on ``jacobian-lab serve``.

Starts the default ``serve`` (a worker per core, the parent's one symbolic pool) of a source tree,
connects a good tab that moves a slider (one round trip after another, for its p50/p95) and a bad tab
that uploads URDF chains, then samples the whole tree's PSS (every process of its session,
``/proc/PID/smaps_rollup``) for ``--seconds``. Prints the growth over idle on a timeline, its peak,
the notices the bad tab received, and the good tab's round trips.

    PYTHONPATH=$PWD python bench/bench_symbolic_room.py                       # this tree
    PYTHONPATH=$PWD python bench/bench_symbolic_room.py --tree /path/to/old --seconds 180
    PYTHONPATH=$PWD python bench/bench_symbolic_room.py --upload general-7 --upload planar-24

Uploads: ``planar-N`` (the issue's chain: N joints about z, 1 cm apart) or ``general-N`` (axes turning
x, y, z, skewed offsets), sent one after another.
"""

from __future__ import annotations

import argparse
import os
import re
import signal
import statistics
import subprocess
import sys
import threading
import time
import uuid
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(HERE / "tests"))

from hostile_helpers import chain_urdf, round_trip, slider, widget  # noqa: E402
from server_process import TreeMemory, session_processes, tree_pss_bytes  # noqa: E402
from wsclient import ViserWsClient  # noqa: E402

from app.viser_adapter import UPLOAD_PART_BYTES, message_class  # noqa: E402


def _upload(ws: ViserWsClient, name: str, content: bytes) -> None:
    button = widget(ws, lambda m: m["type"] == "GuiUploadButtonMessage")
    transfer = uuid.uuid4().hex
    parts = [content[i : i + UPLOAD_PART_BYTES] for i in range(0, len(content), UPLOAD_PART_BYTES)]
    start = message_class("FileTransferStartUpload")
    ws.send(start(button, transfer, name, "text/xml", len(parts), len(content)))
    for i, part in enumerate(parts):
        ws.send(message_class("FileTransferPart")(button, transfer, i, part))


def _trips(ws: ViserWsClient, uuid_: str, stop: threading.Event, out: list[float]) -> None:
    i = 0
    while not stop.is_set():
        i += 1
        try:
            out.append(round_trip(ws, uuid_, float(-40 + (i * 7) % 80), timeout=10))
        except TimeoutError:
            out.append(10_000.0)
        time.sleep(0.2)  # a student's pace


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tree", type=Path, default=HERE, help="the source tree whose server is measured")
    ap.add_argument("--seconds", type=float, default=120.0, help="how long the tree's memory is sampled")
    ap.add_argument("--upload", action="append", help="planar-N or general-N (default: planar-24)")
    args = ap.parse_args()
    uploads = args.upload or ["planar-24"]
    proc = subprocess.Popen(
        [sys.executable, "-u", "-m", "app.cli.main", "serve", "--robot", "planar2", "--port", "0"],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
        cwd=args.tree,
        env=dict(os.environ, PYTHONPATH=str(args.tree)),
        start_new_session=True,
    )
    try:
        assert proc.stdout is not None
        port = next(
            int(m.group(1)) for line in proc.stdout if (m := re.search(r"open http://[^:]+:(\d+)", line))
        )
        threading.Thread(target=proc.stdout.read, daemon=True).start()
        url = f"ws://127.0.0.1:{port}"
        with ViserWsClient(url) as good, ViserWsClient(url) as bad:
            g = slider(good)
            slider(bad)
            for ws in (good, bad):  # the symbolic process is up: part of idle
                ws.wait_for(lambda m: "from kinematics.symbolic." in str(m), timeout=180)
            idle = tree_pss_bytes(proc.pid)
            samples: list[float] = []
            stop = threading.Event()
            mover = threading.Thread(target=_trips, args=(good, g, stop, samples), daemon=True)
            mover.start()
            mark = bad.mark()
            with TreeMemory(proc.pid, every=0.5) as memory:
                for i, case in enumerate(uploads):
                    kind, _, n = case.rpartition("-")
                    _upload(bad, f"{case}-{i}.urdf", chain_urdf(int(n), general=kind == "general"))
                    time.sleep(1.0)
                end = time.monotonic() + args.seconds
                next_line = 0.0
                while time.monotonic() < end:
                    if memory.samples and memory.samples[-1][0] >= next_line:
                        t, b = memory.samples[-1]
                        print(f"  {t:6.0f} s  tree PSS {(b - idle) / 1e6:+6.0f} MB", flush=True)
                        next_line += 15.0
                    time.sleep(0.5)
            stop.set()
            mover.join(15)
            notices = [
                m["props"]["body"] for _, m in bad.messages[mark:] if m["type"] == "NotificationShowMessage"
            ]
        ordered = sorted(samples)
        p95 = ordered[int(0.95 * (len(ordered) - 1))] if ordered else float("nan")
        print(f"tree: {args.tree}; uploads: {', '.join(uploads)}; {args.seconds:.0f} s")
        print(
            f"idle tree PSS {idle / 1e6:.0f} MB; peak +{(memory.peak() - idle) / 1e6:.0f} MB;"
            f" at the end {(memory.samples[-1][1] - idle) / 1e6:+.0f} MB"
        )
        print(
            f"other tab: {len(samples)} round trips, "
            f"p50 {statistics.median(samples):.0f} ms, p95 {p95:.0f} ms"
        )
        print(
            "notices to the uploading tab:" + "".join(f"\n  - {n}" for n in notices)
            if notices
            else "notices to the uploading tab: none"
        )
    finally:
        for pid in session_processes(proc.pid):
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        proc.wait(30)


if __name__ == "__main__":
    main()
