"""Workspace samples and joint maps of manipulability (kinematics.maps)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import robots
from kinematics import (
    ConfigurationError,
    JacobianLabError,
    OptionError,
    fk,
    jacobian,
    manipulability,
    singular_values,
    task_rows,
)
from kinematics.maps import joint_map, measures, measures_dask, sampling_range, workspace


@pytest.mark.parametrize("name", ["puma560", "panda", "planar3", "trr", "iiwa14", "scara"])
def test_workspace_measures_equal_the_plain_svd_per_configuration(name):
    robot = robots.load(name)
    ws = workspace(robot, 300, seed=4)
    assert ws.q.shape == (300, robot.dof) and ws.points.shape == (300, 3)
    lim = sampling_range(robot)
    assert np.all(ws.q >= lim[0]) and np.all(ws.q <= lim[1])
    rows = task_rows(robot)
    for k in range(0, 300, 23):
        J = jacobian(robot, ws.q[k])
        s = singular_values(J, rows)
        assert ws.w[k] == pytest.approx(np.prod(s), rel=1e-8, abs=1e-12)
        assert ws.w[k] == pytest.approx(manipulability(J, rows), rel=1e-8, abs=1e-12)
        assert ws.inverse_kappa[k] == pytest.approx(s[-1] / s[0], abs=1e-7)
        assert np.allclose(ws.points[k], fk(robot, ws.q[k])[:3, 3], atol=1e-12)


def test_workspace_is_seeded_and_uniform():
    robot = robots.load("planar2")  # no limits: ±π
    a, b = workspace(robot, 4000, seed=1), workspace(robot, 4000, seed=1)
    assert np.array_equal(a.q, b.q) and not np.array_equal(a.q, workspace(robot, 4000, seed=2).q)
    assert np.allclose(sampling_range(robot), [[-math.pi] * 2, [math.pi] * 2])
    assert abs(a.q.mean()) < 0.1 and a.q.min() < -3.0 and a.q.max() > 3.0
    # the reach of a 2R arm with unit links: every point within 2 m of the base
    assert np.linalg.norm(a.points[:, :2], axis=1).max() <= 2.0 + 1e-12
    # w of a 2R arm is |l1 l2 sin q2|
    l1l2 = manipulability(jacobian(robot, [0.0, math.pi / 2]), task_rows(robot))
    assert np.allclose(a.w, l1l2 * np.abs(np.sin(a.q[:, 1])), atol=1e-12)


def test_workspace_larger_than_a_chunk():
    robot = robots.load("puma560")
    ws = workspace(robot, 5000, seed=0)
    idx = [0, 2047, 2048, 4095, 4999]
    J = jacobian(robot, ws.q[idx])
    assert np.allclose(ws.w[idx], manipulability(J, task_rows(robot)), rtol=1e-8)


@pytest.mark.parametrize(
    ("name", "i", "j"), [("panda", 1, 3), ("puma560", 2, 4), ("planar3", 0, 2), ("trr", 0, 2)]
)
def test_joint_map_values(name, i, j):
    robot = robots.load(name)
    rng = np.random.default_rng(6)
    q = robot.home
    m = joint_map(robot, q, i, j, resolution=21)
    lim = sampling_range(robot)
    assert m.w.shape == (21, 21) and m.inverse_kappa.shape == (21, 21)
    assert np.allclose(m.values_i[[0, -1]], lim[:, i]) and np.allclose(m.values_j[[0, -1]], lim[:, j])
    rows = task_rows(robot)
    for a, b in rng.integers(0, 21, (6, 2)):
        qq = np.array(q, dtype=float)
        qq[i], qq[j] = m.values_i[a], m.values_j[b]
        assert m.w[a, b] == pytest.approx(manipulability(jacobian(robot, qq), rows), rel=1e-8, abs=1e-12)


def test_joint_map_at_the_current_q():
    """A grid through the current values: the map there is manipulability(jacobian(q))."""
    robot = robots.load("puma560")
    q = robot.home.copy()
    lim = sampling_range(robot)
    q[1], q[2] = lim[0, 1] + 0.5 * (lim[1, 1] - lim[0, 1]), lim[0, 2] + 0.25 * (lim[1, 2] - lim[0, 2])
    m = joint_map(robot, q, 1, 2, resolution=41)  # grid points 20 and 10
    assert m.values_i[20] == pytest.approx(q[1], abs=1e-12) and m.values_j[10] == pytest.approx(
        q[2], abs=1e-12
    )
    w = manipulability(jacobian(robot, q), task_rows(robot))
    assert m.w[20, 10] == pytest.approx(w, rel=1e-9)


@pytest.mark.parametrize(
    ("call", "error", "word"),
    [
        (lambda r: workspace(r, -1, seed=0), OptionError, "n"),
        (lambda r: workspace(r, 10, seed="x"), OptionError, "seed"),
        (lambda r: workspace(r, 10, seed=0, rows=(8,)), OptionError, "rows"),
        (lambda r: joint_map(r, r.home, 0, 9), OptionError, "j"),
        (lambda r: joint_map(r, r.home, 2, 2), OptionError, "different"),
        (lambda r: joint_map(r, r.home, 0, 1, resolution=1), OptionError, "resolution"),
        (lambda r: joint_map(r, [0.0], 0, 1), ConfigurationError, "q"),
    ],
)
def test_bad_inputs(call, error, word):
    with pytest.raises(error, match=word) as info:
        call(robots.load("puma560"))
    assert isinstance(info.value, JacobianLabError)


# ------------------------------------------------------------- batches in chunks
@pytest.mark.parametrize("chunk", [1, 7, 64])
def test_workspace_in_chunks_equals_one_chunk(chunk):
    """The chunk size changes how a batch is cut, not what it gives."""
    robot = robots.load("panda")
    whole = workspace(robot, 200, seed=3, chunk=200)
    cut = workspace(robot, 200, seed=3, chunk=chunk)
    np.testing.assert_array_equal(cut.q, whole.q)
    for name in ("points", "w", "inverse_kappa"):
        np.testing.assert_allclose(getattr(cut, name), getattr(whole, name), rtol=1e-14, atol=1e-15)


def test_workspace_memory_is_bounded_by_the_chunk_not_the_batch():
    """Beyond its results, a workspace's peak memory (tracemalloc sees NumPy's buffers) is that of
    one chunk: 16 times more configurations raise the peak by their results only, far below
    what the whole batch's Jacobians alone would take."""
    import tracemalloc

    robot = robots.load("panda")

    def extra(n: int) -> int:
        workspace(robot, 64, seed=0, chunk=256)  # generated code compiled outside the measure
        tracemalloc.start()
        try:
            ws = workspace(robot, n, seed=0, chunk=256)
            _, peak = tracemalloc.get_traced_memory()
        finally:
            tracemalloc.stop()
        results = ws.q.nbytes + ws.points.nbytes + ws.w.nbytes + ws.inverse_kappa.nbytes
        return peak - results

    small, large = extra(2_000), extra(32_000)
    assert large < small + 64 * 1024
    assert large < 32_000 * 6 * 7 * 8 / 4  # a quarter of the batch's J alone


def test_measures_of_a_batch_in_one_pass():
    """σ (largest first), w = Πσ and σmin/σmax of a batch, against the SVD of each J."""
    robot = robots.load("puma560")
    Q = np.random.default_rng(8).uniform(-3, 3, (50, robot.dof))
    found = measures(robot, Q, chunk=16)
    assert found.sigma.shape == (50, 6) and found.points.shape == (50, 3)
    for k in range(0, 50, 7):
        s = np.linalg.svd(jacobian(robot, Q[k]), compute_uv=False)
        np.testing.assert_allclose(found.sigma[k], s, rtol=1e-7, atol=1e-7)
        assert found.w[k] == pytest.approx(np.prod(s), rel=1e-8, abs=1e-12)
        assert found.inverse_kappa[k] == pytest.approx(s[-1] / s[0], abs=1e-7)
        np.testing.assert_allclose(found.points[k], fk(robot, Q[k])[:3, 3], atol=1e-12)
    with pytest.raises(ConfigurationError, match="batch of configurations"):
        measures(robot, Q[0])
    with pytest.raises(OptionError, match="chunk must be an int"):
        measures(robot, Q, chunk=0)


def test_measures_mapped_with_dask_equal_measures():
    """The same chunk function mapped over a Dask array, one task per chunk: the same numbers."""
    da = pytest.importorskip("dask.array")
    robot = robots.load("panda")
    Q = np.random.default_rng(9).uniform(-2, 2, (100, robot.dof))
    lazy = measures_dask(robot, da.from_array(Q, chunks=30), chunk=16)
    assert lazy.numblocks == (7, 1) and lazy.shape == (100, 3 + 6 + 2)
    got = lazy.compute(scheduler="synchronous")
    want = measures(robot, Q)
    columns = np.column_stack((want.points, want.sigma, want.w, want.inverse_kappa))
    np.testing.assert_allclose(got, columns, rtol=1e-14, atol=1e-15)
    with pytest.raises(ConfigurationError, match="batch of configurations"):
        measures_dask(robot, da.from_array(Q[:, :3], chunks=30))
