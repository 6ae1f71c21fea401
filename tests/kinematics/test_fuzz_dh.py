"""Fuzzing the model's inputs: generated DH tables and configurations, hostile values included.

Every case must end in one of two ways: a result that is sound (a robot whose arrays are all
finite and whose forward kinematics are rigid; finite, rigid results for q), or a
JacobianLabError. Anything else (an OverflowError, TypeError, KeyError, a NumPy warning turned
into an error, NaN in a result, a slow or memory-hungry case) fails the test. The generator is
seeded, so a failure names a case that can be replayed.
"""

from __future__ import annotations

import math
import random
import time
import tracemalloc
import warnings
from fractions import Fraction

import numpy as np
import pytest

import robots
from kinematics import (
    JacobianLabError,
    Robot,
    assess,
    fk,
    jacobian,
    jacobian_dot,
    link_frames,
    manipulability,
)

N_TABLES = 400
N_CONFIGURATIONS = 300
MAX_SECONDS_PER_CASE = 0.5  # [CPU s of this thread]: another job on the machine cannot inflate it
MAX_BYTES_PER_CASE = 20 * 1024 * 1024

KEYS = ["joint", "a", "alpha", "d", "theta", "qlim", "name"]
ODD_KEYS = ["alfa", "A", "length", "", " a", 1, None, (1, 2), b"a", 2.5]
NUMBERS = [
    0,
    1,
    -1,
    0.5,
    -0.25,
    3,
    1e-300,
    1e3,
    1e14,
    9.99e14,
    1e15,
    2e15,
    1e16,
    1e18,
    1e19,
    1e300,
    -1e300,
    10**20,
    10**400,
    -(10**400),
    Fraction(1, 3),
    np.float32(0.5),
    np.int64(2),
    np.float64(-2.0),
]
HOSTILE = [
    math.nan,
    math.inf,
    -math.inf,
    "1",
    "1e400",
    "nan",
    "",
    b"1",
    True,
    False,
    np.bool_(True),
    None,
    1 + 2j,
    [1.0],
    {},
    (0.1, 0.2),
    object(),
    np.array([1.0]),
    np.nan,
]
KINDS = ["revolute", "prismatic", "revolute", "prismatic", "revolut", "Prismatic", "", 3, None, ["revolute"]]
FRAMES = ["base", "tool", "base", "world", "", None, 0, "TOOL"]


def value(rng: random.Random) -> object:
    return rng.choice(NUMBERS) if rng.random() < 0.75 else rng.choice(HOSTILE)


def limits(rng: random.Random) -> object:
    r = rng.random()
    if r < 0.6:
        lo = rng.uniform(-3, 0)
        return (lo, lo + rng.uniform(0.1, 6))
    if r < 0.8:
        return rng.choice([(-1e16, 1e16), (-1e308, 1e308), (-math.inf, math.inf), (0.0, math.inf), None])
    if r < 0.92:
        return (value(rng), value(rng))
    return rng.choice([(1.0,), "ab", [1, 2, 3], 5, {"lo": 0}, (math.nan, 1.0), (math.inf, -math.inf)])


def dh_row(rng: random.Random) -> object:
    if rng.random() < 0.01:
        return rng.choice([42, "row", None, [1, 2, 3], ("joint", "revolute")])
    row: dict = {
        "joint": rng.choice(KINDS[:4]),
        "a": rng.uniform(-1, 1),
        "alpha": rng.choice([0.0, math.pi / 2, -math.pi / 2, rng.uniform(-4, 4)]),
        "d": rng.uniform(-1, 1),
        "theta": rng.uniform(-4, 4),
    }
    for _ in range(rng.choice([0] * 17 + [1, 2, 3])):
        action = rng.random()
        key = rng.choice(KEYS)
        if action < 0.55:
            row[key] = limits(rng) if key == "qlim" else rng.choice(KINDS) if key == "joint" else value(rng)
        elif action < 0.75:
            row.pop(key, None)
        else:
            row[rng.choice(ODD_KEYS)] = value(rng)
    if rng.random() < 0.3:
        row["qlim"] = limits(rng)
    return row


def rows_of(rng: random.Random) -> list:
    """1 to 7 rows; most tables have a single defect at most, so both outcomes are common."""
    return [dh_row(rng) for _ in range(rng.choice([1, 2, 2, 3, 3, 4, 6, 7]))]


def sometimes(rng: random.Random, good: object, bad: list) -> object:
    """``good`` nine times in ten, else one of ``bad``."""
    return good if rng.random() < 0.9 else rng.choice(bad)


def transform(rng: random.Random) -> object:
    r = rng.random()
    if r < 0.8:
        return None
    T = np.eye(4)
    angle = rng.uniform(-3, 3)
    c, s = math.cos(angle), math.sin(angle)
    T[:2, :2] = [[c, -s], [s, c]] if r < 0.95 else [[c, -s], [s, -c]]  # the second is a reflection
    T[:3, 3] = [rng.choice([0.1, -2.0, 0.3, 1e14, 2e15, math.nan]) for _ in range(3)]
    return T if rng.random() < 0.9 else rng.choice([np.eye(3), "eye", [[1, 0], [0, 1]], T.astype(complex)])


def table(rng: random.Random) -> tuple[object, dict]:
    rows: object = rows_of(rng)
    if rng.random() < 0.04:
        rows = rng.choice([[], "rows", {"joint": "revolute"}, 5, None, (r for r in range(2))])
    kwargs = {
        "convention": sometimes(
            rng, rng.choice(["standard", "modified"]), ["craig", "Standard", "", None, 1]
        ),
        "base": transform(rng),
        "tool": transform(rng),
        "planar": sometimes(rng, rng.choice([False, True]), ["yes", 1, None]),
        "task": sometimes(rng, rng.choice(["auto", "full", "linear"]), ["position", "", None]),
    }
    return rows, kwargs


def assert_rigid(T: np.ndarray) -> None:
    assert np.isfinite(T).all()
    R = T[..., :3, :3]
    gram = np.swapaxes(R, -1, -2) @ R
    assert np.abs(gram - np.eye(3)).max() < 1e-9
    assert np.all(np.linalg.det(R) > 0)


def check_robot(robot: Robot, rng: random.Random) -> None:
    """A robot that was accepted is sound: finite arrays, rigid fk, finite J at home and elsewhere."""
    for ax in robot.axes:
        assert math.isfinite(ax.multiplier) and math.isfinite(ax.offset)
        assert np.isfinite(ax.T_parent_joint).all() and np.isfinite(ax.T_joint_child).all()
    assert np.isfinite(robot.base).all() and np.isfinite(robot.tool).all()
    for j in robot.joints:
        assert j.qlim is None or (all(math.isfinite(v) for v in j.qlim) and j.qlim[0] < j.qlim[1])
    assert np.isfinite(robot.home).all()
    q = robot.home + np.array([rng.uniform(-3, 3) for _ in range(robot.dof)])
    for x in (robot.home, q):
        assert_rigid(fk(robot, x))
        assert_rigid(link_frames(robot, x))
        assert np.isfinite(jacobian(robot, x)).all()
        assert np.isfinite(jacobian(robot, x, frame="tool")).all()
    assert_rigid(fk(robot, np.stack([robot.home, q])))


def run_case(case: object, label: str) -> str:
    """Run ``case()`` with NumPy warnings as errors, in a time and memory bound; "ok" or "refused"."""
    tracemalloc.reset_peak()
    start = time.thread_time()
    # NumPy's default error handling (warn on overflow, invalid and division by zero; underflow
    # to zero is harmless) with every warning turned into an error.
    with warnings.catch_warnings(), np.errstate(over="warn", invalid="warn", divide="warn", under="ignore"):
        warnings.simplefilter("error")
        try:
            case()  # type: ignore[operator]
            outcome = "ok"
        except JacobianLabError as exc:
            assert str(exc), label
            outcome = "refused"
    seconds = time.thread_time() - start
    assert seconds < MAX_SECONDS_PER_CASE, f"{label} took {seconds:.2f} s"
    assert tracemalloc.get_traced_memory()[1] < MAX_BYTES_PER_CASE, f"{label} used too much memory"
    return outcome


@pytest.fixture
def traced():
    tracemalloc.start()
    yield
    tracemalloc.stop()


@pytest.mark.slow
def test_generated_dh_tables_give_sound_robots_or_project_errors(traced):
    rng = random.Random(20261201)
    outcomes = {"ok": 0, "refused": 0}
    for i in range(N_TABLES):
        rows, kwargs = table(rng)
        check_rng = random.Random(i)

        def case(rows=rows, kwargs=kwargs, check_rng=check_rng):
            check_robot(Robot.from_dh(rows, **kwargs), check_rng)

        outcomes[run_case(case, f"table {i}: rows={rows!r}, kwargs={kwargs!r}")] += 1
    # The generator must exercise both outcomes substantially, or the test proves little.
    assert outcomes["ok"] > N_TABLES // 5 and outcomes["refused"] > N_TABLES // 5, outcomes


def configuration(rng: random.Random, n: int) -> object:
    r = rng.random()
    if r < 0.35:
        return [
            rng.choice([rng.uniform(-4, 4), rng.uniform(-4, 4), 1e16, -3e17, 1e14, 9e14]) for _ in range(n)
        ]
    if r < 0.5:
        return [[rng.uniform(-4, 4) for _ in range(n)] for _ in range(rng.randint(0, 3))]
    if r < 0.8:
        return [value(rng) for _ in range(n)]
    return rng.choice(
        [
            [0.0] * (n + 1),
            [[0.0] * n, [0.0]],
            "0" * n,
            None,
            1.0,
            {"q": 1},
            b"\x00" * n,
            np.zeros((2, 2, n)),
            np.zeros(n, dtype=complex),
            np.zeros(n, dtype=object),
        ]
    )


def test_generated_configurations_give_finite_results_or_project_errors(traced):
    rng = random.Random(7)
    library = [robots.load(name) for name in ("puma560", "stanford", "scara", "panda", "trr")]
    outcomes = {"ok": 0, "refused": 0}
    for i in range(N_CONFIGURATIONS):
        robot = rng.choice(library)
        q, qd, frame = configuration(rng, robot.dof), configuration(rng, robot.dof), rng.choice(FRAMES)

        def case(robot=robot, q=q, qd=qd, frame=frame):
            T = fk(robot, q)
            assert_rigid(T)
            J = jacobian(robot, q, frame=frame)
            assert np.isfinite(J).all() and J.shape[-2:] == (6, robot.dof)
            if np.ndim(J) == 2:
                assert np.isfinite(manipulability(J, "linear"))
                report = assess(robot, q, J=jacobian(robot, q))
                assert np.isfinite(report.lost_twist).all() and np.isfinite(report.null_motion).all()
                assert np.isfinite(jacobian_dot(robot, q, qd)).all()

        outcomes[
            run_case(case, f"configuration {i}: robot={robot.name}, q={q!r}, qd={qd!r}, frame={frame!r}")
        ] += 1
    assert outcomes["ok"] > N_CONFIGURATIONS // 10 and outcomes["refused"] > N_CONFIGURATIONS // 5, outcomes
