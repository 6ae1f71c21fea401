"""Corpus check of the default chain: every real URDF found, opened with no ``--tip``.

Where the files come from (nothing is downloaded by this script, none is kept in the repo): the
``pybullet`` wheel's ``pybullet_data`` (Panda, KUKA iiwa, xArm, PR2 gripper, quadrupeds, ...) and the
``example-robot-data`` wheel (TIAGo, PR2, UR, Panda, Baxter, Talos, human, ...), either installed or
unpacked anywhere, e.g.::

    pip download --no-deps pybullet example-robot-data -d /tmp/corpus/dl
    cd /tmp/corpus && for w in dl/*.whl; do unzip -qo "$w" -d unpacked; done
    PYTHONPATH=$PWD python bench/corpus_urdf.py /tmp/corpus/unpacked

For each file this prints the default chain (base → tip, dof), whether it ends at a tool frame, the
start pose's κ over the task rows and whether it is regular (κ ≤ 50), or the error in words; then a
summary. Files with no moving joint (a cube, a table, a mug) are counted and skipped; the
``random_urdfs`` of pybullet_data (objects) are skipped. An arm (a chain of 6–7 joints) is judged
right by name: its tip is a tool frame, an end-effector, a hand or a flange, not a finger, a foot or a
leg. With Pinocchio installed (``pin``), J at random configurations is compared with Pinocchio's.

Usage::

    python bench/corpus_urdf.py [ROOT ...] [--configs 10] [--seed 0]
"""

from __future__ import annotations

import argparse
import importlib.metadata
import math
import re
import sys
import time
from collections import Counter
from pathlib import Path

import numpy as np

from kinematics import jacobian
from kinematics.analysis import singular_values, task_rows
from kinematics.errors import JacobianLabError
from kinematics.urdf import chains, robot_from_urdf

TOOL = re.compile(r"(tool0|tcp|flange|ee_link|tool_frame|tool_link|ee_gripper_link|grasptarget)$", re.I)
"""A tip named like a tool frame."""
ARM_END = re.compile(
    r"tool|tcp|flange|(^|_)ee(_|$)|eef|hand|grasp|wrist|gripper|end_?effector|palm|_tip$|nub", re.I
)
"""A tip named like the end of an arm: a tool, a hand, a wrist, a gripper's body or a palm."""
WRONG_END = re.compile(
    r"finger|jaw|knuckle|thumb|foot|toe|leg|ankle|knee|calf|shin|hip|thigh|head|wheel|camera|imu|sensor", re.I
)
"""A tip named like a finger, a leg, a head or a sensor: not the end of an arm."""
EXPECTED = {
    "human_description/robots/human.urdf": "left_hand_virtual",
    "alex_description/urdf/alex_psyonic_hands.urdf": "LeftPsyonicAbilityBaseLink",
    "pr2_description/urdf/pr2.urdf": "l_gripper_tool_frame",
    "franka_panda/panda.urdf": "panda_grasptarget",
    "tiago_description/robots/tiago.urdf": "arm_tool_link",
    "tiago_description/robots/tiago_dual.urdf": "arm_left_tool_link",
    "tiago_description/robots/tiago_no_hand.urdf": "arm_tool_link",
    "tiago_pro_description/robots/tiago_pro.urdf": "arm_left_tool_link",
    "panda_description/urdf/panda.urdf": "panda_hand_tcp",
    "baxter_description/urdf/baxter.urdf": "left_hand_link",
    "kuka_iiwa/model.urdf": "lbr_iiwa_link_7",
    "ur_description/urdf/ur5_robot.urdf": "tool0",
}
"""The tip each named robot should open at (no Interbotix arm ships in these wheels)."""


def arm_end(tip: str) -> bool:
    return bool(TOOL.search(tip) or ARM_END.search(tip)) and not WRONG_END.search(tip)


def roots_default() -> list[Path]:
    """The installed wheels' data folders, when they are installed."""
    roots = []
    for dist, marker in (("pybullet", "pybullet_data"), ("example-robot-data", "example-robot-data")):
        try:
            files = importlib.metadata.files(dist) or []
        except importlib.metadata.PackageNotFoundError:
            continue
        for f in files:
            if marker in str(f) and str(f).endswith(".urdf"):
                path = Path(f.locate()).resolve()
                while path.name != marker and path.parent != path:
                    path = path.parent
                roots.append(path)
                break
    return roots


def urdf_files(roots: list[Path]) -> list[Path]:
    out = set()
    for root in roots:
        out |= {p.resolve() for p in root.rglob("*.urdf") if "random_urdfs" not in p.parts}
    return sorted(out)


def kappa_at_home(robot) -> float:
    s = singular_values(jacobian(robot, robot.home), task_rows(robot))
    return math.inf if not s[-1] > 0 else float(s[0] / s[-1])


def random_q(robot, rng: np.random.Generator, count: int) -> np.ndarray:
    lo, hi = robot.qlim
    wide = np.where(np.array(robot.joint_types) == "revolute", math.pi, 0.5)
    lo = np.where(np.isfinite(lo), lo, -wide)
    hi = np.where(np.isfinite(hi), hi, wide)
    return rng.uniform(lo, hi, size=(count, robot.dof))


def pin_error(path: Path, robot, base: str, tip: str, qs: np.ndarray) -> float:
    """Largest |J − J_pinocchio| over ``qs`` (J in base axes, mimic columns summed)."""
    import pinocchio as pin

    model = pin.buildModelFromUrdf(str(path))
    data = model.createData()
    worst = 0.0
    for q in qs:
        qp = pin.neutral(model)
        for ax in robot.axes:
            joint = model.joints[model.getJointId(ax.name)]
            v = ax.multiplier * q[ax.joint_index] + ax.offset
            if joint.nq == 1:
                qp[joint.idx_q] = v
            else:  # continuous: (cos, sin)
                qp[joint.idx_q : joint.idx_q + 2] = (math.cos(v), math.sin(v))
        pin.computeJointJacobians(model, data, qp)
        pin.updateFramePlacements(model, data)
        b, t = model.getFrameId(base, pin.FrameType.BODY), model.getFrameId(tip, pin.FrameType.BODY)
        Jw = np.asarray(pin.getFrameJacobian(model, data, t, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED))
        Jw = Jw.reshape(6, model.nv)  # one column comes back as a vector
        J = np.zeros((6, robot.dof))
        for ax in robot.axes:
            J[:, ax.joint_index] += ax.multiplier * Jw[:, model.joints[model.getJointId(ax.name)].idx_v]
        R = data.oMf[b].rotation
        J = np.vstack([R.T @ J[:3], R.T @ J[3:]])
        worst = max(worst, float(np.abs(jacobian(robot, q) - J).max()))
    return worst


def base_and_tip(robot) -> tuple[str, str]:
    m = re.search(r"from link '([^']*)' to link '([^']*)'", robot.description)
    if m is None:
        raise RuntimeError(f"description names no chain: {robot.description[:120]}")
    return m.group(1), m.group(2)


def short(path: Path, roots: list[Path]) -> str:
    """``path`` from its package's folder: ``pybullet_data/...`` or ``<robot>_description/...``."""
    text = path.as_posix()
    for cut in ("/example-robot-data/robots/", "/pybullet_data/"):
        if cut in text:
            return text.split(cut, 1)[1]
    for root in roots:
        if path.is_relative_to(root.resolve()):
            return path.relative_to(root.resolve()).as_posix()
    return text


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("roots", nargs="*", type=Path, help="folders searched for .urdf files")
    parser.add_argument("--configs", type=int, default=10, help="random configurations per chain (Pinocchio)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    roots = args.roots or roots_default()
    files = urdf_files(roots)
    if not files:
        sys.exit(
            "no URDF found: give a folder, or install pybullet or example-robot-data (see the module text)"
        )
    try:
        import pinocchio  # noqa: F401

        have_pin = True
    except ImportError:
        have_pin = False
    rng = np.random.default_rng(args.seed)
    start = time.perf_counter()
    opened, static, errors, regular, irregular = 0, 0, Counter(), 0, []
    arms, arms_right, arms_67, arms_67_right, arms_tool, wrong = 0, 0, 0, 0, 0, []
    pin_worst, pin_failed, named = 0.0, [], {}
    for path in files:
        name = short(path, roots)
        try:
            robot = robot_from_urdf(path)
            infos = chains(path)
        except JacobianLabError as exc:
            text = str(exc)
            if "no moving joint" in text:
                static += 1
                continue
            errors[text[:100]] += 1
            print(f"{name[:58]:58s} refused: {text[:150]}")
            continue
        except Exception as exc:  # a crash, not an error in words: counted apart
            errors[f"CRASH {type(exc).__name__}: {str(exc)[:80]}"] += 1
            print(f"{name[:58]:58s} CRASH {type(exc).__name__}: {exc}")
            continue
        opened += 1
        base, tip = base_and_tip(robot)
        kappa = kappa_at_home(robot)
        regular += kappa <= 50
        if kappa > 50:
            irregular.append(f"{name} (κ = {kappa:.3g})")
        # An arm: a chain of 6 or more joints to a tool, hand, wrist or gripper, or a serial 6–7 joint robot.
        serial = len(infos) == 1 and 6 <= infos[0].dof <= 7
        arm_chains = [i for i in infos if i.dof >= 6 and arm_end(i.tip_link)]
        verdict = ""
        if serial or arm_chains or name in EXPECTED:
            ok = EXPECTED[name] == tip if name in EXPECTED else serial or arm_end(tip)
            arms += 1
            arms_right += ok
            arms_tool += bool(TOOL.search(tip))
            six_seven = serial or any(i.dof <= 7 for i in arm_chains)
            arms_67 += six_seven
            arms_67_right += six_seven and ok
            verdict = "arm: right" if ok else "arm: WRONG"
            if not ok:
                wrong.append(f"{name} → {tip}")
        if name in EXPECTED:
            named[name] = (tip, EXPECTED[name])
        err = ""
        if have_pin:
            try:
                e = pin_error(path, robot, base, tip, random_q(robot, rng, args.configs))
                pin_worst = max(pin_worst, e)
                err = f"J−pin {e:.0e}"
            except Exception as exc:
                pin_failed.append(f"{name}: {type(exc).__name__}: {str(exc)[:60]}")
                err = "pin: failed"
        tool = " [tool frame]" if TOOL.search(tip) else ""
        print(
            f"{name[:58]:58s} {base} → {tip} ({robot.dof}){tool} κ={kappa:.3g}"
            f"{'' if kappa <= 50 else ' (not regular)'} {verdict} {err}",
            flush=True,
        )
    print(
        f"\n{len(files)} URDF files ({', '.join(map(str, roots))}; pybullet's random_urdfs left out): "
        f"{static} have no moving joint, {opened} of the other {len(files) - static} open with no --tip, "
        f"{sum(errors.values())} are refused\n"
        f"{regular} of {opened} open at a regular start pose (κ ≤ 50)\n"
        f"arms (a chain of 6+ joints to a tool/hand/wrist/gripper, or a serial 6–7 joint robot): {arms}, "
        f"default chain right by name for {arms_right} ({arms_tool} at a tool frame); with an arm of 6–7 "
        f"joints: {arms_67}, right for {arms_67_right}"
    )
    for w in wrong:
        print(f"  wrong? {w}")
    for n, (tip, want) in sorted(named.items()):
        print(
            f"  {'ok ' if tip == want else 'NO '} {n}: opens at {tip}"
            + ("" if tip == want else f", not {want}")
        )
    for reason, n in errors.most_common():
        print(f"  refused {n} × {reason}")
    for i in irregular:
        print(f"  not regular at the start: {i}")
    if have_pin:
        print(
            f"J against Pinocchio ({args.configs} random configurations per default chain): "
            f"worst {pin_worst:.1e}"
        )
        for f in pin_failed:
            print(f"  Pinocchio failed on {f}")
    print(f"({time.perf_counter() - start:.0f} s)")


if __name__ == "__main__":
    main()
