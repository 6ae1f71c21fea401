"""A phone's first picture (issue 28): a new tab gets its arm, framed, in a frame of its own before the
panel's widgets, so the browser can draw the arm before it lays out the panel
(``bench/bench_first_picture.py`` times it in Chromium; no timing here)."""

from __future__ import annotations

import numpy as np
from app_helpers import scene_node
from wsclient import ViserWsClient

from app.server import Lab


def test_the_arm_and_its_camera_come_before_the_panel_and_stay_the_tabs_scene():
    lab = Lab(port=0)
    try:
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}") as ws:
            ws.wait_for(lambda m: m["type"] == "GuiSliderMessage")
            ws.wait_for(lambda m: m["type"] == "SetCameraPositionMessage" and not m.get("initial"))
            session = lab.session()
            session.settle()
            messages = [m for _, m in ws.messages]
        names = [m.get("name", "") for m in messages]
        arm = names.index("/lab/arm/cylinders")
        first_widget = next(
            i
            for i, m in enumerate(messages)
            if m["type"].startswith("Gui")
            and "uuid" in m
            and m["type"]
            not in (
                "GuiSetPanelPositionMessage",
                "GuiSetPanelWidthMessage",
                "GuiSetPanelHeightMessage",
                "GuiSetPanelCollapsedMessage",
            )
        )
        assert arm < first_widget, (arm, messages[first_widget]["type"])
        # The camera frames the arm before any widget too (the picture is the tab's, not viser's default).
        camera = next(
            i
            for i, m in enumerate(messages)
            if m["type"] == "SetCameraLookAtMessage" and i > 0 and not m.get("initial")
        )
        assert camera < first_widget
        # The scene drawn first is the one the tab keeps: one arm node, at the pose of the tab's state.
        made = [
            m for m in messages if m["type"] == "BatchedMeshesMessage" and m["name"] == "/lab/arm/cylinders"
        ]
        assert len(made) == 1  # not made again by the tab's first full drawing
        cylinders = scene_node(session, "/lab/arm/cylinders")
        posed = [
            m["updates"]["batched_positions"]
            for m in messages[:first_widget]
            if m["type"] == "SceneNodeUpdateMessage"
            and m["name"] == "/lab/arm/cylinders"
            and "batched_positions" in m["updates"]
        ]
        assert posed  # posed before the panel: the first picture shows the arm where the tab has it
        np.testing.assert_allclose(
            np.asarray(posed[-1], float).reshape(-1, 3),
            np.asarray(cylinders.batched_positions, float),
            atol=1e-9,
        )
    finally:
        lab.stop()
