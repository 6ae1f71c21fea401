"""Where one slider change's server CPU goes: per thread, and inside the renderer's visit.

Starts a :class:`app.server.Lab` (the Panda) in this process with ``--tabs`` headless websocket tabs
(``tests/wsclient.py``), moves the first tab's q2 slider ``--changes`` times, 100 ms apart, and
prints the CPU each of the server's threads spent per change (``/proc/<pid>/task/<tid>/schedstat``,
nanoseconds: the renderer that reduces and draws, viser's event loop that serializes and sends,
the pool threads that take the messages in; this process's own client threads are left out),
then the functions of the renderer's visit that cost most (:mod:`cProfile`, enabled only inside
``ClientSession.visit``: profiling slows it, so read the shares). Linux only. E.g.::

    PYTHONPATH=. python bench/profile_change.py --changes 200 --top 40
    PYTHONPATH=. python bench/profile_change.py --followers 60 --changes 100   # a presenter and a room

With ``--followers N`` the lab is in classroom mode: the first tab types the presenter token, the N
others follow it, and the presenter's slider moves (the figures are then per presenter move).
"""

from __future__ import annotations

import argparse
import cProfile
import gc
import os
import pstats
import sys
import threading
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from wsclient import ViserWsClient  # noqa: E402  (a test helper, not part of the app)

from app.server import Lab  # noqa: E402
from app.tab.session import ClientSession  # noqa: E402


def thread_cpu() -> dict[int, float]:
    """CPU time so far [s] of every thread of this process, by native id."""
    out: dict[int, float] = {}
    for task in Path(f"/proc/{os.getpid()}/task").iterdir():
        try:
            out[int(task.name)] = int((task / "schedstat").read_text().split()[0]) / 1e9
        except OSError:  # a thread that just ended
            continue
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robot", default="panda")
    parser.add_argument("--tabs", type=int, default=1, help="tabs connected (only the last one moves)")
    parser.add_argument("--followers", type=int, default=0, help="classroom: a presenter and N followers")
    parser.add_argument("--changes", type=int, default=200)
    parser.add_argument("--top", type=int, default=30, help="functions of the visit printed (0: none)")
    parser.add_argument(
        "--loop", action="store_true", help="profile viser's event loop (serializing, sending) instead"
    )
    parser.add_argument("--tottime", action="store_true", help="order the visit's functions by own time")
    parser.add_argument(
        "--cpu", action="store_true", help="profile with the thread's CPU clock (waits for the GIL left out)"
    )
    parser.add_argument("--callees", default="", help="also print what this function of the visit calls")
    args = parser.parse_args()
    profile = cProfile.Profile(time.thread_time) if args.cpu else cProfile.Profile()
    visit = ClientSession.visit

    measuring = [True]  # the clients' closing (followers redrawing their own scenes) left out
    collections: list[tuple[str, int, float]] = []  # (thread, generation, seconds) during the changes
    warm: list[tuple[str, int, float]] = []  # the same during the warm-up moves (after the room joined)
    collecting: list[Any] = [None, 0.0]

    def timed_collection(phase: str, info: dict) -> None:
        if phase == "start":
            collecting[1] = time.thread_time()
        elif collecting[0] is not None:
            name = threading.current_thread().name
            collecting[0].append((name, info["generation"], time.thread_time() - collecting[1]))

    def profiled(self: ClientSession) -> bool:
        if not measuring[0]:
            return visit(self)
        profile.enable()
        try:
            return visit(self)
        finally:
            profile.disable()

    if args.top and not args.loop:  # else the per-thread figures are the app's own, unprofiled
        ClientSession.visit = profiled  # type: ignore[method-assign]
    token = "profile-token" if args.followers else None
    lab = Lab(robot=args.robot, port=0, presenter_token=token)
    if args.top and args.loop:  # the loop's thread profiles itself from now on (its waits included)
        lab.server._websock_server._background_event_loop.call_soon_threadsafe(profile.enable)
    tabs = args.followers + 1 if args.followers else args.tabs
    clients = [ViserWsClient(f"ws://127.0.0.1:{lab.port}") for _ in range(tabs)]
    try:
        for client in clients:
            client.start()
        end = time.monotonic() + 60
        while len(lab.sessions) < tabs and time.monotonic() < end:  # every tab's session built
            time.sleep(0.05)
        time.sleep(0.5)
        session = lab.session()
        session.settle()
        if args.followers:  # the first tab types the token and presents, the others follow it
            session = lab.sessions[min(lab.sessions)]
            clients.append(clients.pop(0))  # clients[-1] is the one that moves
            clients[-1].set_value(session.panel.classroom.token._impl.uuid, token)  # type: ignore[union-attr]
            time.sleep(1.0)
            session.settle()
            following = sum(each.following.following for each in list(lab.sessions.values()))
            print(f"{following} of {args.followers} tabs follow the presenter")
        # as a browser's page script: the page loaded, on its first tab
        for each in list(lab.sessions.values()):
            each.panel.report.value = '{"kind": "load", "address": "", "resume": "", "tab": ""}'
        session.settle()
        slider = session.panel.joints.sliders[1]  # type: ignore[union-attr]
        uuid = slider._impl.uuid
        time.sleep(1.0)  # the room joined and drawn: a lecturer's pause before the first move
        gc.callbacks.append(timed_collection)
        collecting[0] = warm
        for i in range(20):  # warm up: first draws, the symbolic J's arrival
            clients[-1].set_value(uuid, float(-30 + i % 60))
            time.sleep(0.1)
        time.sleep(1.0)
        own = {t.native_id for t in threading.enumerate() if t.name in ("MainThread", "viser-ws-client")}
        names = {t.native_id: t.name for t in threading.enumerate()}
        profile.clear()
        collecting[0] = collections
        before, redraws = thread_cpu(), session.redraws
        for i in range(args.changes):
            clients[-1].set_value(uuid, float(-30 + i % 60))
            time.sleep(0.1)
        time.sleep(0.5)
        after, drawn = thread_cpu(), session.redraws - redraws
        collecting[0], measuring[0] = None, False
        if args.top and args.loop:  # the clients' closing (followers redrawing their own) left out
            stopped = threading.Event()
            loop = lab.server._websock_server._background_event_loop
            loop.call_soon_threadsafe(lambda: (profile.disable(), stopped.set()))
            stopped.wait(10)
    finally:
        for client in clients:
            client.close()
        lab.stop()
    load = Path("/proc/loadavg").read_text().split()[:3]
    print(f"{args.robot}, {args.tabs} tab(s), {drawn} redraws of {args.changes} changes; load average {load}")
    spent: dict[str, float] = {}
    for tid, seconds in after.items():
        if tid not in own:
            name = names.get(tid, "other").split("_")[0].split(" (")[0]
            spent[name] = spent.get(name, 0.0) + seconds - before.get(tid, 0.0)
    for name, seconds in sorted(spent.items(), key=lambda kv: -kv[1]):
        print(f"  {name:<40} {seconds / args.changes * 1e3:7.3f} ms per change")
    print(f"  {'server threads':<40} {sum(spent.values()) / args.changes * 1e3:7.3f} ms per change")
    own_names = ("MainThread", "viser-ws-client")  # the server's threads' collections, not the clients'
    for when, moves, made in (("the 20 first moves", 20, warm), ("the changes", args.changes, collections)):
        for generation in range(3):
            times = [t for name, g, t in made if g == generation and not name.startswith(own_names)]
            if times:
                print(
                    f"  garbage collections in {when}, generation {generation}: {len(times)}, "
                    f"{sum(times) / moves * 1e3:.3f} ms per move, longest {max(times) * 1e3:.1f} ms"
                )
    if args.top:
        pstats.Stats(profile).sort_stats(
            "tottime" if args.loop or args.tottime else "cumulative"
        ).print_stats(args.top)
        if args.callees:
            pstats.Stats(profile).sort_stats("cumulative").print_callees(args.callees)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
