"""Per-redraw CPU of one tab, by part: compute(state), the scene, the panel (thread CPU, best of N).

Starts a :class:`app.server.Lab` on ``--port`` with one headless websocket client,
prepares ``--redraws`` states of the chosen robot (its q2 swept), and draws each
as the session does (``compute``, then the scene and the panel inside
``client.atomic()``), timing every part with ``time.thread_time``. The best of
``--repeats`` passes is printed, so that other work on a shared machine counts
as little as it can. Run it from the checkout to measure, e.g.::

    PYTHONPATH=. python bench/profile_redraw.py --robot panda --port 8711

(the viser event loop's share, serializing and sending, is not included: see
``bench/bench_app_load.py`` for the whole server's CPU).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from wsclient import ViserWsClient  # noqa: E402  (a test helper, not part of the app)

from app.core.actions import SetJoint  # noqa: E402
from app.core.reducer import reduce  # noqa: E402
from app.core.snapshot import compute  # noqa: E402
from app.server import Lab  # noqa: E402


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robot", default="panda")
    parser.add_argument("--port", type=int, default=0, help="the server's port (0: a free one)")
    parser.add_argument("--redraws", type=int, default=300)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    lab = Lab(robot=args.robot, port=args.port)
    try:
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}"):
            session = lab.session()
            session.settle()
            states = [
                reduce(session.state, SetJoint(1, -0.5 + 0.005 * (i % 200))) for i in range(args.redraws)
            ]
            best: dict[str, float] = {}
            clock = time.thread_time
            with session.lock:  # the renderer stays idle meanwhile
                assert session.scene is not None
                session._drawing.active = True  # as in a redraw: the inputs' echoes are ignored
                for _ in range(args.repeats):
                    spent = dict.fromkeys(("compute", "scene", "panel", "total"), 0.0)
                    for state in states:
                        t0 = clock()
                        snap = compute(state)
                        t1 = clock()
                        with session.client.atomic():
                            t2 = clock()
                            session.scene.update(snap, state)
                            t3 = clock()
                            session.panel.draw(state, snap)
                            t4 = clock()
                        t5 = clock()
                        spent["compute"] += t1 - t0
                        spent["scene"] += t3 - t2
                        spent["panel"] += t4 - t3
                        spent["total"] += t5 - t0
                    for key, value in spent.items():
                        best[key] = min(best.get(key, float("inf")), value / len(states) * 1e3)
                    time.sleep(0.2)  # let the event loop send what was queued
    finally:
        lab.stop()
    parts = ", ".join(f"{key} {value:.2f}" for key, value in best.items())
    print(f"{args.robot}: ms per redraw (thread CPU, best of {args.repeats}): {parts}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
