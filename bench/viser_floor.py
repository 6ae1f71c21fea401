"""The transport's floor: a bare viser server that answers a slider change with the messages the app sends.

No kinematics, no state, no HTML built from numbers: every tab gets the nodes and GUI elements of the
app's Panda tab (``bench/redraw_messages.py``: a batched-mesh arm, five joint labels, an ellipsoid, the
J columns' line segments, three HTML readouts, the page's address script), and each change of its
``q2`` slider sends the same 14 messages with the same sizes, from viser's own callback thread, in one
atomic frame. What one change costs this server is what viser itself costs per change: the app cannot
spend less. Run by ``bench/bench_app_load.py --floor`` beside the app, or alone::

    python bench/viser_floor.py --port 8713
"""

from __future__ import annotations

import argparse
import json
import sys
import threading
from pathlib import Path

import numpy as np
import trimesh
import viser

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from app.viser_adapter import (
    install_fast_prop_casts,
    install_loop_safe_events,
    quiet_banner,
    run_javascript,
    update_props,
)  # noqa: E402

LINKS = 8
LABELS = 5
HTML_SIZES = (1600, 780, 1120)
"""Characters of the three readouts' HTML (the J matrix, the measures, the open tab's readout)."""


def readout(size: int, value: float) -> str:
    """HTML of about ``size`` characters that changes with ``value`` (as a readout of numbers does)."""
    row = "".join(f"<td>{np.sin(value + k):+.3f}</td>" for k in range(7))
    html = ""
    while len(html) < size:
        html += f"<tr>{row}</tr>"
    return f"<table>{html[:size]}</table>"


def address(value: float) -> str:
    return f"?robot=panda&q=0,{value:.1f},0,-90,0,90,45"


def tab(client: viser.ClientHandle, messages: int = 14) -> None:
    """The nodes and elements of one tab, and its slider's redraw: the first ``messages`` of the 14
    updates per change (fewer, to split the cost per change from the cost per message)."""
    cylinder = trimesh.creation.cylinder(radius=0.04, height=1.0, sections=16)
    arm = client.scene.add_batched_meshes_simple(
        "/lab/arm/cylinders",
        vertices=cylinder.vertices,
        faces=cylinder.faces,
        batched_positions=np.zeros((LINKS, 3)),
        batched_wxyzs=np.tile([1.0, 0.0, 0.0, 0.0], (LINKS, 1)),
    )
    labels = [client.scene.add_label(f"/lab/arm/label_{i}", f"q{i}") for i in range(LABELS)]
    ellipsoid = client.scene.add_icosphere("/lab/jacobian/velocity_ellipsoid", radius=1.0, opacity=0.3)
    columns = client.scene.add_line_segments(
        "/lab/jacobian/columns", points=np.zeros((7, 2, 3)), colors=(255, 0, 0)
    )
    client.gui.add_text("page", "")
    htmls = [client.gui.add_html(readout(size, 0.0)) for size in HTML_SIZES]
    slider = client.gui.add_slider("q2 (deg)", min=-180.0, max=180.0, step=0.1, initial_value=0.0)
    rng = np.random.default_rng(0)

    def turn() -> np.ndarray:
        wxyz = rng.normal(size=(LINKS, 4))
        return wxyz / np.linalg.norm(wxyz, axis=1, keepdims=True)

    def sends(value: float) -> list:
        """The 14 updates of one change, the arm's first (a frame with it counts as redrawn)."""
        script = f"history.replaceState(null, '', {json.dumps(address(value))});"
        return [
            lambda: update_props(arm, batched_positions=rng.normal(size=(LINKS, 3)), batched_wxyzs=turn()),
            *(lambda label=label: setattr(label, "position", rng.normal(size=3)) for label in labels),
            lambda: setattr(ellipsoid, "scale", (1.0, 0.5 + 0.1 * abs(value) / 180.0, 0.2)),
            lambda: setattr(ellipsoid, "position", rng.normal(size=3)),
            lambda: setattr(ellipsoid, "wxyz", (0.0, 1.0, 0.0, 0.0)),
            lambda: setattr(columns, "points", rng.normal(size=(7, 2, 3)).astype(np.float32)),
            *(
                lambda h=h, n=n: setattr(h, "content", readout(n, value))
                for h, n in zip(htmls, HTML_SIZES, strict=True)
            ),
            lambda: run_javascript(client, script),
        ]

    @slider.on_update
    def _(_: object) -> None:
        with client.atomic():
            for send in sends(float(slider.value))[:messages]:
                send()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--port", type=int, default=0)
    parser.add_argument("--messages", type=int, default=14, choices=range(1, 15), metavar="1..14")
    args = parser.parse_args()
    install_fast_prop_casts()  # viser as the app runs it (its speed-ups, not its checks)
    install_loop_safe_events()
    with quiet_banner():
        server = viser.ViserServer(host="127.0.0.1", port=args.port, verbose=False)
    server.on_client_connect(lambda client: tab(client, args.messages))
    print(f"viser floor: open http://127.0.0.1:{server.get_port()}", flush=True)
    try:
        threading.Event().wait()  # until Ctrl-C (the bench ends it with SIGTERM)
    except KeyboardInterrupt:
        pass
    finally:
        with quiet_banner():
            server.stop()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
