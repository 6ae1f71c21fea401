"""The Motion, Maps, v = J q̇, q̇ = J⁺v, τ = JᵀF and Build tabs, their notices and refusals in the tab's
language (issue 27), server level: every text of every widget of those tabs (labels, hints, options,
HTML, the charts' titles and axes) is walked in a tab with ?lang=pl / pt / es and checked against the
English of the catalogs; the robot file's own words (names, presets, joints) aside, they are another
area's."""

from __future__ import annotations

import json
import re
from typing import Any

import numpy as np
import pytest
from app_helpers import running_lab, wait_until
from babel.messages.pofile import read_po
from test_i18n_app import numbers_of, report

import robots
from app.core.actions import GoTo, Play, SetDesired, SetOption
from app.core.commands import ToggleRecording
from app.core.i18n import LOCALE_DIR, language_of, translations
from app.core.refusals import say
from app.views.panel import TABS

MY_TABS = ("motion", "maps", "forward", "inverse", "force", "build")
_LABELS = {tab.name: tab.label for tab in TABS}
ENGLISH_WORDS = re.compile(
    r"\b(the|and|of|with|from|this|your|is|are|at|joints?|tool|rates?|rows?|velocity|singular(ity)?)\b",
    re.IGNORECASE,
)
"""Words of English no Portuguese, Spanish or Polish sentence holds."""


def _texts_of(obj: Any, out: list[str]) -> None:
    if isinstance(obj, str):
        out.append(obj)
    elif isinstance(obj, dict):
        for value in obj.values():
            _texts_of(value, out)
    elif isinstance(obj, (list, tuple)):
        for value in obj:
            _texts_of(value, out)


def widget_texts(handle: Any) -> list[str]:
    """Every string the browser is sent for ``handle`` and everything under it (label, hint, options,
    HTML content, a chart's title, series and axes labels; not a chart's numbers), HTML tags and style
    blocks taken out."""
    found: list[str] = []
    impl = getattr(handle, "_impl", None)
    if impl is not None:
        props = impl.props
        for name in dir(props):
            if name.startswith("_") or name == "data":
                continue
            value = getattr(props, name)
            if not callable(value):
                _texts_of(value, found)
    for child in getattr(handle, "_children", {}).values():
        found += widget_texts(child)
    out = []
    for text in found:
        text = re.sub(r"<style>.*?</style>|data:image/[^\"]*", " ", text, flags=re.S)
        text = re.sub(r"<[^>]+>", " ", text).replace("&nbsp;", " ")
        if text.strip():
            out.append(re.sub(r"\s+", " ", text).strip())
    return out


def robot_file_words(state) -> list[str]:
    """The robot file's own words shown in the tabs (its names, presets' names and descriptions, joint
    names, the library's robot names): translated by the robot files, not by the catalogs."""
    robot = state.robot
    words = [j.name for j in robot.joints] + [robot.name, robot.title or ""]
    for preset in robots.motions(state.robot_name):
        words += [preset.name, preset.description or ""]
    words += list(robots.names())
    return sorted((w for w in words if w), key=len, reverse=True)


def english_fragments(code: str) -> list[str]:
    """The English of the catalog's messages that the language's catalog does not say the same: each
    message's pieces between placeholders, HTML taken out, of two words and 10 characters or more."""
    locale = language_of(code).locale
    with (LOCALE_DIR / locale / "LC_MESSAGES" / "messages.po").open("rb") as f:
        catalog = read_po(f, locale=locale)
    fragments = set()
    for message in catalog:
        if not message.id:
            continue
        ids = message.id if isinstance(message.id, tuple) else (message.id,)
        said = " ".join(message.string if isinstance(message.string, tuple) else (message.string,))
        for english in ids:
            for piece in re.split(r"\{\w*\}", re.sub(r"<[^>]+>", " ", english)):
                piece = re.sub(r"\s+", " ", piece).strip(" .,:;()")
                if len(piece) >= 10 and " " in piece and piece not in said:
                    fragments.add(piece)
    return sorted(fragments)


def shown_in(session, code: str) -> dict[str, list[str]]:
    """Each of the tabs' texts in language ``code``, with the preset played and a desired v set."""
    report(session, address=f"?lang={code}")
    assert session.language == code
    panel = session.panel
    panel.motion._click(session.dispatch, "Play")  # the shown preset, applied and played
    session.settle()
    wait_until(lambda: session.state.playing)
    session.settle()
    session.dispatch(SetOption("joint_map", True))
    session.dispatch(SetOption("workspace", True))
    session.dispatch(SetDesired(0, 0.1))  # a v the wrist cannot give all of at the singularity
    session.settle()
    texts = {}
    for name in MY_TABS:  # each drawn open, as the user sees it
        report(session, kind="tab", tab=panel.tabs[name]._label)
        wait_until(lambda name=name: session.page.tab == _LABELS[name])
        session.settle()
        texts[name] = widget_texts(panel.tabs[name])
    return texts


@pytest.mark.parametrize(
    ("code", "words"),
    [
        ("pl", {"motion": "Metoda jakobianowa", "maps": "Kliknij mapę", "build": "Zacznij od"}),
        ("pt", {"motion": "Controle por velocidade", "maps": "Clique no mapa", "build": "Começar de"}),
        ("es", {"motion": "Control por velocidad", "maps": "Hacé clic en el mapa", "build": "Partir de"}),
    ],
)
def test_every_text_of_the_tabs_is_in_the_tabs_language(code, words):
    with running_lab() as (_lab, session, _ws):
        session.dispatch(GoTo("wrist_singular"))  # the wrist lost: the mappings say what is lost
        session.settle()
        english = english_fragments(code)
        texts = shown_in(session, code)
        for tab, word in words.items():
            assert any(word in text for text in texts[tab]), f"{tab}: no «{word}»"
        left = []
        own = robot_file_words(session.state)
        for tab, shown in texts.items():
            for text in shown:
                for word in own:  # the robot file's words are another area's
                    text = text.replace(word, " ")
                left += [f"{tab}: {piece!r} in {text!r}" for piece in english if piece in text]
                if ENGLISH_WORDS.search(text):
                    left.append(f"{tab}: English word in {text!r}")
        assert not left, "\n".join(left[:20])
        # the played preset's readout and the charts' axes in the language, numbers with a decimal comma
        readout = session.panel.motion.readout.content
        assert numbers_of(readout) and all("," in x for x in numbers_of(readout)), readout
        title = {
            "pl": "prędkości w przegubach",
            "pt": "velocidades das juntas",
            "es": "velocidades articulares",
        }
        assert session.panel.motion.rates.title.startswith(title[code])


def test_the_same_walk_finds_english_in_an_english_tab():
    """The check can fail: in English the same walk finds the English words it looks for."""
    with running_lab() as (_lab, session, _ws):
        texts = shown_in(session, "en")
        english = english_fragments("pl")
        found = [p for shown in texts.values() for text in shown for p in english if p in text]
        assert len(found) > 20
        assert any(ENGLISH_WORDS.search(text) for shown in texts.values() for text in shown)


@pytest.mark.parametrize(
    ("code", "refusal"),
    [
        ("pl", "Wiersz 1, dolne ograniczenie: dolne ograniczenie 90 jest większe od górnego 10"),
        ("pt", "Linha 1, limite inferior: o limite inferior 90 é maior que o superior 10"),
        ("es", "Fila 1, límite inferior: el límite inferior 90 es mayor que el superior 10"),
        ("en", "Row 1, lower limit: the lower limit 90 is above the upper limit 10"),
    ],
)
def test_the_build_tab_reads_a_decimal_comma_and_refuses_in_the_tabs_language(code, refusal):
    with running_lab() as (_lab, session, _ws):
        report(session, address=f"?lang={code}")
        editor = session.panel.editor
        editor.a.value = "0,3" if code != "en" else "0.3"
        session.settle()
        assert editor.error == "" and editor.built is not None
        assert editor.built.dh is not None and editor.built.dh[0].a == pytest.approx(0.3)
        assert ("0,3" if code != "en" else "0.3") in editor.summary.content  # the table, as it writes numbers
        editor.lower.value = "90"
        editor.upper.value = "10"
        session.settle()
        assert editor.error == refusal
        assert refusal in editor.problem.content


def test_a_decimal_point_is_refused_in_polish_with_the_reason_in_polish():
    with running_lab() as (_lab, session, _ws):
        report(session, address="?lang=pl")
        editor = session.panel.editor
        editor.d.value = "1.000"
        session.settle()
        assert editor.error.startswith("Wiersz 1, d [m]: ")
        assert "przecinkiem" in editor.error


@pytest.mark.parametrize(
    ("code", "title", "body"),
    [
        ("pl", "Nic nie nagrano", "Porusz czymś"),
        ("pt", "Nada foi gravado", "Mova algo"),
        ("es", "No se grabó nada", "Mové algo"),
    ],
)
def test_a_notice_speaks_the_tabs_language(code, title, body):
    with running_lab() as (_lab, session, ws):
        report(session, address=f"?lang={code}")
        mark = ws.mark()
        session.dispatch(ToggleRecording())
        session.settle()
        session.dispatch(ToggleRecording())  # nothing moved: nothing recorded
        session.settle()
        _, notice = ws.wait_for(lambda m: m["type"] == "NotificationShowMessage", after=mark)
        assert notice["props"]["title"] == title
        assert notice["props"]["body"].startswith(body)


@pytest.mark.parametrize(
    ("code", "why"),
    [
        ("pl", "najpierw ustaw prędkość efektora v (albo wybierz przykład)"),
        ("pt", "defina antes uma velocidade da garra v (ou escolha um exemplo)"),
        ("es", "primero fijá una velocidad del extremo v (o elegí un ejemplo)"),
    ],
)
def test_a_refused_motion_says_why_in_the_tabs_language(code, why):
    with running_lab() as (_lab, session, _ws):
        report(session, address=f"?lang={code}")
        session.panel.motion.preset.value = session.panel.motion.own_twist  # "your own v", in its words
        session.settle()
        session.dispatch(Play(True, "resolved_rate"))  # no v set: refused, in English in the state
        session.settle()
        assert session.state.stopped == "set a tool velocity v first (or choose a preset)"
        assert why in session.panel.motion.readout.content
        assert why in session.panel.status.content


def test_a_stop_written_by_the_kinematics_is_said_with_its_values_and_decimal_commas():
    """The resolved-rate step's message (kinematics, English) reaches the tab in its language, the joint's
    name kept and its numbers written with a decimal comma."""
    from kinematics.motion.resolved_rate import resolved_rate_step

    robot = robots.load("puma560")
    q = robot.qlim[0] + 1e-3  # every joint just above its lower limit
    stop = next(
        (
            step[2]
            for k in range(6)
            for sign in (1.0, -1.0)
            if (step := resolved_rate_step(robot, q, sign * 0.05 * np.eye(6)[k], dt=1.0))[2] is not None
            and "would pass its" in step[2].message
        ),
        None,
    )
    assert stop is not None
    text = say(f"stopped: {stop.message}", translations("pl"))
    assert text.startswith("zatrzymano: przegub ") and "granic" in text, text
    assert "would" not in text
    assert say(
        "w of the held rows (vx, vy) reached a maximum with the tool held: w = 0.4321", translations("es")
    ) == ("w de las filas sostenidas (vx, vy) llegó a un máximo con el extremo fijo: w = 0,4321")


def test_the_number_boxes_guard_speaks_the_tabs_language():
    """The page script that stops a comma in a slider's number box (a Mantine box takes a point) says so
    in the tab's words; a translation is data in the script (JSON), never its code."""
    from app.views.panel.typed import SAID, number_guard_js

    polish = number_guard_js(translations("pl"))
    assert "To pole przyjmuje kropkę dziesiętną: 0.3, nie 0,3." in polish
    assert not [text for text in SAID.values() if text in polish and "{" not in text]
    words = re.search(r"const SAID = (\{.*?\});\n", polish).group(1)
    assert json.loads(words)["dropped"] == "Wykładnik porzucony."
    assert "Use a point for decimals: 0.3, not 0,3." in number_guard_js(translations("en"))


@pytest.mark.parametrize(
    ("code", "wrong", "spent"),
    [
        ("pl", "to nie jest kod prowadzącego", "ta karta wpisała 5 błędnych kodów"),
        ("pt", "esse não é o código do apresentador", "esta aba digitou 5 códigos errados"),
        ("es", "ese no es el código del presentador", "esta pestaña escribió 5 códigos equivocados"),
    ],
)
def test_a_refused_presenter_token_is_said_in_the_tabs_language(code, wrong, spent):
    """The classroom refuses a token in English (one classroom serves every language); the tab says
    why in its own words, the spent connection's count with the language's plural."""
    from types import SimpleNamespace

    from app.core.commands import ClaimPresenter
    from app.services.classroom import TOKEN_TRIES, Classroom
    from app.tab.following import Following

    said: list[tuple[str, str]] = []
    notices = SimpleNamespace(
        tr=translations(code), notify=lambda title, body, seconds=8.0: said.append((title, body))
    )
    room = Classroom("a-strong-token-for-the-test-1234")
    member = SimpleNamespace(
        latest=(None, None), scene_messages=(), role=None, subscribe=lambda fn: lambda: None
    )
    member.mirror = member.mirror_camera = member.mirror_tab = lambda *a, **k: None
    member.role_changed = lambda role: None
    room.join(1, member)
    following = Following(1, room, lambda m: None, notices, lambda: None, None, None, None, None)
    for i in range(TOKEN_TRIES + 1):
        following._typed_token = f"guess-{i}"
        following.command(ClaimPresenter(f"guess-{i}", settled=True))
    bodies = [body for _, body in said]
    assert len(bodies) == TOKEN_TRIES + 1
    assert bodies[0] == wrong and bodies[-1].startswith(spent), bodies
    assert not [b for b in bodies if "token" in b or "reload" in b], bodies
    assert said[0][0] == translations(code).gettext("Not the presenter") != "Not the presenter"
