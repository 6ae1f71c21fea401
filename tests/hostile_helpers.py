"""Helpers for the hostile-tab tests: the widgets a tab sees, and another tab's slider round trips
measured while a hostile one attacks."""

from __future__ import annotations

import statistics
import threading
import time
from typing import Any

from wsclient import ViserWsClient

INPUTS = (
    "GuiSliderMessage",
    "GuiNumberMessage",
    "GuiDropdownMessage",
    "GuiCheckboxMessage",
    "GuiButtonMessage",
    "GuiButtonGroupMessage",
    "GuiVector2Message",
    "GuiVector3Message",
    "GuiTextMessage",
    "GuiUploadButtonMessage",
    "GuiMultiSliderMessage",
    "GuiRgbMessage",
)
ROUND_TRIP_BOUND_MS = 200.0
"""Another tab's slider round trip (median of several) must stay under this while a tab attacks."""


def is_scene(m: dict) -> bool:
    return str(m.get("name", "")).startswith("/")


def widgets(ws: ViserWsClient) -> dict[str, dict[str, Any]]:
    """Every input widget this tab was sent and not removed since: uuid → its creation message."""
    found: dict[str, dict[str, Any]] = {}
    with ws._cond:
        messages = [m for _, m in ws.messages]
    for m in messages:
        if m["type"] in INPUTS:
            found[m["uuid"]] = m
        elif m["type"] == "GuiRemoveMessage":
            found.pop(m["uuid"], None)
    return found


def slider(ws: ViserWsClient, prefix: str = "q2 ", timeout: float = 60.0) -> str:
    """The uuid of the tab's joint slider whose label starts with ``prefix``."""
    _, msg = ws.wait_for(
        lambda m: m["type"] == "GuiSliderMessage" and m["props"]["label"].startswith(prefix), timeout=timeout
    )
    return msg["uuid"]


def round_trip(ws: ViserWsClient, uuid: str, value: float, timeout: float = 30.0) -> float:
    """Slider change → first scene message back on this tab [ms]."""
    mark = ws.mark()
    sent = ws.set_value(uuid, value)
    received, _ = ws.wait_for(is_scene, after=mark, timeout=timeout)
    return (received - sent) * 1e3


class RoundTrips:
    """Another tab moving its slider in a thread, one round trip after another, while a test attacks.

    ``median()`` is robust to a loaded machine's occasional stall (a test asserts the median of
    several, under a generous bound, and that enough round trips were made).
    """

    def __init__(self, ws: ViserWsClient, uuid: str) -> None:
        self.ws, self.uuid = ws, uuid
        self.samples: list[float] = []
        self.failures: list[str] = []
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True, name="round-trips")

    def __enter__(self) -> RoundTrips:
        for i in range(3):  # warm up: the first redraws build caches
            round_trip(self.ws, self.uuid, 5.0 + i)
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join(60)

    def _run(self) -> None:
        i = 0
        while not self._stop.is_set():
            i += 1
            try:
                self.samples.append(round_trip(self.ws, self.uuid, float(-40 + (i * 7) % 80)))
            except Exception as exc:  # a timeout is a failure the test reports
                self.failures.append(f"{type(exc).__name__}: {exc}")
            time.sleep(0.02)  # a student's pace, not a flood

    def wait_for_samples(self, n: int, timeout: float = 60.0) -> None:
        end = time.monotonic() + timeout
        while len(self.samples) < n and time.monotonic() < end and not self.failures:
            time.sleep(0.05)

    def median(self) -> float:
        return statistics.median(self.samples)

    def check(self, n: int = 5) -> None:
        """At least ``n`` round trips, none lost, and their median under the bound."""
        self.wait_for_samples(n)
        assert not self.failures, self.failures[:3]
        assert len(self.samples) >= n, f"only {len(self.samples)} round trips"
        assert self.median() < ROUND_TRIP_BOUND_MS, (
            f"median {self.median():.0f} ms over {len(self.samples)}: {sorted(self.samples)}"
        )


def widget(ws: ViserWsClient, predicate, timeout: float = 30.0) -> str:
    """The uuid of the first input widget of this tab whose creation message satisfies ``predicate``,
    waiting for it to arrive (the server may still be sending the panel)."""
    end = time.monotonic() + timeout
    while True:
        found = [u for u, m in widgets(ws).items() if predicate(m)]
        if found:
            return found[0]
        if time.monotonic() > end:
            raise TimeoutError("no such widget arrived")
        time.sleep(0.05)


def all_widgets(ws: ViserWsClient, timeout: float = 30.0) -> dict[str, dict[str, Any]]:
    """Every input widget of the tab once the panel has arrived (its count stopped growing)."""
    widget(ws, lambda m: m["type"] == "GuiUploadButtonMessage", timeout)  # the Build tab's last input
    end, last = time.monotonic() + timeout, -1
    while time.monotonic() < end:
        found = widgets(ws)
        if len(found) == last:
            return found
        last = len(found)
        time.sleep(0.5)
    return widgets(ws)


def chain_urdf(joints: int, general: bool = False) -> bytes:
    """A serial URDF chain of ``joints`` revolute joints: about z, 1 cm apart (the issues' uploads), or
    ``general`` (axes turning x, y, z, skewed offsets: nothing for the symbolic snapping to use)."""
    axes = ("1 0 0", "0 1 0", "0 0 1")
    links = "".join(f'<link name="l{i}"/>' for i in range(joints + 1))
    chain = "".join(
        f'<joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/>'
        + (
            f'<origin xyz="0.1 0.05 0.2" rpy="0 0.3 0"/><axis xyz="{axes[i % 3]}"/>'
            if general
            else '<origin xyz="0.01 0 0"/><axis xyz="0 0 1"/>'
        )
        + '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        for i in range(joints)
    )
    return f'<?xml version="1.0"?><robot name="c{joints}">{links}{chain}</robot>'.encode()
