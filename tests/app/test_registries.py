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
from app.core.commands import ChooseRobot
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


def test_every_method_has_one_spelling_in_every_table() -> None:
    from app.views.methods import METHODS as VIEWS
    from kinematics.symbolic import DERIVATIONS as WHOLE
    from kinematics.symbolic.steps.methods import METHOD_STEPS

    assert list(VIEWS) == list(METHODS)
    assert OPTION["derive"].choices == ("", *METHODS)
    assert set(METHOD_STEPS) == set(DERIVATIONS) and set(WHOLE) <= set(DERIVATIONS)
    for key, view in VIEWS.items():
        assert view.steps is METHODS[key] and view.label and view.title
        assert (view.symbolic is None) == (key not in DERIVATIONS)
        assert all(prefix for prefix in view.symbols)


def _spy(obj, method: str, calls: list) -> None:
    real = getattr(obj, method)

    def spy(*args):
        calls.append(args)
        return real(*args)

    setattr(obj, method, spy)


def test_every_tab_and_glyph_of_the_lists_is_built_and_drawn() -> None:
    from app.core.actions import SetJoint, SetOption
    from app.views.panel import TABS
    from app.views.scene import GLYPHS

    with running_lab() as (_lab, session, _ws):
        session.dispatch(ChooseRobot("puma560"))
        session.settle()
        panel, scene = session.panel, session.scene
        assert [t.name for t in TABS] == list(panel.tabs)
        assert [panel.tabs[t.name]._label for t in TABS] == [t.label for t in TABS]
        built = [t.name for t in TABS if t.build is not None]
        assert list(panel.parts) == built and all(getattr(panel, n) is panel.parts[n] for n in built)
        assert list(scene.glyphs) == [g.name for g in GLYPHS]
        drawn: dict[str, list] = {n: [] for n in [*built, *scene.glyphs]}
        for name, part in panel.parts.items():
            _spy(part, "draw", drawn[name])
        for name, glyph in scene.glyphs.items():
            _spy(glyph, "update", drawn[name])
        session.dispatch(SetOption("derive", "whitney"))
        session.dispatch(SetJoint(1, 0.4))
        session.settle()
        state = session.state
        assert state.q[1] == 0.4
        for name, calls in drawn.items():
            assert calls, f"{name} was not drawn"
            assert calls[-1][0] is state or calls[-1][1] is state, name  # drawn with the last state
        assert len(scene.glyphs["derive"].extent)  # the Derive glyph drew Whitney's vectors


@pytest.mark.parametrize("key", list(METHODS))
def test_every_method_record_is_shown_and_drawn_at_every_step(key: str) -> None:
    from app_helpers import assert_all_finite

    from app.core.actions import SetOption

    with running_lab() as (_lab, session, _ws):
        for name in ("puma560", "scara"):
            session.dispatch(ChooseRobot(name))
            session.dispatch(SetOption("derive", key))
            session.settle()
            for j in range(session.state.robot.dof):
                session.dispatch(SetOption("derive_step", j))
                session.settle()
                body = session.panel.derive.body.content
                assert f"Step {j + 1} of" in body and "✗" not in body, (name, key, j)
                assert len(session.scene.derive.extent), (name, key, j)
                assert_all_finite(session)
