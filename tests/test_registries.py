"""The registries hold: every option row has a default in range and a widget that sets it; every
derivation method's numbers assemble J; every tab and glyph of the lists is built and drawn.

The registries replace parallel lists (the options' defaults, ranges and widgets; the methods'
tables in six places), so these tests walk them: a row, a record or a list entry without its
other half fails here, not in a classroom.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from app_helpers import running_lab

import robots
from app.core.actions import ChooseRobot
from app.core.options import OPTION, OPTIONS
from app.core.state import Options
from kinematics import jacobian
from kinematics.steps import DERIVATIONS, METHODS


def test_every_option_field_has_one_row_and_every_row_a_field() -> None:
    fields = [f.name for f in dataclasses.fields(Options)]
    assert sorted(fields) == sorted(OPTION)
    assert len(OPTIONS) == len(OPTION)  # one row per name


@pytest.mark.parametrize("row", OPTIONS, ids=lambda r: r.name)
def test_every_default_is_in_range_and_is_the_options_default(row) -> None:
    value = getattr(Options(), row.name)
    assert value == row.default
    if row.kind == "bool":
        assert isinstance(value, bool)
    elif row.kind == "float":
        assert row.lo <= value <= row.hi and row.step > 0
        assert math.isclose(round((row.hi - row.lo) / row.step), (row.hi - row.lo) / row.step)
    elif row.kind == "choice":
        assert value in row.choices
        assert not row.labels or len(row.labels) == len(row.choices) == len(set(row.labels))
    else:
        assert isinstance(value, int) and value >= 0
    assert row.label


def _inputs(session) -> dict[str, object]:
    """The tab's input widgets by label (the panel builds each label once)."""
    handles = session.client.gui._gui_input_handle_from_uuid.values()
    return {h.label: h for h in handles if not h.disabled}


def test_every_option_row_has_a_widget_that_sets_it() -> None:
    """Each widget built from a row shows its label, range or choices, and moving it sets the option."""
    with running_lab() as (_lab, session, _ws):
        session.dispatch(ChooseRobot("puma560"))
        session.settle()
        widgets = _inputs(session)
        for row in OPTIONS:
            if row.widget == "own":
                continue
            assert row.label in widgets, f"option {row.name}: no widget labelled {row.label!r}"
            handle = widgets[row.label]
            before = getattr(session.state.options, row.name)
            if row.kind == "bool" and row.widget == "button":
                continue  # a button flips it: test_app_server presses the symbolic J⁻¹ one
            if row.kind == "bool":
                handle.value = not before
                want: object = not before
            elif row.kind == "float":
                assert (handle.min, handle.max, handle.step) == (row.lo, row.hi, row.step)
                want = row.hi if before != row.hi else row.lo
                handle.value = want
            else:
                assert tuple(handle.options) == (row.labels or row.choices)
                want = next(c for c in row.choices if c != before)
                handle.value = row.label_of(want)
            session.settle()
            assert getattr(session.state.options, row.name) == want, row.name
            assert handle.value == (row.label_of(want) if row.kind == "choice" else want)


@pytest.mark.parametrize("key", DERIVATIONS)
@pytest.mark.parametrize("name", ["puma560", "stanford", "panda", "trr", "scara"])
def test_every_method_assembles_j_at_random_configurations(key: str, name: str) -> None:
    robot = robots.load(name)
    method = METHODS[key]
    assert method.column is not None and method.step is not None
    rng = np.random.default_rng(16)
    for _ in range(4):
        q = rng.uniform(-math.pi, math.pi, robot.dof)
        q = np.array(
            [x if j.kind == "revolute" else 0.3 * x / math.pi for x, j in zip(q, robot.joints, strict=True)]
        )
        J = jacobian(robot, q)
        assembled = np.column_stack([method.column(robot, q, j) for j in range(robot.dof)])
        tol = 1e-6 if key == "differentiation" else 1e-9
        np.testing.assert_allclose(assembled, J, atol=tol * max(1.0, float(np.abs(J).max())))
