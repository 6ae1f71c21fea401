"""The fast steps of the symbolic simplification give exactly what SymPy's own steps give.

:func:`kinematics.symbolic.tr10i.tr10i` (TR10i with an index of the pairs that can combine) must
return the very expression ``sympy.simplify.fu.TR10i`` returns, on real Jacobian entries and on
sums built to hit every branch of TR10i (phases √2, √3 ratios, constant angles, common factors);
:func:`kinematics.symbolic.trig.normal_form` (polynomial rings over ℚ) the very expression of
:func:`kinematics.symbolic.trig.normal_form_sympy` (SymPy's ``expand`` and ``reduced``).
"""

from __future__ import annotations

import importlib

import numpy as np
import pytest
import sympy as sp
from fakes import random_configurations

import kinematics
import robots
from kinematics import symbolic
from kinematics.symbolic import build_model, jacobian_whitney
from kinematics.symbolic.chain import frames
from kinematics.symbolic.simplify import COLLAPSE_MAX
from kinematics.symbolic.tr10i import pair_keys, tr10i
from kinematics.symbolic.trig import AngleShift, normal_form, normal_form_sympy

fu = importlib.import_module("sympy.simplify.fu")
q1, q2, q3, q4 = sp.symbols("q1:5", real=True)
a, b = sp.symbols("a b", positive=True)
c1, s1, c2, s2, c3, s3 = sp.cos(q1), sp.sin(q1), sp.cos(q2), sp.sin(q2), sp.cos(q3), sp.sin(q3)

HANDMADE = [
    c1 * c2 - s1 * s2,
    a * c1 * c2 * c3 - a * s1 * s2 * c3 + b * s3 + 2 * s1 * c2 + 2 * c1 * s2,
    c1 + s1,  # a phase: √2 sin(q1 + π/4)
    sp.sqrt(3) * c1 - s1 + c2,
    sp.sqrt(2) * c1 * s2 + sp.sqrt(6) * s1 * s2,
    c1**2 * c2 - c1 * s1 * s2 + a,
    sp.cos(sp.Rational(3, 10)) * c1 - sp.sin(sp.Rational(3, 10)) * s1 + c2 * s3 + s2 * c3,
    (c1 * c2 - s1 * s2) * c3 - (s1 * c2 + c1 * s2) * s3,
    sp.expand((a * c1 + b * s2 + c3) * (c1 * c2 - s1 * s2 + s3 * c1)),
    sp.sqrt(q4) * c1 * c2 - s1 * s2,
    c1 / c2 - s1 * s2 / c2**2,
    a * c1 * s1 + a * c1 * c2 - a * s1 * s2 + c1 * s1 * c2,
    c1 * s1 + s2 * c2 + c1 * c2 * s1 * s2 - sp.sqrt(3) * c1 * s1,
    sp.sqrt(2) * c1 * c2 - sp.sqrt(2) * s1 * s2 + sp.sqrt(2) * c3 + sp.sqrt(2) * s3,
]


@pytest.mark.parametrize("expr", HANDMADE, ids=range(len(HANDMADE)))
def test_tr10i_is_sympys_tr10i(expr):
    assert tr10i(expr) == fu.TR10i(expr)


@pytest.mark.parametrize("name", ["puma560", "stanford", "puma560_mdh"])
def test_tr10i_is_sympys_tr10i_on_jacobian_entries(name):
    robot = robots.load(name)
    model = build_model(robot, False)
    shift = AngleShift(model.q, model.angle_offsets())
    for entry in jacobian_whitney(robot):
        nf = normal_form(shift.apply(entry), shift.vars)
        if 1 < len(sp.Add.make_args(nf)) <= COLLAPSE_MAX:
            assert tr10i(nf) == fu.TR10i(nf)


def test_pair_keys_meet_exactly_for_pairs_that_may_combine():
    assert not pair_keys(a * c1 * c2).isdisjoint(pair_keys(-a * s1 * s2))
    assert pair_keys(a * c1 * c2).isdisjoint(pair_keys(b * s1 * s2))  # a ≠ b: no common factor left
    assert pair_keys(a * c1 * c2).isdisjoint(pair_keys(a**2 * s1 * s2))
    assert pair_keys(c1 / c2) is None  # anything unusual may pair with anything


# ------------------------------------------------------------------ normal form on polynomial rings
NF_CASES = [
    sp.sin(q1) ** 2 + sp.cos(q1) ** 2,
    (a * c1 + b * sp.cos(q1 + q2)) * (s1 - sp.sqrt(2) * s2) ** 2,
    (sp.sqrt(6) - sp.sqrt(2)) / 4 * s1 * sp.sqrt(3) + sp.sqrt(2) * sp.sqrt(3) * c2,
    sp.cos(sp.Rational(3, 10)) ** 2 * s3 + sp.sin(sp.Rational(3, 10)) ** 2 * s3 - s3,
    sp.sin(q1 + sp.pi / 12) * sp.cos(q2 - q3) * q4**2,
    sp.Float(0.5) * s1**2,  # not over ℚ: the reference path
    c1 / a + s1**3,  # not a polynomial: the reference path
]


@pytest.mark.parametrize("expr", NF_CASES, ids=range(len(NF_CASES)))
def test_normal_form_is_the_reference_normal_form(expr):
    q = (q1, q2, q3, q4)
    assert normal_form(expr, q) == normal_form_sympy(expr, q)


@pytest.mark.parametrize("name", ["puma560", "stanford", "ur5", "elbow3r", "scara"])
@pytest.mark.parametrize("params", [False, True])
def test_normal_form_is_the_reference_on_jacobian_and_fk_entries(name, params):
    robot = robots.load(name)
    model = build_model(robot, params)
    shift = AngleShift(model.q, model.angle_offsets())
    for entry in [*jacobian_whitney(robot, "base", params), *frames(model).tool]:
        e = shift.apply(entry)
        assert normal_form(e, shift.vars) == normal_form_sympy(e, shift.vars)


# ------------------------------------------------------------------ whole derivations
def _sympy_steps(monkeypatch):
    """The simplification as it was: SymPy's expand + reduced and SymPy's TR10i."""
    from kinematics.symbolic import analytic, det, simplify, trig

    for module in (trig, simplify, det, analytic):
        monkeypatch.setattr(module, "normal_form", trig.normal_form_sympy)
    monkeypatch.setattr(trig, "tr10i", fu.TR10i)


@pytest.mark.parametrize("name", ["planar2", "planar3", "trr", "elbow3r", "wrist", "scara", "stanford"])
@pytest.mark.parametrize("params", [False, True])
def test_derivation_is_the_one_of_sympys_steps(name, params, monkeypatch):
    robot = robots.load(name)
    ours = symbolic.derive(robot, symbolic_params=params, use_cache=False, timeout=None)
    _sympy_steps(monkeypatch)
    theirs = symbolic.derive(robot, symbolic_params=params, use_cache=False, timeout=None)
    assert ours.J == theirs.J and ours.T == theirs.T and ours.notes == theirs.notes


@pytest.mark.slow
@pytest.mark.parametrize("name", [n for n in robots.names() if robots.load(n).dof <= 7])
def test_derived_jacobian_is_the_numeric_one_to_1e_12(name):
    robot = robots.load(name)
    d = symbolic.derive(robot, use_cache=False, timeout=None)
    assert d.complete
    model = build_model(robot, False)
    J, T = symbolic.numeric_function(d.J, model), symbolic.numeric_function(d.T, model)
    for q in random_configurations(robot, 10, seed=7):
        np.testing.assert_allclose(J(q), kinematics.jacobian(robot, q), atol=1e-12, rtol=0)
        np.testing.assert_allclose(T(q), kinematics.fk(robot, q), atol=1e-12, rtol=0)
