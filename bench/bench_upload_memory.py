"""Memory of unfinished uploads, and whether it comes back when their tabs leave (issue 26, point 5).

Starts ``jacobian-lab serve`` (default robot and workers: one per core) in a process session of its own,
opens ``--tabs`` tabs (viser's websocket protocol, no rendering), and has each start ``--uploads``
uploads of 2 MB (4 parts of 512 KiB, the browser's) and send ``--parts`` of their parts, paced under the
message rate limit; then closes the tabs. Prints the server tree's PSS (``/proc/PID/smaps_rollup``:
a page shared by k processes counts 1/k in each, so the sum is what the tree costs the machine) and RSS,
summed over its processes, at each step once it stopped moving: idle, the tabs open, the uploads sent,
the tabs closed, and ``--after`` seconds later; then each process's PSS.

Usage::

    PYTHONPATH=$PWD python bench/bench_upload_memory.py                 # 30 tabs × 3 uploads, 3 of 4 parts
    PYTHONPATH=$PWD python bench/bench_upload_memory.py --uploads 0     # the tabs alone
    PYTHONPATH=$PWD python bench/bench_upload_memory.py --workers 1 --robot planar2

Run it in trees of two commits to compare.
"""

from __future__ import annotations

import argparse
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import uuid
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]
from hostile_helpers import widget  # noqa: E402  (test helpers, not part of the app)
from wsclient import ViserWsClient  # noqa: E402

from app.viser_adapter import UPLOAD_PART_BYTES, message_class  # noqa: E402
from bench.common import memory, rollup_kb, tree  # noqa: E402

START = message_class("FileTransferStartUpload")
PART = message_class("FileTransferPart")


def settled(pid: int, timeout: float = 30.0) -> tuple[float, float]:
    """(PSS, RSS) of the tree [MiB] once two readings half a second apart agree within 0.5 MiB."""
    last = memory(pid)
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        time.sleep(0.5)
        now = memory(pid)
        if abs(now[0] - last[0]) < 0.5:
            return now[0], now[1]
        last = now
    return last[0], last[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--tabs", type=int, default=30)
    parser.add_argument("--uploads", type=int, default=3, help="uploads each tab starts")
    parser.add_argument("--parts", type=int, default=3, help="parts of 4 each upload sends")
    parser.add_argument("--workers", type=int, default=None, help="serve --workers (default: serve's)")
    parser.add_argument("--robot", default=None, help="serve --robot (default: serve's)")
    parser.add_argument("--after", type=float, default=10.0, help="seconds to watch after the tabs left")
    args = parser.parse_args()
    command = [sys.executable, "-u", "-m", "app.cli.main", "serve", "--port", "0"]
    command += ["--workers", str(args.workers)] if args.workers else []
    command += ["--robot", args.robot] if args.robot else []
    log = Path(tempfile.mkdtemp(prefix="jl-upload-mem-")) / "serve.log"
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    with log.open("w") as err:
        proc = subprocess.Popen(
            command, stdout=subprocess.PIPE, stderr=err, text=True, cwd=ROOT, env=env, start_new_session=True
        )
    tabs: list[ViserWsClient] = []
    try:
        assert proc.stdout is not None
        match = None
        for line in proc.stdout:
            match = re.search(r"open http://[^:]+:(\d+)", line)
            if match:
                print(line.strip())
                break
        if match is None:
            raise RuntimeError(f"the server did not start: {log.read_text()[-2000:]}")
        url = f"ws://127.0.0.1:{match.group(1)}"
        rows = [("idle", settled(proc.pid))]
        tabs = [ViserWsClient(url).__enter__() for _ in range(args.tabs)]
        buttons = [widget(ws, lambda m: m["type"] == "GuiUploadButtonMessage", 120) for ws in tabs]
        rows.append((f"{args.tabs} tabs open", settled(proc.pid)))
        part = os.urandom(UPLOAD_PART_BYTES)
        for ws, button in zip(tabs, buttons, strict=True):
            for i in range(args.uploads):
                transfer = uuid.uuid4().hex
                ws.send(START(button, transfer, f"arm{i}.urdf", "text/xml", 4, 4 * UPLOAD_PART_BYTES))
                for k in range(args.parts):
                    ws.send(PART(button, transfer, k, part))
                    time.sleep(0.012)  # under the message rate limit
        rows.append((f"{args.uploads} uploads × {args.parts} of 4 parts sent", settled(proc.pid)))
        for ws in tabs:
            ws.close()
        tabs = []
        rows.append(("the tabs just closed", settled(proc.pid)))
        time.sleep(args.after)
        rows.append((f"{args.after:g} s later", settled(proc.pid)))
        base = rows[1][1]
        for what, (pss, rss) in rows:
            grown = f"PSS {pss:7.1f} MiB ({pss - base[0]:+6.1f})  RSS {rss:7.1f} MiB ({rss - base[1]:+6.1f})"
            print(f"  {what:<32} {grown}")
        for p in tree(proc.pid):
            try:
                fields = rollup_kb(Path(f"/proc/{p}/smaps_rollup").read_text())
                name = Path(f"/proc/{p}/cmdline").read_bytes().replace(b"\0", b" ").decode()[:70]
            except OSError:
                continue
            print(f"  {p:>8} PSS {fields.get('Pss', 0) / 1024:7.1f} MiB  {name}")
    finally:
        for ws in tabs:
            ws.close()
        os.killpg(proc.pid, signal.SIGTERM)
        try:
            proc.wait(30)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)


if __name__ == "__main__":
    main()
