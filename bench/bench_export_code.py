"""The exported C functions' time per call, side by side with Pinocchio and our NumPy kernel.

For the Puma 560 and the Panda, in one run on this machine:

* the C functions of ``jacobian-lab export ROBOT --format c`` (``NAME_jacobian``, and ``NAME_fk`` and
  ``NAME_jacobian_dot`` beside ``kinematics.fk`` and ``kinematics.jacobian_dot``), compiled with
  ``cc -O2`` and timed in C (a loop of calls over varying configurations, ``clock_gettime``), so no
  Python call overhead counts;
* Pinocchio's ``computeFrameJacobian(..., LOCAL_WORLD_ALIGNED)`` on the URDF our robot exports (the
  same chain), timed from Python (its call overhead included: that is how a Python user calls it);
* ``kinematics.jacobian`` for one configuration.

It checks that the three agree and prints ratios. Run with::

    pip install -e '.[bench]' && python bench/bench_export_code.py
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
import timeit
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import robots  # noqa: E402
from kinematics import fk, jacobian, jacobian_dot, to_urdf  # noqa: E402
from kinematics.symbolic.typeset.ccode import c_identifier  # noqa: E402
from kinematics.symbolic.typeset.export import export_c  # noqa: E402

HARNESS = r"""
#include <stdio.h>
#include <time.h>
#include "arm.h"
int main(void) {
    double q[%(n)d], qd[%(n)d], J[%(size)d], sink = 0.0;
    struct timespec t0, t1;
    long calls = %(calls)dL;
    for (int k = 0; k < %(n)d; ++k) { q[k] = 0.1 * (k + 1); qd[k] = 0.3 - 0.1 * k; }
    %(call)s;
    for (int r = 0; r < %(size)d; ++r) printf("%%.17g ", J[r]);
    (void)qd;
    printf("\n");
    double best = 1e30;
    for (int rep = 0; rep < 5; ++rep) {
        clock_gettime(CLOCK_MONOTONIC, &t0);
        for (long i = 0; i < calls; ++i) { q[i %% %(n)d] += 1e-9; %(call)s; sink += J[0]; }
        clock_gettime(CLOCK_MONOTONIC, &t1);
        double s = (t1.tv_sec - t0.tv_sec) + 1e-9 * (t1.tv_nsec - t0.tv_nsec);
        if (s < best) best = s;
    }
    printf("%%.6e %%g\n", best / calls, sink);
    return 0;
}
"""


def per_call(fn, min_time: float = 0.3) -> float:
    number = 1
    while timeit.timeit(fn, number=number) < min_time / 5:
        number *= 2
    return min(timeit.repeat(fn, number=number, repeat=5)) / number


def time_c(robot, folder: Path, what: str = "jacobian") -> tuple[float, np.ndarray]:
    """Seconds per call of the exported C function ``NAME_<what>`` (timed in C) and its result at
    q = 0.1, 0.2, …, q̇ = 0.3, 0.2, … (J, T or J̇, flattened row-major)."""
    cc = shutil.which("cc")
    if cc is None:
        raise SystemExit("no C compiler: python tests/install_test_deps.py installs one")
    header, source = export_c(robot, "arm")
    (folder / "arm.h").write_text(header)
    (folder / "arm.c").write_text(source)
    function = c_identifier(robot.name, reserved=frozenset()) + "_" + what
    size = {"fk": 16}.get(what, 6 * robot.dof)
    call = f"{function}(q, qd, J)" if what == "jacobian_dot" else f"{function}(q, J)"
    values = {"n": robot.dof, "size": size, "calls": 2_000_000, "call": call}
    (folder / "main.c").write_text(HARNESS % values)
    exe = folder / "bench"
    subprocess.run(
        [cc, "-O2", "-o", str(exe), str(folder / "main.c"), str(folder / "arm.c"), "-lm"], check=True
    )
    out = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout.split("\n")
    M = np.array([float(v) for v in out[0].split()])
    return float(out[1].split()[0]), M


def pinocchio_time(pin, robot, q: np.ndarray) -> tuple[float, np.ndarray]:
    model = pin.buildModelFromXML(to_urdf(robot))
    data = model.createData()
    fid = model.getFrameId("tool")
    seconds = per_call(lambda: pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL_WORLD_ALIGNED))
    return seconds, pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL_WORLD_ALIGNED)


def bench_robot(name: str, pin) -> None:
    robot = robots.load(name)
    q = 0.1 * np.arange(1, robot.dof + 1)
    with tempfile.TemporaryDirectory() as tmp:
        c_time, J_c = time_c(robot, Path(tmp))
    J_c = J_c.reshape(6, robot.dof)
    ours = per_call(lambda: jacobian(robot, q))
    print(f"\n{name}: {robot.dof} joints; max |J_C − J_numpy| = {np.abs(J_c - jacobian(robot, q)).max():.1e}")
    print(f"  exported C function (timed in C)          {c_time * 1e9:9.1f} ns")
    print(f"  kinematics.jacobian, one configuration    {ours * 1e9:9.1f} ns")
    if pin is not None:
        pin_time, J_pin = pinocchio_time(pin, robot, q)
        print(
            f"  Pinocchio computeFrameJacobian (Python)   {pin_time * 1e9:9.1f} ns"
            f"   (max |J_C − J_pin| = {np.abs(J_c - J_pin).max():.1e})"
        )
        print(f"  ratio Pinocchio / exported C              {pin_time / c_time:9.2f}")
    print(f"  ratio kinematics.jacobian / exported C    {ours / c_time:9.2f}")
    qd = 0.3 - 0.1 * np.arange(robot.dof)
    for what, numpy_name, reference in (
        ("fk", "kinematics.fk", lambda: fk(robot, q)),
        ("jacobian_dot", "kinematics.jacobian_dot", lambda: jacobian_dot(robot, q, qd)),
    ):
        with tempfile.TemporaryDirectory() as tmp:
            seconds, M = time_c(robot, Path(tmp), what)
        numpy_time = per_call(reference)
        error = np.abs(M - reference().ravel()).max()
        print(
            f"  exported {what:13s} (timed in C)          {seconds * 1e9:9.1f} ns"
            f"   (max |C − numpy| = {error:.1e})"
        )
        print(
            f"  {numpy_name:24s} one configuration {numpy_time * 1e9:9.1f} ns"
            f"   ratio numpy / C {numpy_time / seconds:7.2f}"
        )


def main() -> None:
    try:
        import pinocchio as pin
    except ImportError:
        pin = None
        print("Pinocchio is not installed (pip install -e '.[bench]'): its column is left out")
    for name in ("puma560", "panda"):
        bench_robot(name, pin)


if __name__ == "__main__":
    main()
