"""004's generalised inverse ("Metoda jakobianowa – inwers uogólniony"), checked as the course derives it.

The course minimises ½⟨q, q⟩ under y = A q with a Lagrange multiplier and arrives at
A⁺ = Aᵀ(AAᵀ)⁻¹ (Moore–Penrose), then writes every solution as q = A⁺y + (I − A⁺A)ω, z ∈ Ker A.
``kinematics.pinv`` (what the q̇ = J⁺v tab uses for a redundant arm) is computed by the SVD; here it is
held against the course's closed formula and against the minimum it was derived from.
"""

from __future__ import annotations

import numpy as np
import pytest
from fakes import random_q

import robots
from kinematics import jacobian, pinv, select_rows, task_rows


@pytest.mark.parametrize("name", ["panda", "iiwa14", "planar3"])
def test_pinv_is_the_courses_minimum_norm_solution(name):
    robot = robots.load(name)
    rng = np.random.default_rng(29)
    rows = (0, 1) if name == "planar3" else task_rows(robot)  # the 3R planar arm holding its tool point
    A = select_rows(jacobian(robot, random_q(robot, rng)), rows)
    m, n = A.shape
    assert m < n and np.linalg.matrix_rank(A) == m  # the course's case: m ≤ n, rank A = m
    Ap = pinv(A)
    np.testing.assert_allclose(Ap, A.T @ np.linalg.inv(A @ A.T), atol=1e-10)  # A⁺ = Aᵀ(AAᵀ)⁻¹
    y = rng.normal(size=m)
    q = Ap @ y
    np.testing.assert_allclose(A @ q, y, atol=1e-10)  # a solution of y = A q
    # q = Aᵀλ with λ = (AAᵀ)⁻¹y: the stationarity condition qᵀ − λᵀA = 0 of the Lagrangian
    lam = np.linalg.solve(A @ A.T, y)
    np.testing.assert_allclose(q, A.T @ lam, atol=1e-10)
    for _ in range(20):  # every other solution q + z, z = (I − A⁺A)ω ∈ Ker A, is longer
        z = (np.eye(n) - Ap @ A) @ rng.normal(size=n)
        np.testing.assert_allclose(A @ z, 0, atol=1e-10)
        np.testing.assert_allclose(A @ (q + z), y, atol=1e-10)
        assert np.linalg.norm(q + z) ** 2 == pytest.approx(np.linalg.norm(q) ** 2 + np.linalg.norm(z) ** 2)
        assert np.linalg.norm(q + z) >= np.linalg.norm(q)
