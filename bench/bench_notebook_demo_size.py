"""What a recorded demo adds to a notebook (.ipynb), part by part.

Records the docs' demo (the Puma 560, 4 s at 15 fps, ``docs/notebooks.md``), puts
``show_recording(...)`` in a cell's output as Jupyter saves it, and prints the notebook's size and
where the bytes are: the cell holds the recording (base64) and a script; viser's client page (the 3-D
player, one self-contained HTML file, already zstd-compressed by viser) is written once beside the
notebook (``jacobian-lab-player/``) and not counted in the .ipynb.

Usage::

    python bench/bench_notebook_demo_size.py
    python bench/bench_notebook_demo_size.py --robot planar2 --seconds 2 --fps 10

Issue 30's target: ≤ 300 kB for this demo.
"""

from __future__ import annotations

import argparse
import base64
import gzip
import lzma
import tempfile

import nbformat

import robots
from app.demo.folder import client_page
from app.demo.player import PLAYER_DIR, player_page
from app.demo.record import record
from app.notebook import show_recording


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robot", default="puma560")
    parser.add_argument("--seconds", type=float, default=4.0)
    parser.add_argument("--fps", type=float, default=15.0)
    args = parser.parse_args()
    recording = record(args.robot, robots.load(args.robot), seconds=args.seconds, fps=args.fps)
    with tempfile.TemporaryDirectory() as folder:
        view = show_recording(recording, folder=folder)  # writes the player beside the "notebook"
    cell = nbformat.v4.new_code_cell("show_recording(...)")
    cell.outputs = [
        nbformat.v4.new_output(
            "execute_result",
            data={"text/html": view._repr_html_(), "text/plain": repr(view)},
            execution_count=1,
        )
    ]
    notebook = nbformat.v4.new_notebook(cells=[cell])
    size = len(nbformat.writes(notebook).encode("utf-8"))
    player = client_page().read_bytes()
    page = view.html().encode("utf-8")
    shared = player_page()
    kB = 1e3
    print(f"{recording.title}: {recording.frames} frames, {recording.duration:.1f} s")
    print(f"  the .ipynb with the demo         {size / kB:8.1f} kB")
    print(f"  viser's client page (player)     {len(player) / kB:8.1f} kB")
    print(f"    gzip -9 of it                  {len(gzip.compress(player, 9)) / kB:8.1f} kB")
    print(f"    xz -9 of it                    {len(lzma.compress(player, preset=9)) / kB:8.1f} kB")
    print(f"  the recording (.viser)           {len(recording.data) / kB:8.1f} kB")
    print(f"    as base64 in the page          {len(base64.b64encode(recording.data)) / kB:8.1f} kB")
    print(f"  the cell's HTML output           {len(view._repr_html_()) / kB:8.1f} kB")
    print(f"  the player beside the notebook   {len(shared) / kB:8.1f} kB (once per folder: {PLAYER_DIR}/)")
    print(f"  one self-contained page (.html)  {len(page) / kB:8.1f} kB (show_recording(...).html())")


if __name__ == "__main__":
    main()
