"""Corpus check: every URDF of example-robot-data, every chain, against independent references.

For each ``.urdf`` file shipped by the ``example-robot-data`` wheel (``pip install -e '.[bench]'``)
this lists its chains (``kinematics.urdf.chains``: the default one and one per leaf), loads each
with our reader, and compares at random configurations:

* ``fk`` with yourdfpy's own scene graph (``update_cfg`` then ``get_transform(tip, base)``);
* ``J`` with Pinocchio (``getFrameJacobian`` in LOCAL_WORLD_ALIGNED axes, turned into base axes,
  mimic columns summed with their multipliers) when ``pin`` is installed, else with central
  finite differences of the yourdfpy transforms (accurate to ~1e-8 only).

Usage::

    python bench/bench_urdf_corpus.py [--configs 20] [--seed 0] [--default-only]

``--default-only`` only counts the files that open with no tip (``robot_from_urdf(path)``); it
runs against any version of the code (set ``PYTHONPATH`` to compare two checkouts).
"""

from __future__ import annotations

import argparse
import importlib.metadata
import logging
import math
import sys
import time
from collections import Counter
from pathlib import Path

import numpy as np

from kinematics import fk, jacobian
from kinematics.errors import JacobianLabError
from kinematics.urdf import robot_from_urdf


def urdf_files() -> list[Path]:
    """The ``.urdf`` files installed by the example-robot-data wheel, sorted."""
    try:
        files = importlib.metadata.files("example-robot-data") or []
    except importlib.metadata.PackageNotFoundError:
        sys.exit("example-robot-data is not installed: pip install -e '.[bench]'")
    return sorted(Path(f.locate()).resolve() for f in files if str(f).endswith(".urdf"))


def random_q(robot, rng: np.random.Generator, count: int) -> np.ndarray:
    """``count`` configurations: uniform within finite limits, else in [-π, π] or [-0.5, 0.5] m."""
    lo, hi = robot.qlim
    wide = np.where(np.array(robot.joint_types) == "revolute", math.pi, 0.5)
    lo = np.where(np.isfinite(lo), lo, -wide)
    hi = np.where(np.isfinite(hi), hi, wide)
    return rng.uniform(lo, hi, size=(count, robot.dof))


class PinReference:
    """Pinocchio's model of a whole URDF file (fixed base, mimic joints as independent joints)."""

    def __init__(self, path: Path) -> None:
        import pinocchio as pin

        self.pin = pin
        self.model = pin.buildModelFromUrdf(str(path))
        self.data = self.model.createData()

    def fk_jacobian(self, robot, q: np.ndarray, base: str, tip: str) -> tuple[np.ndarray, np.ndarray]:
        pin, model, data = self.pin, self.model, self.data
        qp = pin.neutral(model)
        for ax in robot.axes:
            joint = model.joints[model.getJointId(ax.name)]
            v = ax.multiplier * q[ax.joint_index] + ax.offset
            if joint.nq == 1:
                qp[joint.idx_q] = v
            else:  # continuous joint: (cos θ, sin θ)
                qp[joint.idx_q : joint.idx_q + 2] = (math.cos(v), math.sin(v))
        pin.computeJointJacobians(model, data, qp)
        pin.updateFramePlacements(model, data)
        body = pin.FrameType.BODY
        b, t = model.getFrameId(base, body), model.getFrameId(tip, body)
        T = (data.oMf[b].inverse() * data.oMf[t]).homogeneous
        Jw = pin.getFrameJacobian(model, data, t, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        J = np.zeros((6, robot.dof))
        for ax in robot.axes:
            J[:, ax.joint_index] += ax.multiplier * Jw[:, model.joints[model.getJointId(ax.name)].idx_v]
        R = data.oMf[b].rotation
        return T, np.vstack([R.T @ J[:3], R.T @ J[3:]])


def yourdfpy_fk(urdf, robot, q: np.ndarray, base: str, tip: str) -> np.ndarray:
    urdf.update_cfg({name: float(v) for name, v in zip(robot.joint_names, q, strict=True)})
    return urdf.get_transform(frame_to=tip, frame_from=base)


def fd_jacobian(urdf, robot, q: np.ndarray, base: str, tip: str, h: float = 1e-6) -> np.ndarray:
    from kinematics.transforms import rotation_log

    J = np.zeros((6, robot.dof))
    for k in range(robot.dof):
        dq = np.zeros(robot.dof)
        dq[k] = h
        Tp, Tm = yourdfpy_fk(urdf, robot, q + dq, base, tip), yourdfpy_fk(urdf, robot, q - dq, base, tip)
        J[:3, k] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
        J[3:, k] = Tm[:3, :3] @ rotation_log(Tm[:3, :3].T @ Tp[:3, :3]) / (2 * h)
    return J


def check_file(path: Path, configs: int, rng: np.random.Generator) -> dict:
    import yourdfpy

    from kinematics.urdf import chains

    row = {"file": path.name, "chains": 0, "loaded": 0, "refused": Counter(), "fk": 0.0, "J": 0.0}
    row |= {"six": 0, "singular_home": 0}
    try:
        infos = chains(path)
    except JacobianLabError as exc:
        row["refused"][str(exc)[:90]] += 1
        return row
    row["chains"] = len(infos)
    default = next(i for i in infos if i.is_default)
    row["default"] = f"{default.tip_link} ({default.dof})"
    urdf = yourdfpy.URDF.load(str(path), build_scene_graph=True, load_meshes=False)
    try:
        ref = PinReference(path)
    except ImportError:
        ref = None
    for info in infos:
        try:
            robot = robot_from_urdf(path, info.base_link, info.tip_link)
        except JacobianLabError as exc:
            row["refused"][str(exc)[:90]] += 1
            continue
        row["loaded"] += 1
        if robot.dof >= 6:
            row["six"] += 1
            row["singular_home"] += int(singular_start(robot))
        for q in random_q(robot, rng, configs):
            T = yourdfpy_fk(urdf, robot, q, info.base_link, info.tip_link)
            row["fk"] = max(row["fk"], float(np.abs(fk(robot, q) - T).max()))
            if ref is not None:
                T_pin, J_ref = ref.fk_jacobian(robot, q, info.base_link, info.tip_link)
                row["fk"] = max(row["fk"], float(np.abs(fk(robot, q) - T_pin).max()))
            else:
                J_ref = fd_jacobian(urdf, robot, q, info.base_link, info.tip_link)
            row["J"] = max(row["J"], float(np.abs(jacobian(robot, q) - J_ref).max()))
    return row


def singular_start(robot) -> bool:
    """True when the robot's start configuration has σmin/σmax ≤ 1e-3 over its task rows."""
    from kinematics.analysis import singular_values, task_rows

    s = singular_values(jacobian(robot, robot.home), task_rows(robot))
    return not s[-1] > 1e-3 * s[0]


def default_only(files: list[Path]) -> None:
    opened, reasons, singular = 0, Counter(), 0
    for path in files:
        try:
            robot = robot_from_urdf(path)
            opened += 1
            singular += int(singular_start(robot))
        except Exception as exc:  # the old code raises more than its own errors
            reasons[f"{type(exc).__name__}: {str(exc)[:70]}"] += 1
    print(f"{opened} of {len(files)} files open with no tip; {singular} of them at a singular start pose")
    for reason, n in reasons.most_common():
        print(f"  {n:3d}  {reason}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--configs", type=int, default=20, help="random configurations per chain")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--default-only", action="store_true", help="only count files that open with no tip")
    args = parser.parse_args()
    logging.getLogger("yourdfpy").setLevel(logging.ERROR)
    files = urdf_files()
    if args.default_only:
        default_only(files)
        return
    rng = np.random.default_rng(args.seed)
    start = time.perf_counter()
    rows = []
    print(f"{'file':40s} {'chains':>6s} {'loaded':>6s} {'fk err':>9s} {'J err':>9s}  default tip (dof)")
    for path in files:
        r = check_file(path, args.configs, rng)
        rows.append(r)
        print(
            f"{r['file'][:40]:40s} {r['chains']:6d} {r['loaded']:6d} {r['fk']:9.1e} {r['J']:9.1e}  "
            f"{r.get('default', '-')}",
            flush=True,
        )
        for reason, n in r["refused"].items():
            print(f"{'':42s}refused {n}: {reason}")
    n_chains = sum(r["chains"] for r in rows)
    n_loaded = sum(r["loaded"] for r in rows)
    opened = sum(1 for r in rows if "default" in r)
    print(
        f"\n{len(rows)} files, {opened} open with no tip; {n_chains} chains, {n_loaded} loaded, "
        f"{n_chains - n_loaded} refused; worst fk error {max(r['fk'] for r in rows):.1e}, "
        f"worst J error {max(r['J'] for r in rows):.1e} ({args.configs} configurations per chain, "
        f"{time.perf_counter() - start:.0f} s)\n"
        f"chains with 6 or more joints: {sum(r['six'] for r in rows)}, starting at a singular pose "
        f"(σmin/σmax ≤ 1e-3 over the task rows): {sum(r['singular_home'] for r in rows)}"
    )


if __name__ == "__main__":
    main()
