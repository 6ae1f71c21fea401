"""A recorded demo in a notebook stays small (app.demo.player): the player page is written once beside
the notebook and the cell holds the recording alone; issue 30's target is ≤ 300 kB for the docs' demo."""

from __future__ import annotations

import base64
import html
import json
import re

import nbformat
import pytest

import robots
from app.core.i18n import translations
from app.demo.folder import client_page
from app.demo.player import PLAYER_DIR, player_name, player_page, server_player_url, write_player
from app.demo.record import record
from app.notebook import show_recording


@pytest.fixture(autouse=True)
def _not_in_vs_code(monkeypatch):
    """These tests run as Jupyter's kernel would (a terminal of VS Code would choose the inline page)."""
    for name in ("VSCODE_PID", "VSCODE_CWD", "COLAB_RELEASE_TAG"):
        monkeypatch.delenv(name, raising=False)


def _saved_size(view) -> int:
    """The .ipynb's size with the view as a cell's output, as Jupyter saves it."""
    cell = nbformat.v4.new_code_cell("show_recording(...)")
    cell.outputs = [
        nbformat.v4.new_output(
            "execute_result",
            data={"text/html": view._repr_html_(), "text/plain": repr(view)},
            execution_count=1,
        )
    ]
    return len(nbformat.writes(nbformat.v4.new_notebook(cells=[cell])).encode("utf-8"))


def test_the_docs_demo_adds_under_300_kB_to_the_notebook_and_the_cell_holds_the_recording(tmp_path):
    """The docs' demo (Puma 560, 4 s at 15 fps): 42 kB, was 870 kB with the player in every cell."""
    rec = record("puma560", robots.load("puma560"), seconds=4, fps=15)
    view = show_recording(rec, folder=tmp_path)
    size = _saved_size(view)
    encoded = len(base64.b64encode(rec.data))
    assert size <= 300_000
    assert encoded < size < encoded + 5_000  # the recording, a script and one line: no player inside
    cell = view._repr_html_()
    data = json.loads(re.search(r"var data=(\"[^\"]*\")", cell).group(1))
    assert base64.b64decode(data) == rec.data  # the whole recording, in the notebook itself
    assert json.loads(re.search(r"rel=(\"[^\"]*\")", cell).group(1)) == f"{PLAYER_DIR}/{player_name()}"
    written = tmp_path / PLAYER_DIR / player_name()
    assert written.read_bytes() == player_page()
    assert len(player_page()) > client_page().stat().st_size > size  # what the cell no longer carries


def test_the_player_is_written_once_per_folder_and_named_by_its_bytes(tmp_path):
    first = write_player(tmp_path)
    stamp = first.stat().st_mtime_ns
    again = show_recording(record("planar2", robots.load("planar2"), seconds=1, fps=5), folder=tmp_path)
    assert first.stat().st_mtime_ns == stamp and [p.name for p in (tmp_path / PLAYER_DIR).iterdir()] == [
        first.name
    ]
    assert again.player_url is None  # no Jupyter server's root holds tmp_path
    first.write_bytes(b"cut short")  # a broken copy is written again
    assert write_player(tmp_path).read_bytes() == player_page()
    page = player_page().decode("utf-8")
    assert page.index("location.hash.slice(1)") < page.index("</head>")  # the recording from the fragment


def test_the_player_url_is_where_the_kernels_server_serves_the_folder(tmp_path):
    folder = tmp_path / "course" / "week 1"
    folder.mkdir(parents=True)
    servers = [
        {"pid": 11, "root_dir": str(tmp_path / "elsewhere"), "base_url": "/"},
        {"pid": 12, "root_dir": str(tmp_path), "base_url": "/user/ana/"},
        {"pid": 13, "root_dir": str(tmp_path / "course"), "base_url": "/"},
    ]
    name = player_name()
    assert server_player_url(folder, servers, parent=13) == f"/files/week%201/{PLAYER_DIR}/{name}"
    assert (
        server_player_url(folder, servers, parent=12)
        == f"/user/ana/files/course/week%201/{PLAYER_DIR}/{name}"
    )
    assert server_player_url(folder, servers[:1], parent=12) is None


@pytest.mark.parametrize("lang, words", [("en", "HTML export next to"), ("es", "celda"), ("pl", "komórkę")])
def test_with_no_player_or_no_scripts_the_cell_says_where_the_player_goes(lang, words, tmp_path):
    rec = record("planar2", robots.load("planar2"), seconds=1, fps=5, tr=translations(lang))
    cell = show_recording(rec, folder=tmp_path)._repr_html_()
    line = re.search(r"<p[^>]*>(.*?)</p>", cell).group(1)
    assert words in line and f"<code>{PLAYER_DIR}/</code>" in line
    assert cell.index("</p>") < cell.index("<script>")  # shown until the script finds the player


def test_a_folder_that_cannot_be_written_gets_the_whole_page_in_the_cell(tmp_path):
    rec = record("planar2", robots.load("planar2"), seconds=1, fps=5)
    (tmp_path / PLAYER_DIR).write_text("a file where the folder goes")
    with pytest.warns(UserWarning, match="cannot be written"):
        view = show_recording(rec, folder=tmp_path)
    cell = view._repr_html_()
    assert cell.startswith('<iframe srcdoc="') and html.unescape(cell.split('"')[1]) == view.html()


def test_vs_code_and_colab_get_the_whole_page_and_inline_chooses_either(tmp_path):
    rec = record("planar2", robots.load("planar2"), seconds=1, fps=5)
    vscode = show_recording(rec, folder=tmp_path, environ={"VSCODE_PID": "4242"})
    colab = show_recording(rec, folder=tmp_path, environ={"COLAB_RELEASE_TAG": "release-colab_20260101"})
    for view in (vscode, colab):
        assert view._repr_html_().startswith('<iframe srcdoc="')  # their webviews frame no file beside it
    assert not (tmp_path / PLAYER_DIR).exists()
    forced = show_recording(rec, folder=tmp_path, inline=False, environ={"VSCODE_PID": "4242"})
    assert "var data=" in forced._repr_html_() and (tmp_path / PLAYER_DIR).is_dir()
    assert (
        show_recording(rec, folder=tmp_path, inline=True, environ={})
        ._repr_html_()
        .startswith("<iframe srcdoc=")
    )
