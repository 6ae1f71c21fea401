"""Cold symbolic J of the 6–7 joint arms: SymPy's own steps against ours, side by side in one run.

"SymPy's steps" is the simplification as it was: the normal form with ``sympy.expand`` and
``sympy.reduced`` on expressions (:func:`kinematics.symbolic.trig.normal_form_sympy`) and sums of
angles collapsed by ``sympy.simplify.fu.TR10i``. "Ours" is the normal form on sparse polynomials
over ℚ (:func:`kinematics.symbolic.trig.normal_form`) and TR10i with an index of the pairs that can
combine (:func:`kinematics.symbolic.tr10i.tr10i`). Both give the same expressions (tests/kinematics/
test_symbolic_fast.py); this bench also checks that the two J and T are identical.

    python bench/bench_symbolic_fast.py              # the library's 6–7 joint arms
    python bench/bench_symbolic_fast.py --urdf DIR   # and every 6–7 joint URDF under DIR (default chain)
    python bench/bench_symbolic_fast.py --export     # whole LaTeX exports (det J included) too

"Cold" is ``symbolic.derive(robot, use_cache=False)`` with the in-process caches emptied (SymPy
imported); times are the process's CPU time, and so are the time limits (the machine is shared: a
busy machine must not cut one side short; wall time is shown too).
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import logging
import os
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

import robots  # noqa: E402
from kinematics import Robot, symbolic  # noqa: E402
from kinematics.symbolic import analytic, cache, chain, det, model, simplify, trig  # noqa: E402
from kinematics.symbolic.typeset.export import export  # noqa: E402
from kinematics.urdf import robot_from_urdf  # noqa: E402

LIBRARY_ARMS = ("puma560", "puma560_mdh", "stanford", "ur5", "iiwa14", "panda")


@contextlib.contextmanager
def sympy_steps() -> Iterator[None]:
    """Swap in SymPy's own normal form and TR10i (the steps before this bench's change)."""
    fu = importlib.import_module("sympy.simplify.fu")
    saved = [(m, "normal_form", m.normal_form) for m in (trig, simplify, det, analytic)]
    saved.append((trig, "tr10i", trig.tr10i))
    try:
        for m, name, _ in saved[:-1]:
            setattr(m, name, trig.normal_form_sympy)
        trig.tr10i = fu.TR10i
        yield
    finally:
        for m, name, value in saved:
            setattr(m, name, value)


def _reset() -> None:
    cache.clear_memory()
    model.build_model.cache_clear()
    chain.frames.cache_clear()
    chain.relative_frames.cache_clear()


def cold(robot: Robot, old: bool, timeout: float) -> tuple[float, float, symbolic.Derivation]:
    """(CPU s, wall s, result) of one cold derivation, with SymPy's steps (``old``) or ours."""
    _reset()
    with sympy_steps() if old else contextlib.nullcontext():
        cpu, wall = time.process_time(), time.perf_counter()
        d = symbolic.derive(robot, use_cache=False, timeout=timeout)
        return time.process_time() - cpu, time.perf_counter() - wall, d


def cold_export(robot: Robot, old: bool, timeout: float) -> tuple[float, str]:
    """(CPU s, text) of one cold LaTeX export (J, det J, singular sets) in an empty cache folder."""
    _reset()
    with tempfile.TemporaryDirectory() as tmp, sympy_steps() if old else contextlib.nullcontext():
        os.environ["XDG_CACHE_HOME"] = tmp
        cpu = time.process_time()
        text = export(robot, "latex", timeout=timeout)
        return time.process_time() - cpu, text


def arms(urdf_dir: str | None) -> list[tuple[str, Robot]]:
    out = [(n, robots.load(n)) for n in LIBRARY_ARMS]
    if urdf_dir:
        logging.disable(logging.WARNING)
        for p in sorted(Path(urdf_dir).rglob("*.urdf")):
            try:
                r = robot_from_urdf(str(p))
            except Exception:  # noqa: BLE001 - a file we cannot read is not an arm to time
                continue
            if r.dof in (6, 7):
                out.append((p.name, r))
    return out


def _state(d: symbolic.Derivation) -> str:
    return "complete" if d.complete else f"{len(d.pending)} left"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--urdf", help="a folder of URDFs (e.g. example-robot-data's robots/)")
    parser.add_argument("--timeout", type=float, default=60.0)
    parser.add_argument("--export", action="store_true", help="time whole LaTeX exports too")
    parser.add_argument("--only", nargs="+", help="only these arms (library names or URDF file names)")
    args = parser.parse_args(argv)
    os.environ["XDG_CACHE_HOME"] = tempfile.mkdtemp()
    trig.clock = time.process_time  # time limits count this process's work, as in the test suite
    versions = f"sympy {sp.__version__}, python {sys.version.split()[0]}, {os.cpu_count()} CPUs"
    print(f"{versions}, timeout {args.timeout:g} s")
    print("cold symbolic J and T (derive), CPU seconds [wall]; ratio = SymPy's steps / ours")
    head = f"{'arm':<34}{'dof':>4}{'SymPy steps':>20}{'ours':>20}{'ratio':>8}  same  result (SymPy / ours)"
    print(head)
    ok = True
    for name, robot in arms(args.urdf):
        if args.only and name not in args.only:
            continue
        c_old, w_old, d_old = cold(robot, True, args.timeout)
        c_new, w_new, d_new = cold(robot, False, args.timeout)
        same = d_old.complete and d_new.complete and d_old.J == d_new.J and d_old.T == d_new.T
        ok &= d_new.complete and c_new <= 10.0 and (same or not d_old.complete)
        print(
            f"{name:<34}{robot.dof:>4}{c_old:>11.2f} [{w_old:5.1f}]{c_new:>11.2f} [{w_new:5.1f}]"
            f"{c_old / c_new:>7.1f}×  {'yes' if same else ('—' if not d_old.complete else 'NO'):<5} "
            f"{_state(d_old)} / {_state(d_new)}",
            flush=True,
        )
        if args.export:
            e_old, t_old = cold_export(robot, True, args.timeout)
            e_new, t_new = cold_export(robot, False, args.timeout)
            stars = t_new.count(r"\ast"), t_old.count(r"\ast")
            print(
                f"{'  LaTeX export, det J included':<38}{e_old:>11.2f}{'':>8}{e_new:>11.2f}{'':>8}"
                f"{e_old / e_new:>7.1f}×  ∗ entries {stars[1]} / {stars[0]}",
                flush=True,
            )
    target = "target (every arm complete, ours <= 10 s CPU, identical to SymPy's steps):"
    print(target, "met" if ok else "NOT met")
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
