"""CPU per animation frame of the explorer's motions, with the Panda, in a running app.

Starts the app in this process on a free port, connects one websocket client (viser's protocol, no
rendering, so every frame is serialised and sent), loads the Panda, and lets each motion play on the
tab's own ticker for a few seconds. Reports, side by side:

* the process CPU per drawn frame [ms] (everything: the ticker, the reducer's kinematics, compute,
  scene, panel, charts, viser's serialisation) and the frames per second reached (target 30);
* the reducer's step alone (the maths of one frame) [ms], and the share of a frame it is;
* the share of one core an animating tab costs (so how many tabs can animate at once).

Usage::

    python bench/bench_motion.py                # Panda, 4 s per motion
    python bench/bench_motion.py --seconds 8
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]
from wsclient import ViserWsClient  # noqa: E402  (a test helper, not part of the app)

import robots  # noqa: E402
from app.core.actions import ApplyPreset, Play, ResetMotion, SelfMove, Step  # noqa: E402
from app.core.commands import ChooseRobot  # noqa: E402
from app.core.motion_rules import FRAME_DT  # noqa: E402
from app.core.reducer import reduce  # noqa: E402
from app.server import Lab  # noqa: E402


def reducer_step_ms(state, repeats: int = 300) -> float:
    """Median time of one reduce(state, Step) [ms] along the motion."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        nxt = reduce(state, Step(FRAME_DT))
        times.append(time.perf_counter() - t0)
        state = nxt if nxt.playing else state
    times.sort()
    return 1e3 * times[len(times) // 2]


def measure(session, seconds: float) -> tuple[float, float]:
    """(CPU per frame [ms], frames per second) while the tab plays."""
    session.settle()
    r0, c0, t0 = session.redraws, time.process_time(), time.perf_counter()
    time.sleep(seconds)
    r1, c1, t1 = session.redraws, time.process_time(), time.perf_counter()
    frames = max(r1 - r0, 1)
    return 1e3 * (c1 - c0) / frames, frames / (t1 - t0)


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--seconds", type=float, default=4.0)
    args = parser.parse_args()
    lab = Lab(port=0)
    try:
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}"):
            session = lab.session()
            session.dispatch(ChooseRobot("panda"))
            session.settle()
            preset = robots.motions("panda")[0]
            rows = []
            # Resolved rate: the preset's straight line (slowed so it plays the whole window).
            session.dispatch(
                ApplyPreset(preset.name, tuple(preset.q), tuple(preset.twist), preset.frame, 0.2)
            )
            session.dispatch(Play(True, "resolved_rate"))
            session.settle()
            maths = reducer_step_ms(session.state)
            cpu, fps = measure(session, args.seconds)
            rows.append(("resolved rate (preset)", cpu, fps, maths))
            session.dispatch(Play(False))
            session.dispatch(ResetMotion())
            # The manipulability climb, from off the symmetric ready pose.
            session.dispatch(SelfMove(1.0))
            session.dispatch(Play(True, "climb"))
            session.settle()
            maths = reducer_step_ms(session.state, repeats=100)
            cpu, fps = measure(session, args.seconds)
            rows.append(("climb w (tool held)", cpu, fps, maths))
            session.dispatch(Play(False))
            session.settle()
    finally:
        lab.stop()
    print(f"Panda, one tab animating on its ticker (30 frames/s), {args.seconds:g} s per motion")
    head = ("motion", "CPU/frame", "frames/s", "maths/frame", "maths share", "core share")
    print(f"{head[0]:<26}{head[1]:>11}{head[2]:>10}{head[3]:>13}{head[4]:>13}{head[5]:>12}")
    for name, cpu, fps, maths in rows:
        print(
            f"{name:<26}{cpu:>9.2f}ms{fps:>10.1f}{maths:>11.2f}ms{maths / cpu:>13.2f}{cpu * fps / 1e3:>12.2f}"
        )


if __name__ == "__main__":
    main()
