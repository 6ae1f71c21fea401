"""Every refusal of a motion and the nearest-singularity wait reach a tab in its language (issue 29): the
reducer keeps a refusal's catalog sentence (:func:`kinematics.text.words`), the tab's notice says it
through the catalogs (Polish here), its values (a robot's, a preset's name, a count) kept as they are."""

from __future__ import annotations

import pytest

import robots
from app.core.actions import ApplyPreset, DriveTool, FollowPath, Play, SelfMove, Wait
from app.core.i18n import translations
from app.core.reducer import InvalidAction, reduce
from app.core.snapshot import compute
from app.core.state import LabState
from app.tab.commands import LOOKING
from app.tab.notices import _said
from app.views.panel.readouts import status_html


def puma() -> LabState:
    return LabState.initial("puma560", robots.load("puma560"))


REFUSED = [
    (
        "preset",
        ApplyPreset("stretch", (0.0, 0.0), (0.0,) * 6),  # two joints for a six-joint arm
        "przykład 'stretch' nie pasuje do puma560",
    ),
    (
        "preset-not-finite",
        ApplyPreset("stretch", (0.0,) * 6, (float("nan"),) + (0.0,) * 5),
        "przykład 'stretch' zawiera wartość, która nie jest skończoną liczbą",
    ),
    (
        "self-motion",
        SelfMove(0.1),
        "puma560 nie ma ruchu własnego: żaden przegub nie jest zbędny dla jego zadania",
    ),
    ("drag", DriveTool((0.0,) * 15), "przeciągnięty cel musi mieć 16 skończonych liczb (pozycja 4×4)"),
    ("path", FollowPath(((0.0, 0.0),), ""), "ścieżka wymaga wierszy po 6 skończonych wartości przegubów"),
    ("motion", Play(True, "dance"), "nieznany ruch 'dance'; ruchy to joints, resolved_rate, climb"),
]


@pytest.mark.parametrize(("what", "action", "polish"), REFUSED, ids=[r[0] for r in REFUSED])
def test_a_refused_motion_is_said_in_polish(what, action, polish):
    with pytest.raises(InvalidAction) as refused:
        reduce(puma(), action)
    english = str(refused.value)
    assert _said(refused.value, translations("en")) == english
    assert _said(refused.value, translations("pl")) == polish != english


def test_the_nearest_singularity_wait_is_said_in_the_tabs_language():
    state = reduce(puma(), Wait(LOOKING))
    assert state.stopped == "looking for the nearest singularity…"  # the state's English, for every tab
    snap = compute(state)
    assert "looking for the nearest singularity…" in status_html(snap, state)
    assert "szukanie najbliższej osobliwości…" in status_html(snap, state, translations("pl"))
    assert "buscando la singularidad más cercana…" in status_html(snap, state, translations("es"))
    assert "looking" not in status_html(snap, state, translations("pt"))
