"""Issue 28, stumble 8: the iiwa's candle loses two translations of its wrist centre (z and y); each
arrow carries its own label (the second had none), near its own tip, in every language."""

from __future__ import annotations

import numpy as np
import pytest
from app_helpers import scene_node

from app.core.actions import GoTo
from app.core.commands import ChooseRobot
from app.core.i18n import translations
from app.views.scene.overlays import MAX_LOSSES

ROOT = "/lab/jacobian"


def test_both_lost_translations_of_the_candle_are_labelled(session):
    session.dispatch(ChooseRobot("iiwa14"))
    session.dispatch(GoTo("candle"))
    session.settle()
    arm = [x for x in session.snapshot.losses if x.part == "arm" and x.translation_share > 0.5]
    assert len(arm) == 2  # z and y of the wrist centre (an independent fact of the candle: both lost)
    assert abs(arm[0].translation @ arm[1].translation) < 1e-9
    arrows = scene_node(session, f"{ROOT}/lost_translation").points
    tips = arrows[:, 1]
    labels = [scene_node(session, f"{ROOT}/lost_label_{i}") for i in range(MAX_LOSSES)]
    shown = [label for label in labels if label.visible]
    texts = [label.text for label in shown]
    assert "arm: lost translation (wrist centre)" in texts
    assert "arm: second lost translation (wrist centre)" in texts
    size = session.scene.size
    for label in shown:
        if "translation" not in label.text:
            continue
        gaps = np.linalg.norm(tips - np.asarray(label.position), axis=1)
        assert gaps.min() < 0.25 * size, (label.text, gaps / size)  # at its arrow's tip
    near = {
        int(np.argmin(np.linalg.norm(tips - np.asarray(label.position), axis=1)))
        for label in shown
        if "translation" in label.text
    }
    assert near == {0, 1}  # one label at each arrow


@pytest.mark.parametrize("code", ["pt", "es", "pl"])
def test_the_second_label_is_translated(code):
    tr = translations(code)
    first = tr.gettext("arm: lost translation (wrist centre)")
    second = tr.gettext("arm: second lost translation (wrist centre)")
    assert second != "arm: second lost translation (wrist centre)" and second != first
