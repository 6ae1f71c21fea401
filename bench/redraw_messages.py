"""What one slider change sends to its tab: every message, its node or GUI element, and its size.

Starts a :class:`app.server.Lab` with one headless websocket client, moves the ``q2`` slider a few
times, and lists the messages that followed the last change (msgpack size, binary buffers counted).
The client reports its page loaded, as a browser's page script does (so only the open tab's readouts
are drawn; ``--no-report``: every tab's), e.g.::

    PYTHONPATH=. python bench/redraw_messages.py --robot panda --port 8711
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import msgspec.msgpack
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from wsclient import ViserWsClient  # noqa: E402  (a test helper, not part of the app)

from app.server import Lab  # noqa: E402
from app.viser_adapter import handle_uuid  # noqa: E402


def size(message: dict) -> int:
    """Bytes of ``message`` as msgpack, arrays as their raw bytes."""
    return len(
        msgspec.msgpack.encode(message, enc_hook=lambda o: o.tobytes() if isinstance(o, np.ndarray) else o)
    )


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robot", default="panda")
    parser.add_argument("--port", type=int, default=0)
    parser.add_argument("--changes", type=int, default=5)
    parser.add_argument(
        "--no-report", action="store_true", help="send no page report (not a browser: every tab is drawn)"
    )
    args = parser.parse_args()
    lab = Lab(robot=args.robot, port=args.port)
    try:
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}") as ws:
            session = lab.session()
            session.settle()
            if not args.no_report:  # as a browser's page script: the page loaded, on its first tab
                session.panel.report.value = '{"kind": "load", "address": "", "resume": "", "tab": ""}'
                session.settle()
            time.sleep(1.0)  # the first drawing and its echoes
            uuid = handle_uuid(session.panel.joints.sliders[1])
            mark = ws.mark()
            for k in range(args.changes):
                mark = ws.mark()
                ws.set_value(uuid, float(-20 + 3 * k))
                time.sleep(0.3)
            messages = [m for _, m in ws.messages[mark:]]
    finally:
        lab.stop()
    total = 0
    for m in messages:
        what = m.get("name") or m.get("uuid") or ""
        fields = m.get("updates") or {}
        n = size(m)
        total += n
        print(f"{m['type']:26s} {str(what)[:44]:44s} {n:6d}  {', '.join(fields)}")
    print(f"{len(messages)} messages, {total} bytes after one change of q2 ({args.robot})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
