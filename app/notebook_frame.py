"""The live cell's HTML: the lab's ``<iframe>`` when a lab answers, else a dead frame, a still picture
of what the cell showed and a line on how to start it again (a saved or reopened notebook).

The picture is the 3-D view as the cell's browser last rendered it (viser's ``get_render``), kept in
the cell's output (a JPEG in a ``data:`` address). A small script asks the lab's address first
(``fetch`` with ``no-cors``: any answer means a lab is there) and only then swaps the iframe in; with
no answer, or where outputs run no scripts (an untrusted notebook in JupyterLab), the picture and the
line stay.
"""

from __future__ import annotations

import base64
import html
import io
import json
import uuid

import numpy as np

from .core.i18n import translations

__all__ = ["cell_html", "jpeg", "restart_line"]


def restart_line(lang: str = "") -> str:
    """The dead frame's line, in the notebook's language (``show(lang=...)``; English without it)."""
    tr = translations(lang or "en")
    return tr.gettext(
        "No lab answers here: this is a still picture of what this cell showed. "
        "Run the cell again to start the lab."
    )


def jpeg(rgb: np.ndarray, quality: int = 85) -> bytes | None:
    """``rgb`` (H, W, 3) as JPEG bytes (None where no JPEG writer is installed: Pillow)."""
    try:
        import imageio.v3 as iio

        buffer = io.BytesIO()
        iio.imwrite(buffer, np.asarray(rgb, dtype=np.uint8)[..., :3], extension=".jpeg", quality=quality)
    except (ImportError, ValueError, RuntimeError, OSError):
        return None
    return buffer.getvalue()


def cell_html(url: str, title: str, height: int, picture: bytes | None, lang: str = "") -> str:
    """The cell: the picture (if any) and the line, and the lab's iframe swapped in when ``url`` answers."""
    box = f"jlab-{uuid.uuid4().hex[:12]}"
    src = html.escape(url, quote=True)
    label = html.escape(title, quote=True)
    still = (
        f'<img src="data:image/jpeg;base64,{base64.b64encode(picture).decode("ascii")}" alt="{label}" '
        'style="display:block;width:100%;height:100%;object-fit:contain;background:#fff">'
        if picture
        else ""
    )
    line = (
        '<p class="jlab-restart" style="position:absolute;left:0;right:0;bottom:0;margin:0;'
        "padding:6px 10px;background:rgba(255,255,255,.92);color:#222;border-top:1px solid #ddd;"
        f'font:14px/1.4 sans-serif">{html.escape(restart_line(lang))}</p>'
    )
    frame = (
        f'<iframe data-src="{src}" width="100%" height="{int(height)}" title="{label}" '
        'style="display:none;border:0;position:absolute;top:0;left:0"></iframe>'
    )
    probe = (
        "<script>(function(){var b=document.getElementById(BOX);if(!b)return;"
        "var f=b.querySelector('iframe'),u=f.getAttribute('data-src');"
        "fetch(u,{mode:'no-cors',cache:'no-store'}).then(function(){"
        "f.src=u;f.style.display='block';"
        "b.querySelectorAll('img,.jlab-restart').forEach(function(e){e.style.display='none';});"
        "},function(){});})();</script>"
    ).replace("BOX", json.dumps(box))
    return (
        f'<div id="{box}" class="jlab-cell" style="position:relative;width:100%;height:{int(height)}px;'
        f'border:1px solid #ddd;overflow:hidden">{still}{line}{frame}{probe}</div>'
    )
