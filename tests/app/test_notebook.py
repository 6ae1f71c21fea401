"""The app in a notebook (app.notebook): the live lab's state API, its iframe, the Origin check it keeps,
and a recorded demo embedded with no server."""

from __future__ import annotations

import base64
import html
import re
import socket

import numpy as np
import pytest
import viser
import websockets.sync.client
from fakes import FakeSymbolicService, poll
from websockets.exceptions import InvalidStatus
from wsclient import ViserWsClient

import robots
from app.core.actions import SetJoint
from app.demo.record import record
from app.notebook import NotebookLab, hub_origin, proxied_url, show, show_recording
from app.server import Lab
from kinematics import jacobian


def _notebook_lab(robot: str = "planar2", **kwargs) -> NotebookLab:
    return NotebookLab(Lab(robot=robot, port=0, symbolic=FakeSymbolicService(), **kwargs))


def test_the_state_api_before_any_tab_is_the_notebooks_own():
    nb = _notebook_lab("puma560")
    try:
        robot = robots.load("puma560")
        assert np.array_equal(nb.q, robot.home)
        np.testing.assert_allclose(nb.J, jacobian(robot, robot.home), atol=1e-12)
        q = np.array([0.1, -0.4, 0.3, 0.2, 0.5, -0.7])
        shown = nb.set_q(q)  # no tab yet: the notebook's own state moves
        np.testing.assert_allclose(shown, q, atol=1e-12)
        np.testing.assert_allclose(nb.J, jacobian(robot, q), atol=1e-12)
        assert nb.snapshot.report.condition == pytest.approx(np.linalg.cond(jacobian(robot, q)), rel=1e-9)
        with pytest.raises(ValueError, match="6 finite numbers for puma560"):
            nb.set_q([0.0, 1.0])
        with pytest.raises(ValueError, match="finite"):
            nb.set_q([np.nan] * 6)
    finally:
        nb.stop()


def test_set_q_moves_every_tab_and_a_slider_moved_in_the_cell_is_read_back():
    nb = _notebook_lab("planar2")
    robot = robots.load("planar2")
    try:
        with ViserWsClient(f"ws://127.0.0.1:{nb.lab.port}") as ws:
            session = nb.lab.session()
            mark = ws.mark()
            nb.set_q([0.3, -0.5])
            assert np.allclose(session.state.q, [0.3, -0.5]) and np.allclose(session.snapshot.q, [0.3, -0.5])
            ws.wait_for(lambda m: m["type"] == "SceneNodeUpdateMessage", after=mark)  # the cell's arm moved
            np.testing.assert_allclose(nb.J, jacobian(robot, [0.3, -0.5]), atol=1e-12)
            session.dispatch(SetJoint(0, 0.1))  # the student drags joint 1 in the cell
            session.settle()
            np.testing.assert_allclose(nb.q, [0.1, -0.5], atol=1e-12)
            np.testing.assert_allclose(nb.J, jacobian(robot, [0.1, -0.5]), atol=1e-12)
            # a tab opened later (the notebook reloaded) starts where the notebook put the arm
            nb.set_q([0.7, 0.2])
            with ViserWsClient(f"ws://127.0.0.1:{nb.lab.port}"):
                poll(lambda: len(nb.lab.sessions) == 2)
                late = nb.lab.session()
                assert late is not session
                poll(lambda: np.allclose(late.state.q, [0.7, 0.2]))
    finally:
        nb.stop()


def test_the_cell_frames_the_labs_own_page_and_the_origin_check_still_holds():
    nb = _notebook_lab("planar2")
    try:
        port = nb.lab.port
        frame = nb._repr_html_()
        assert re.search(rf'<iframe data-src="http://127\.0\.0\.1:{port}/"', frame), frame
        url, proto = f"ws://127.0.0.1:{port}", [f"viser-v{__import__('viser').__version__}"]
        # the framed page is the lab's own: its websocket says the lab's origin, and is accepted
        with websockets.sync.client.connect(url, origin=f"http://127.0.0.1:{port}", subprotocols=proto):
            pass
        # the notebook's page (another origin) may not connect, as any other page
        with pytest.raises(InvalidStatus) as refused:
            websockets.sync.client.connect(url, origin="http://localhost:8888", subprotocols=proto)
        assert refused.value.response.status_code == 403
    finally:
        nb.stop()
    # behind a proxy the notebook's origin is allowed explicitly, and only it
    nb = _notebook_lab("planar2", allow_origin=["https://hub.example.org"])
    try:
        url = f"ws://127.0.0.1:{nb.lab.port}"
        with websockets.sync.client.connect(url, origin="https://hub.example.org", subprotocols=proto):
            pass
        with pytest.raises(InvalidStatus):
            websockets.sync.client.connect(url, origin="https://evil.example.org", subprotocols=proto)
    finally:
        nb.stop()


def test_show_serves_from_the_kernel_and_stop_closes_the_port(monkeypatch):
    monkeypatch.setattr("app.server.SymbolicService", FakeSymbolicService)
    nb = show("planar2", height=500)
    port = nb.lab.port
    assert 'height="500"' in nb._repr_html_() and "serving http://127.0.0.1" in repr(nb)
    with socket.create_connection(("127.0.0.1", port), timeout=5):
        pass
    nb.stop()
    nb.stop()  # twice is harmless (the kernel's exit calls it again)
    assert "stopped" in repr(nb)
    poll(lambda: _refused(port))


def test_show_lang_speaks_that_language_in_the_cell(monkeypatch):
    from wsclient import ViserWsClient

    monkeypatch.setattr("app.server.SymbolicService", FakeSymbolicService)
    nb = show("planar2", lang="es")
    try:
        with ViserWsClient(f"ws://127.0.0.1:{nb.lab.port}", headers={"Accept-Language": "pl"}):
            session = nb.lab.session()
            assert session.language == "es"  # the cell's language, over the browser's
            assert "configuración regular" in session.panel.status.content
    finally:
        nb.stop()
    with pytest.raises(ValueError, match="no language"):
        show("planar2", lang="fr")


def _refused(port: int) -> bool:
    try:
        socket.create_connection(("127.0.0.1", port), timeout=1).close()
        return False
    except OSError:
        return True


def test_a_recorded_demo_saves_as_one_self_contained_page(tmp_path):
    robot = robots.load("planar2")
    rec = record("planar2", robot, seconds=1.0, fps=10)
    view = show_recording(rec, height=400, folder=tmp_path)
    page = view.html()
    data = re.search(r'window\.__VISER_EMBED_DATA__="([A-Za-z0-9+/=]*)"', page).group(1)
    assert base64.b64decode(data) == rec.data  # the whole recording, no file or server behind it
    assert f"<title>{html.escape(rec.title)}</title>" in page
    assert page.index("__VISER_EMBED_DATA__") < page.index("</head>")
    assert "11 frames, 1.0 s" in repr(view)


def test_show_with_lang_speaks_that_language_in_the_cell(monkeypatch):
    """show(..., lang="es"): the cell's address says ?lang=es and a tab that connects speaks the Argentinian
    course's Spanish (the Puma's configuration text from its robot file, the status in the panel's words)."""
    from app.core.actions import GoTo

    monkeypatch.setattr("app.server.SymbolicService", FakeSymbolicService)
    with pytest.raises(ValueError, match="no language 'fr'"):
        show("planar2", lang="fr")
    nb = show("puma560", lang="es")
    try:
        port = nb.lab.port
        assert f'src="http://127.0.0.1:{port}/?lang=es"' in nb._repr_html_()
        with ViserWsClient(f"ws://127.0.0.1:{port}"):
            session = nb.lab.session()
            assert session.language == "es"
            session.dispatch(GoTo("wrist_singular"))
            session.settle()
            status = session.panel.status.content
            assert "configuración singular" in status and "la flexión de muñeca q5 = 0" in status
    finally:
        nb.stop()
    assert show.__kwdefaults__["lang"] == ""  # default: the notebook browser's own language


def test_under_jupyterhub_show_frames_the_lab_through_the_proxy_and_accepts_the_hubs_pages(monkeypatch):
    monkeypatch.setattr("app.server.SymbolicService", FakeSymbolicService)
    monkeypatch.setenv("JUPYTERHUB_SERVICE_PREFIX", "/user/ana/")
    monkeypatch.setenv("JUPYTERHUB_PUBLIC_URL", "https://hub.example.org/")
    nb = show("planar2", lang="pl")
    try:
        port = nb.lab.port
        assert nb.url == f"/user/ana/proxy/{port}/?lang=pl"  # a path on the notebook's own origin
        assert f'src="/user/ana/proxy/{port}/?lang=pl"' in nb._repr_html_()
        proto = ["viser-v" + viser.__version__]

        def through_the_proxy(origin: str) -> None:
            # jupyter-server-proxy passes the browser's Host and Origin on to 127.0.0.1:port
            sock = socket.create_connection(("127.0.0.1", port), timeout=10)
            with websockets.sync.client.connect(
                "ws://hub.example.org/", sock=sock, origin=origin, subprotocols=proto
            ):
                pass

        through_the_proxy("https://hub.example.org")  # the hub's page is accepted ...
        with pytest.raises(InvalidStatus):
            through_the_proxy("https://evil.example.org")  # ... and any other site's still refused
    finally:
        nb.stop()


def test_proxied_url_and_hub_origin_read_jupyterhubs_environment():
    assert proxied_url(8765, {}) is None  # not under JupyterHub: the lab's own address is used
    assert proxied_url(8765, {"JUPYTERHUB_SERVICE_PREFIX": "/user/me/"}) == "/user/me/proxy/8765/"
    assert proxied_url(8765, {"JUPYTERHUB_SERVICE_PREFIX": "user/me"}) == "/user/me/proxy/8765/"
    assert (
        hub_origin({"JUPYTERHUB_PUBLIC_URL": "https://hub.example.org:8443/hub/"})
        == "https://hub.example.org:8443"
    )
    assert hub_origin({"JUPYTERHUB_PUBLIC_URL": ""}) is None and hub_origin({}) is None


def test_the_notebook_tools_are_an_extra_of_their_own_and_the_test_extra_holds_them():
    from pathlib import Path

    import tomllib

    extras = tomllib.loads((Path(__file__).parents[2] / "pyproject.toml").read_text())["project"][
        "optional-dependencies"
    ]
    names = {re.split(r"[<>=\[ ]", d)[0] for d in extras["notebook"]}
    assert {"ipykernel", "nbformat", "nbclient", "jupyter-server-proxy"} <= names
    assert set(extras["notebook"]) <= set(extras["test"])  # the suite runs the notebook tests
