"""A recorded demo as files: the folder any static web server can serve (``index.html``, viser's
client page, ``recording.viser``, ``joint_rates.csv``) and the one self-contained page a notebook cell
embeds. The recording itself is :mod:`app.demo.record`'s."""

from __future__ import annotations

import base64
import html
import json
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import viser

from kinematics.files import write_user_file

from ..core.i18n import translations
from .rates import rates_csv

if TYPE_CHECKING:
    from .record import Recording

__all__ = ["CLIENT_PAGE", "RECORDING", "RATES", "client_page", "write_demo", "demo_files", "embedded_page"]

CLIENT_PAGE = "viser-client.html"
"""viser's client page, copied next to the recording."""
RECORDING = "recording.viser"
RATES = "joint_rates.csv"
"""Every frame's q and the motion's q̇, with units (the recording draws them; this keeps the numbers)."""


_INDEX = """<!doctype html>
<html lang="{lang}">
<head>
<meta charset="utf-8">
<title>{title}</title>
<meta http-equiv="refresh" content="0; url={target}">
<script>location.replace({target_js} + location.hash);</script>
</head>
<body><p>{link}</p></body>
</html>
"""


def client_page() -> Path:
    """viser's client page, as shipped in its wheel (one self-contained HTML file)."""
    return Path(viser.__file__).resolve().parent / "client" / "build" / "index.html"


def write_demo(recording: Recording, out_dir: str | Path) -> Sequence[Path]:
    """Write ``index.html``, the client page, ``recording.viser`` and ``joint_rates.csv`` into
    ``out_dir`` (created if needed); returns the files written.

    Raises:
        OSError: the folder or a file cannot be written.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = {out / name: data for name, data in demo_files(recording).items()}
    for path, data in files.items():  # names the user did not give: never written through a link
        write_user_file(path, data, named=False)
    return list(files)


def demo_files(recording: Recording) -> dict[str, bytes]:
    """The files of a demo folder by name: ``index.html``, the client page, ``recording.viser`` and the
    joint rates (``joint_rates.csv``)."""
    target = f"{CLIENT_PAGE}?playbackPath={RECORDING}"
    page = client_page().read_text(encoding="utf-8")
    page = page.replace("<title>Viser</title>", f"<title>{html.escape(recording.title)}</title>", 1)
    return {
        RECORDING: recording.data,
        RATES: rates_csv(recording.states, recording.fps).encode("utf-8"),
        CLIENT_PAGE: page.encode("utf-8"),
        "index.html": _index(recording, target).encode("utf-8"),
    }


def _index(recording: Recording, target: str) -> str:
    """The folder's ``index.html``: it sends the browser to the player; its one line in the demo's
    language."""
    tr = translations(recording.language)
    link = f'<a href="{html.escape(target)}">{html.escape(recording.title)}</a>'
    sentence = tr.gettext("{title} (a recorded {app} demo)")  # the app's name is no course word
    before, _, after = html.escape(sentence.replace("{app}", "Jacobian Lab")).partition("{title}")
    return _INDEX.format(
        lang=html.escape(tr.code),
        title=html.escape(recording.title),
        target=html.escape(target),
        target_js=json.dumps(target),
        link=f"{before}{link}{after}",
    )


def embedded_page(recording: Recording, dark_mode: bool = False) -> str:
    """One self-contained HTML page that plays ``recording`` with no server and no other file: viser's
    client page with the recording inside (as viser's own ``as_html`` embeds a scene), for a notebook
    cell or a single file to mail."""
    page = client_page().read_text(encoding="utf-8")
    page = page.replace("<title>Viser</title>", f"<title>{html.escape(recording.title)}</title>", 1)
    data = base64.b64encode(recording.data).decode("ascii")
    dark = "true" if dark_mode else "false"
    inject = (
        f'<script>window.__VISER_EMBED_DATA__="{data}";'
        f"window.__VISER_EMBED_CONFIG__={{darkMode:{dark}}};</script>"
    )
    head_end = page.index("</head>")
    return page[:head_end] + inject + page[head_end:]
