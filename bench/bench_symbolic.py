"""Benchmark of the symbolic Jacobian: derive + simplify time (cold and cached), and LaTeX length.

Targets (issue "Symbolic Jacobians"): Puma 560 cold ≤ 10 s, cached ≤ 0.1 s on a
2-core machine; our compact LaTeX of the Puma's J at most half as long as
``sympy.latex(sympy.simplify(J))`` of the same matrix.

    python bench/bench_symbolic.py                 # Puma 560 and Panda
    python bench/bench_symbolic.py --robots ur5 --repeat 5

"Cold" starts from an empty cache directory and empty in-process caches
(SymPy already imported); "cached (disk)" reads the pickle written by the cold
run; "cached (memory)" is a repeated request in the same process.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

import robots  # noqa: E402
from kinematics import symbolic  # noqa: E402
from kinematics.symbolic import cache, chain, model  # noqa: E402
from kinematics.symbolic.printing import Notation  # noqa: E402


def _reset(memory_only: bool = False) -> None:
    cache.clear_memory()
    if not memory_only:
        model.build_model.cache_clear()
        chain.frames.cache_clear()
        chain.relative_frames.cache_clear()


def _timed(fn, repeat: int) -> tuple[float, object]:
    times, out = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times), out


def bench_robot(name: str, repeat: int) -> dict:
    robot = robots.load(name)
    with tempfile.TemporaryDirectory() as tmp:
        os.environ["XDG_CACHE_HOME"] = tmp
        cold = []
        for _ in range(repeat):
            for f in Path(tmp).rglob("*.pkl"):
                f.unlink()
            _reset()
            start = time.perf_counter()
            d = symbolic.derive(robot)
            cold.append(time.perf_counter() - start)
            assert d.complete and not d.from_cache

        def from_disk():
            _reset(memory_only=True)
            return symbolic.derive(robot)

        disk, d_disk = _timed(from_disk, repeat)
        assert d_disk.from_cache
        memory, _ = _timed(lambda: symbolic.derive(robot), repeat)
        _reset()
        det_cold, _ = _timed(lambda: symbolic.determinant(robot, use_cache=False), 1)
    return {
        "robot": name,
        "cold": statistics.median(cold),
        "disk": disk,
        "memory": memory,
        "det": det_cold,
        "d": d,
    }


def latex_lengths(name: str) -> dict:
    robot = robots.load(name)
    d = symbolic.derive(robot)
    ours = Notation(d.q, d.display, d.joint_kinds).latex(d.J)
    raw = symbolic.jacobian(robot, simplify=False)
    start = time.perf_counter()
    plain = sp.latex(sp.simplify(raw))
    return {
        "ours": len(ours),
        "plain": len(plain),
        "simplify_seconds": time.perf_counter() - start,
        "raw": len(sp.latex(raw)),
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robots", nargs="+", default=["puma560", "panda"])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    print(f"sympy {sp.__version__}, python {sys.version.split()[0]}, {os.cpu_count()} CPUs")
    print(f"{'robot':<12}{'cold [s]':>10}{'disk [s]':>11}{'memory [s]':>12}{'det J cold [s]':>16}")
    ok = True
    for name in args.robots:
        r = bench_robot(name, args.repeat)
        print(f"{name:<12}{r['cold']:>10.3f}{r['disk']:>11.4f}{r['memory']:>12.6f}{r['det']:>16.3f}")
        if name == "puma560":
            ok &= r["cold"] <= 10.0 and r["disk"] <= 0.1
    lens = latex_lengths("puma560")
    ratio = lens["ours"] / lens["plain"]
    print(
        f"\nPuma 560 J in LaTeX: ours {lens['ours']} characters; sympy.latex(sympy.simplify(J)) "
        f"{lens['plain']} (simplify took {lens['simplify_seconds']:.1f} s); unsimplified {lens['raw']}; "
        f"ratio {ratio:.2f}"
    )
    ok &= ratio <= 0.5
    print("targets (Puma cold <= 10 s, cached <= 0.1 s, LaTeX <= 1/2):", "met" if ok else "NOT met")
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
