"""A recorded demo in a notebook cell that stays small: viser's player page (819 kB) is written once as
a file beside the notebook, ``jacobian-lab-player/player-<digest>.html``, shared by every demo of every
notebook in that folder, and the cell keeps only the recording (base64) and a script that frames the
player with the recording in the address's fragment (never sent to a server).

The script tries the player where the notebook's Jupyter server serves it (``{base_url}files/…``, from
the running server whose root holds the kernel's folder) and then beside the page (a relative path: the
notebook's HTML export in the same folder, opened from a web server or from the disk). With no player
found, or no scripts run (an untrusted notebook, a code host's preview), the cell shows one line saying
where the demo plays and how to write the player again. (An export opened through Jupyter's own
``/files/`` is sandboxed by Jupyter's security policy, which lets no page frame it: the line shows there
too.)

The file's name holds a digest of its bytes: a notebook keeps playing with the player it was written
with, and a new viser writes a new file beside the old one.
"""

from __future__ import annotations

import base64
import functools
import hashlib
import html
import json
import os
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any
from urllib.parse import quote

from kinematics.files import write_user_file

from ..core.i18n import translations
from .folder import client_page

if TYPE_CHECKING:
    from .record import Recording

__all__ = ["PLAYER_DIR", "player_page", "player_name", "write_player", "server_player_url", "cell_html"]

PLAYER_DIR = "jacobian-lab-player"
"""The folder beside the notebook that holds the player page."""

# viser's client reads the embedded scene when it starts (as in embedded_page); here it comes from the
# fragment, so one file plays any recording.
_FROM_FRAGMENT = (
    "<script>if(location.hash.length>1){window.__VISER_EMBED_DATA__=location.hash.slice(1);"
    "window.__VISER_EMBED_CONFIG__={darkMode:false};}</script>"
)

_SCRIPT = """<script>(function(){
var me=document.currentScript,box=me&&me.previousElementSibling;
if(!box||box.id!==%(id)s)box=document.getElementById(%(id)s);if(!box)return;
var data=%(data)s,size=%(size)s,rel=%(rel)s,server=%(server)s;
var local=location.protocol==="file:";
var places=local?[rel]:[server,rel].filter(Boolean);
function play(u){var f=document.createElement("iframe");f.src=u+"#"+data;f.width="100%%";
f.height=%(height)s;f.title=%(title)s;f.style.cssText="border:1px solid #ddd;display:block";
box.replaceChildren(f);}
function next(i){if(i>=places.length)return;if(local){play(places[i]);return;}
fetch(places[i],{method:"HEAD",credentials:"same-origin"}).then(function(r){
var n=r.headers.get("content-length");if(r.ok&&(n===null||Number(n)===size))play(places[i]);else next(i+1);
},function(){next(i+1);});}
next(0);})();</script>"""


@functools.cache
def player_page() -> bytes:
    """viser's client page that plays the recording given in its address's fragment."""
    page = client_page().read_text(encoding="utf-8")
    head_end = page.index("</head>")
    return (page[:head_end] + _FROM_FRAGMENT + page[head_end:]).encode("utf-8")


def player_name() -> str:
    """The player's file name, with a digest of its bytes (another viser, another file)."""
    return f"player-{hashlib.sha256(player_page()).hexdigest()[:12]}.html"


def write_player(folder: str | Path) -> Path:
    """Write the player into ``folder/jacobian-lab-player/`` unless it is there already; returns its path.

    Raises:
        OSError: the folder or the file cannot be written.
    """
    page = player_page()
    path = Path(folder) / PLAYER_DIR / player_name()
    if path.is_file() and not path.is_symlink() and path.stat().st_size == len(page):
        return path
    path.parent.mkdir(parents=True, exist_ok=True)
    write_user_file(path, page, named=False)
    return path


def _running_servers() -> list[Mapping[str, Any]]:
    try:
        from jupyter_server.serverapp import list_running_servers
    except ImportError:  # not in a Jupyter kernel's environment: the relative path only
        return []
    try:
        return list(list_running_servers())
    except (OSError, ValueError):
        return []


def server_player_url(
    folder: str | Path, servers: Iterable[Mapping[str, Any]] | None = None, parent: int | None = None
) -> str | None:
    """Where the Jupyter server serves the player written in ``folder``: ``{base_url}files/{path}``,
    from the running server whose root holds ``folder`` (the kernel's own server, its parent process,
    first); ``None`` when no server's root holds it."""
    where = Path(folder).resolve()
    ppid = os.getppid() if parent is None else parent
    found = list(_running_servers() if servers is None else servers)
    for server in sorted(found, key=lambda s: s.get("pid") != ppid):
        root = server.get("root_dir") or server.get("notebook_dir")
        if not root:
            continue
        try:
            inside = where.relative_to(Path(root).expanduser().resolve())
        except ValueError:
            continue
        base = str(server.get("base_url") or "/")
        base = base if base.endswith("/") else base + "/"
        path = "/".join(quote(part) for part in (*inside.parts, PLAYER_DIR, player_name()))
        return f"{base}files/{path}"
    return None


def _js(value: object) -> str:
    """A JavaScript literal safe inside ``<script>``."""
    return json.dumps(value).replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


def cell_html(recording: Recording, height: int, server_url: str | None) -> str:
    """The cell's HTML: the line shown with no player, and the script that frames the player."""
    data = base64.b64encode(recording.data).decode("ascii")
    box = "jacobian-lab-demo-" + hashlib.sha256(recording.data).hexdigest()[:16]
    tr = translations(recording.language)
    # TRANSLATORS: shown in a notebook cell when the demo's player page is not found; {folder} is a
    # folder's name, {title} the demo's title.
    line = tr.gettext(
        "The recorded demo “{title}” plays in Jupyter, or in this notebook's HTML export next to the "
        "folder {folder}: run the cell again to write the player there."
    )
    text = html.escape(line).replace("{title}", html.escape(recording.title))
    text = text.replace("{folder}", f"<code>{PLAYER_DIR}/</code>")
    script = _SCRIPT % {
        "id": _js(box),
        "data": _js(data),
        "size": len(player_page()),
        "rel": _js(f"{PLAYER_DIR}/{player_name()}"),
        "server": _js(server_url),
        "height": _js(str(int(height))),
        "title": _js(recording.title),
    }
    return f'<div id="{box}"><p style="font:14px sans-serif;color:#555">{text}</p></div>{script}'
