"""Jacobian speed, side by side with the libraries users would pick instead.

Times, in one run on this machine:

* ours: ``kinematics.jacobian`` for one configuration, and batched
  (N = 100 000 configurations, cost per configuration);
* Robotics Toolbox for Python: ``jacob0`` of its DH model and of the model's
  compiled ETS (``robot.ets().jacob0``);
* Pinocchio: ``computeFrameJacobian(..., LOCAL_WORLD_ALIGNED)`` on a model
  built from the URDF our robot exports (so it is the very same chain).

for Puma 560 and Panda, checks that everybody computes the same Jacobian,
and prints ratios. Run with::

    pip install -e '.[bench]' && python bench/bench_kinematics.py
"""

from __future__ import annotations

import argparse
import timeit

import numpy as np

import robots
from kinematics import jacobian, to_urdf


def per_call(fn, min_time: float = 0.3) -> float:
    """Best-of-5 seconds per call of ``fn``."""
    number = 1
    while timeit.timeit(fn, number=number) < min_time / 5:
        number *= 2
    return min(timeit.repeat(fn, number=number, repeat=5)) / number


def bench_robot(name: str, rtb_name: str, batch: int) -> list[tuple[str, float]]:
    robot = robots.load(name)
    rng = np.random.default_rng(0)
    q = rng.uniform(-1, 1, robot.dof)
    Q = rng.uniform(-1, 1, (batch, robot.dof))
    rows = [("ours, single", per_call(lambda: jacobian(robot, q)))]
    rows.append(("ours, batched (per configuration)", per_call(lambda: jacobian(robot, Q), 1.0) / batch))
    J_ours = jacobian(robot, q)

    import roboticstoolbox as rtb

    dh = getattr(rtb.models.DH, rtb_name)()
    ets = dh.ets()
    rows.append(("RTB DH jacob0", per_call(lambda: dh.jacob0(q))))
    rows.append(("RTB compiled ETS jacob0", per_call(lambda: ets.jacob0(q))))
    # RTB's models carry their own base/tool: compare position rows of the arm without tool offsets
    # only as a sanity check of the same robot (angular rows are frame-independent of the tool offset).
    J_rtb = dh.jacob0(q)
    angular_gap = np.abs(J_rtb[3:] - J_ours[3:]).max()

    import pinocchio as pin

    model = pin.buildModelFromXML(to_urdf(robot))
    data = model.createData()
    fid = model.getFrameId("tool")
    rows.append(
        (
            "Pinocchio computeFrameJacobian",
            per_call(lambda: pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL_WORLD_ALIGNED)),
        )
    )
    J_pin = pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL_WORLD_ALIGNED)
    pin_gap = np.abs(J_pin - J_ours).max()
    print(
        f"\n{name}: {robot.dof} joints.  max |J_ours − J_pinocchio| = {pin_gap:.1e}; "
        f"max |ω rows ours − RTB {rtb_name}| = {angular_gap:.1e}"
    )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--batch", type=int, default=100_000)
    args = parser.parse_args()
    for name, rtb_name in (("puma560", "Puma560"), ("panda", "Panda")):
        rows = bench_robot(name, rtb_name, args.batch)
        t = dict(rows)
        fastest_single_peer = min(v for k, v in rows if not k.startswith("ours"))
        for label, seconds in rows:
            print(f"  {label:40s} {seconds * 1e6:9.2f} µs")
        single = t["ours, single"]
        ets, pin_ = t["RTB compiled ETS jacob0"], t["Pinocchio computeFrameJacobian"]
        print(f"  ratio ours single / RTB compiled ETS      {single / ets:6.2f}   (target ≤ 3)")
        print(f"  ratio ours single / Pinocchio             {single / pin_:6.2f}")
        print(
            f"  ratio ours batched / fastest peer single  "
            f"{t['ours, batched (per configuration)'] / fastest_single_peer:6.2f}   (target ≤ 1)"
        )


if __name__ == "__main__":
    main()
