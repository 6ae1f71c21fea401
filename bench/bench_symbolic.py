"""Benchmark of the symbolic Jacobian: derive + simplify time (cold and cached), LaTeX sizes.

Targets: Puma 560 cold ≤ 10 s, cached ≤ 0.1 s on a 2-core machine; our compact LaTeX of
the Puma's J at most half as long as ``sympy.latex(sympy.simplify(J))`` of the same matrix;
the realistic 7-joint arms of ``tests/data`` (URDFs with 1.5708-style right angles) exported
to LaTeX, det J included, in well under a minute; a hard arm (6 joints twisted by 0.3 rad)
exported with ``timeout=5`` returning within the timeout plus a few seconds.

    python bench/bench_symbolic.py                 # Puma 560 and Panda, the URDF arms, the hard arm
    python bench/bench_symbolic.py --robots ur5 --repeat 5

"Cold" starts from an empty cache directory and empty in-process caches
(SymPy already imported); "cached (disk)" reads the JSON file written by the cold
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
from kinematics import Robot, robot_from_urdf, symbolic  # noqa: E402
from kinematics.symbolic import cache, chain, model  # noqa: E402
from kinematics.symbolic.typeset.export import export  # noqa: E402
from kinematics.symbolic.typeset.printing import Notation  # noqa: E402


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
            for f in Path(tmp).rglob("*.json"):
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


DATA = Path(__file__).resolve().parents[1] / "tests" / "data"
URDF_ARMS = ("iiwa14_like", "xarm7_like")


def bench_export(robot, timeout: float = 60.0) -> dict:
    """A full LaTeX export (J, columns, det J, singular sets): cold, from disk, from memory."""
    with tempfile.TemporaryDirectory() as tmp:
        os.environ["XDG_CACHE_HOME"] = tmp
        _reset()
        start = time.perf_counter()
        text = export(robot, "latex", timeout=timeout)
        cold = time.perf_counter() - start
        _reset(memory_only=True)
        start = time.perf_counter()
        export(robot, "latex", timeout=timeout)
        disk = time.perf_counter() - start
        start = time.perf_counter()
        export(robot, "latex", timeout=timeout)
        memory = time.perf_counter() - start
    notes = [line for line in text.splitlines() if line.startswith("% Note:")]
    return {"cold": cold, "disk": disk, "memory": memory, "chars": len(text), "notes": notes}


def hard_arm() -> Robot:
    rows = [
        dict(joint="revolute", a=0.1 * (i + 1), alpha=0.3 * (i + 1), d=0.05 * i, theta=0.2 * i)
        for i in range(6)
    ]
    return Robot.from_dh(rows, name="twisted6")


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
    head = f"{'cold [s]':>10}{'disk [s]':>10}{'memory [s]':>12}{'LaTeX [chars]':>15}"
    print(f"\n{'LaTeX export (with det J)':<28}{head}")
    for name in URDF_ARMS:
        r = bench_export(robot_from_urdf(str(DATA / f"{name}.urdf")))
        print(f"{name + '.urdf':<28}{r['cold']:>10.2f}{r['disk']:>10.3f}{r['memory']:>12.4f}{r['chars']:>15}")
        ok &= r["cold"] < 60 and r["chars"] < 50_000 and not any("time limit" in n for n in r["notes"])
    r = bench_export(hard_arm(), timeout=5.0)
    row = f"{r['cold']:>10.2f}{r['disk']:>10.3f}{r['memory']:>12.4f}{r['chars']:>15}"
    print(f"{'twisted6, timeout=5 s':<28}{row}")
    for note in r["notes"]:
        print("   ", note[:140])
    ok &= r["cold"] < 5.0 + 10.0
    print(
        "targets (Puma cold <= 10 s, cached <= 0.1 s, LaTeX <= 1/2; URDF arms < 60 s, complete; "
        "hard arm < timeout + 10 s):",
        "met" if ok else "NOT met",
    )
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
