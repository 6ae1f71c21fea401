"""What the symbolic J costs by joint count and structure: the measurements behind the app's rule of
what is worth attempting (:mod:`app.services.symbolic_budget`, issue 26 item 1).

Each case runs :func:`kinematics.symbolic.jacobian_mathml` (the panel's J, what a tab asks first) cold
(an empty disk cache) in a process of its own, stopped after ``--seconds`` or at ``--memory-mb`` of
resident memory; the table gives the time, the peak resident memory and whether it finished.

    python bench/bench_symbolic_size.py                       # URDF chains 2..24 joints, the DH library
    python bench/bench_symbolic_size.py --seconds 60 --only general

Cases: ``planar-N`` (N revolute joints about z, 1 cm apart: the issue's upload), ``general-N``
(axes turning x, y, z, offsets in two directions: a URDF arm with no right-angle structure the
snapping can use), and the library's DH robots.
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def chain_urdf(joints: int, general: bool) -> bytes:
    """A serial URDF chain of ``joints`` revolute joints (``general``: skewed axes and offsets)."""
    axes = ("1 0 0", "0 1 0", "0 0 1")
    links = "".join(f'<link name="l{i}"/>' for i in range(joints + 1))
    chain = "".join(
        f'<joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/>'
        + (f'<origin xyz="0.1 0.05 0.2" rpy="0 0.3 0"/><axis xyz="{axes[i % 3]}"/>' if general else "")
        + ('<origin xyz="0.01 0 0"/><axis xyz="0 0 1"/>' if not general else "")
        + '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        for i in range(joints)
    )
    return f'<?xml version="1.0"?><robot name="c{joints}">{links}{chain}</robot>'.encode()


def robot_of(case: str):
    import robots
    from kinematics.urdf import robot_from_urdf_string

    kind, _, n = case.rpartition("-")
    if kind in ("planar", "general"):
        return robot_from_urdf_string(chain_urdf(int(n), kind == "general"), name=case)
    return robots.load(case)


def _run(case: str, cache: str) -> None:
    os.environ["XDG_CACHE_HOME"] = cache
    from kinematics.symbolic import jacobian_mathml

    jacobian_mathml(robot_of(case), frame="base", timeout=3600.0)


def _rss(pid: int) -> int:
    try:
        return int(Path(f"/proc/{pid}/statm").read_text().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, IndexError):
        return 0


def measure(case: str, seconds: float, memory: int) -> tuple[float, int, str]:
    """(time [s], peak RSS [bytes], outcome) of one cold symbolic J in a fresh process."""
    ctx = multiprocessing.get_context("spawn")
    with tempfile.TemporaryDirectory() as cache:
        p = ctx.Process(target=_run, args=(case, cache))
        start = time.monotonic()
        p.start()
        peak, outcome = 0, "done"
        while p.is_alive():
            peak = max(peak, _rss(p.pid))
            if time.monotonic() - start > seconds:
                outcome = f"stopped at {seconds:.0f} s"
            elif peak > memory:
                outcome = f"stopped at {memory / 1e6:.0f} MB"
            else:
                p.join(0.1)
                continue
            p.kill()
            p.join()
        if outcome == "done" and p.exitcode != 0:
            outcome = f"failed ({p.exitcode})"
        return time.monotonic() - start, peak, outcome


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=90.0)
    ap.add_argument("--memory-mb", type=float, default=1500.0)
    ap.add_argument("--only", default="", help="run only the cases whose name contains this")
    ap.add_argument("cases", nargs="*")
    args = ap.parse_args()
    cases = args.cases or [
        *(f"planar-{n}" for n in (3, 6, 8, 12, 24)),
        *(f"general-{n}" for n in (3, 4, 5, 6, 7, 8, 10, 12, 24)),
        *("planar3", "puma560", "stanford", "ur5", "panda", "iiwa14"),
    ]
    print("| case | joints | time [s] | peak RSS [MB] | outcome |\n|---|---|---|---|---|", flush=True)
    for case in cases:
        if args.only not in case:
            continue
        t, peak, outcome = measure(case, args.seconds, int(args.memory_mb * 1e6))
        print(f"| {case} | {robot_of(case).dof} | {t:.1f} | {peak / 1e6:.0f} | {outcome} |", flush=True)


if __name__ == "__main__":
    main()
