"""Manipulability maps and IK speed, side by side with what they are measured against.

In one run on this machine:

* ``kinematics.maps.workspace(panda, 100_000)`` (sampling, FK, Jacobians, w and σmin/σmax)
  against NumPy's own singular values of 100 000 random 6×7 matrices
  (``np.linalg.svd(A, compute_uv=False)``): the ratio should be ≤ 1;
* ``kinematics.motion.ik.solve`` for the Panda from a near start (the app's warm-started gizmo
  drag), per call, and, when installed, Robotics Toolbox's compiled ``ets.ik_LM`` on the same
  target, as a ratio.

Run with::

    python bench/bench_maps.py                    # add --large 1000000: a million Panda samples
"""

from __future__ import annotations

import argparse
import time
import timeit
import tracemalloc

import numpy as np

import robots
from kinematics import fk
from kinematics.maps import workspace
from kinematics.motion.ik import solve


def best_of(fn, repeat: int = 5) -> float:
    """Best-of-``repeat`` seconds of one call of ``fn``."""
    return min(timeit.repeat(fn, number=1, repeat=repeat))


def per_call(fn, min_time: float = 0.3) -> float:
    """Best-of-5 seconds per call of ``fn``."""
    number = 1
    while timeit.timeit(fn, number=number) < min_time / 5:
        number *= 2
    return min(timeit.repeat(fn, number=number, repeat=5)) / number


def bench_workspace(n: int) -> None:
    panda = robots.load("panda")
    A = np.random.default_rng(0).standard_normal((n, 6, 7))
    # Interleaved, best of 7 each: the machine's load then weighs on both alike.
    ours, svd = np.inf, np.inf
    for _ in range(7):
        ours = min(ours, best_of(lambda: workspace(panda, n, seed=0), repeat=1))
        svd = min(svd, best_of(lambda: np.linalg.svd(A, compute_uv=False), repeat=1))
    print(f"workspace(panda, {n})          {ours * 1e3:8.1f} ms")
    print(f"np.linalg.svd of {n} 6×7       {svd * 1e3:8.1f} ms")
    print(f"ratio (must be ≤ 1)                {ours / svd:8.2f}")


def bench_ik() -> None:
    panda = robots.load("panda")
    rng = np.random.default_rng(1)
    q0 = panda.home
    q_goal = q0 + rng.normal(0, 0.1, panda.dof)
    T = fk(panda, q_goal)
    res = solve(panda, T, q0, max_iterations=20)
    ours = per_call(lambda: solve(panda, T, q0, max_iterations=20))
    steps = f"{res.iterations} Newton steps, {res.reason}"
    print(f"ik.solve panda, near start         {ours * 1e6:8.1f} µs  ({steps})")
    try:
        import roboticstoolbox as rtb
        from spatialmath import SE3
    except ImportError:
        print("roboticstoolbox not installed: no comparison")
        return
    ets = rtb.models.Panda().ets()
    # RTB's Panda model ends at its own hand offset: compare speeds on its own target.
    T_rtb = SE3(ets.fkine(q_goal))
    try:
        sol = ets.ik_LM(T_rtb, q0=q0, ilimit=20, slimit=1)
    except TypeError as exc:  # RTB 1.5's compiled binding rejects NumPy 2 arrays here
        print(f"RTB ets.ik_LM unavailable in this environment ({str(exc).splitlines()[0]})")
        return
    theirs = per_call(lambda: ets.ik_LM(T_rtb, q0=q0, ilimit=20, slimit=1))
    print(f"RTB ets.ik_LM (C++), same start     {theirs * 1e6:8.1f} µs  (success {bool(sol[1])})")
    print(f"ratio ours / RTB                   {ours / theirs:8.2f}")


def bench_large(n: int) -> None:
    """``workspace(panda, n)`` once: time, and the peak memory beyond its results (tracemalloc
    sees NumPy's buffers), which the chunks bound whatever ``n``."""
    panda = robots.load("panda")
    workspace(panda, 1000, seed=0)
    start = time.thread_time()
    workspace(panda, n, seed=0)
    seconds = time.thread_time() - start
    tracemalloc.start()
    ws = workspace(panda, n, seed=0)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    results = sum(a.nbytes for a in (ws.q, ws.points, ws.w, ws.inverse_kappa))
    print(
        f"workspace(panda, {n:,}): {seconds:.1f} s of CPU ({seconds / n * 1e6:.2f} µs per configuration); "
        f"results {results / 2**20:.0f} MiB, peak beyond them {(peak - results) / 2**20:.1f} MiB"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100_000, help="workspace samples")
    parser.add_argument("--large", type=int, default=0, help="also one workspace of this many samples")
    args = parser.parse_args()
    bench_workspace(args.n)
    bench_ik()
    if args.large:
        bench_large(args.large)


if __name__ == "__main__":
    main()
