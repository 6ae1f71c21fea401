"""A tab in its own language (issue 27), server level: chosen from the handshake's Accept-Language, the
page's address (?lang=) or navigator.languages, the Language menu and the room's default; words and
numbers of the panel in that language; a follower keeps its own language while following."""

from __future__ import annotations

import json
import re

import pytest
from app_helpers import running_lab, wait_until
from wsclient import ViserWsClient

from app.core.actions import GoTo, SetJoint
from app.core.i18n import translations
from app.views import fmt
from app.views.panel import TAB_LABELS

TOKEN = "lecture-27"


def report(session, **fields) -> None:
    """What the page script sends on (re)connection, typed into the hidden report input."""
    fields.setdefault("kind", "load")
    session.panel.report.value = json.dumps(fields)
    session.settle()
    session.settle()


def newest(lab, known):
    wait_until(lambda: any(s not in known for s in lab.sessions.values()))
    return next(s for s in lab.sessions.values() if s not in known)


def status_words(session) -> str:
    """The status banner's words (the second span of the banner)."""
    return re.findall(r"<span>([^<]*)</span>", session.panel.status.content)[1]


def numbers_of(html: str) -> list[str]:
    """The decimal numbers of a piece of HTML's text, as written (``0.432`` or ``0,432``)."""
    return re.findall(r"\d+[.,]\d+", re.sub(r"<[^>]*>", " ", html))


def test_a_tab_whose_address_says_lang_pl_speaks_polish_with_decimal_commas():
    with running_lab() as (_lab, session, _ws):
        assert session.language == "en" and status_words(session) == "regular"
        english = session.panel.matrix.numeric.content
        assert numbers_of(english) and all("." in x for x in numbers_of(english))
        report(session, address="?lang=pl")
        assert session.language == "pl"
        panel = session.panel
        assert status_words(session) == "konfiguracja regularna"
        numbers = numbers_of(panel.matrix.numeric.content)
        assert numbers and all("," in x for x in numbers)  # the same J, written with decimal commas
        assert "prędkość punktu efektora" in panel.matrix.numeric.content
        assert "Układ współrzędnych J" == panel.matrix.frame.label
        session.dispatch(GoTo("wrist_singular"))
        session.settle()
        assert status_words(session) == "konfiguracja osobliwa: nadgarstek"
        assert "Osobliwość nadgarstka" in panel.status.content  # the lost rotation, in Polish
        assert "κ = ∞" in panel.status.content
        # the address keeps the language, with robot and q
        wait_until(lambda: session.page.address.endswith("&lang=pl"))  # written at most every 0.4 s
        assert "robot=puma560&q=" in session.page.address


@pytest.mark.parametrize(
    ("accept", "code", "words"),
    [
        ("pt-BR,pt;q=0.9,en;q=0.8", "pt", "configuração regular"),
        ("es-MX,es;q=0.9", "es", "configuración regular"),  # the nearest the lab has: es_AR
        ("pt-PT", "pt", "configuração regular"),
        ("fr-FR,fr;q=0.9", "en", "regular"),  # none it has: English
    ],
)
def test_the_handshakes_accept_language_chooses_the_first_language(accept, code, words):
    with running_lab() as (lab, first, _ws):
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}", headers={"Accept-Language": accept}):
            session = newest(lab, {first})
            assert session.language == code
            assert status_words(session) == words


def test_navigator_languages_choose_when_the_handshake_said_nothing():
    with running_lab() as (_lab, session, _ws):
        report(session, address="", languages=["es-AR", "en"])
        assert session.language == "es" and status_words(session) == "configuración regular"


def test_an_unknown_lang_speaks_english_and_says_so_in_english():
    with running_lab() as (lab, first, _ws):
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}", headers={"Accept-Language": "pl"}) as ws:
            session = newest(lab, {first})
            assert session.language == "pl"
            mark = ws.mark()
            report(session, address="?lang=xx")
            assert session.language == "en" and status_words(session) == "regular"
            _, notice = ws.wait_for(lambda m: m["type"] == "NotificationShowMessage", after=mark)
            assert "“xx”" in notice["props"]["body"] and "English" in notice["props"]["body"]


def test_the_language_menu_rebuilds_the_panel_in_that_language_and_keeps_it_in_the_address():
    with running_lab() as (_lab, session, _ws):
        report(session, address="")
        session.dispatch(SetJoint(1, 0.4))
        session.settle()
        before = session.state
        session.panel.language.value = "Español (Argentina)"
        session.settle()
        assert session.language == "es" and session.state is before  # the state is untouched
        assert status_words(session) == "configuración regular"
        assert session.panel.language.value == "Español (Argentina)"
        assert [t._label for t in session.panel.tabs.values()][4:] == [
            "Movimiento",
            "Mapas",
            "Deducción",
            "Vista",
            "Armar",
        ]
        assert session.panel.joints is not None and session.panel.matrix is not None
        session.dispatch(SetJoint(1, 0.5))  # the rebuilt panel is live
        session.settle()
        assert session.state.q[1] == pytest.approx(0.5)
        wait_until(lambda: session.page.address.endswith("&lang=es"))


def test_the_rooms_language_is_the_default_and_a_tabs_own_choice_wins():
    with running_lab(language="pl") as (lab, first, _ws):
        assert first.language == "pl"
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}", headers={"Accept-Language": "pt-BR"}):
            session = newest(lab, {first})
            assert session.language == "pl"  # the room's, over the browser's
            report(session, address="?lang=es")
            assert session.language == "es"  # the tab's own, over the room's
    with pytest.raises(ValueError, match="no language 'xx'"):
        running_lab(language="xx").__enter__()


def test_a_follower_in_spanish_follows_a_presenter_in_portuguese_and_reads_spanish():
    with running_lab(presenter_token=TOKEN) as (lab, follower, _ws):
        report(follower, address="?lang=es")
        with ViserWsClient(f"ws://127.0.0.1:{lab.port}", headers={"Accept-Language": "pt-BR"}):
            presenter = newest(lab, {follower})
            presenter.panel.classroom.token.value = TOKEN
            wait_until(lambda: presenter.role.presenting and follower.role.following)
            assert presenter.language == "pt"
            presenter.dispatch(GoTo("wrist_singular"))
            presenter.settle()
            wait_until(lambda: follower.state.configuration == "wrist_singular")
            follower.settle()
            assert status_words(presenter) == "configuração singular: punho"
            assert status_words(follower) == "configuración singular: muñeca"
            assert follower.language == "es"
            # the 3-D words too: the follower draws its own scene from the presenter's state
            labels = [lab for lab in follower.scene.overlays.lost_labels if lab.visible]
            assert [lab.text for lab in labels] == ["muñeca:\neje de giro perdido"]  # longer: two lines
            shown = [lab.text for lab in presenter.scene.overlays.lost_labels if lab.visible]
            assert shown == ["punho:\neixo de giro perdido"]
            # the presenter's open tab reaches the follower by its key, shown in the follower's words
            report(presenter, kind="tab", tab="Movimento")
            wait_until(lambda: follower.page.tab == "Motion")


def test_tab_labels_of_every_language_map_back_to_the_english_key():
    from app.tab.page import TAB_KEYS

    for code in ("en", "pt", "es", "pl"):
        for label in TAB_LABELS:
            assert TAB_KEYS[translations(code).gettext(label)] == label


def test_a_robots_configuration_description_is_in_the_tabs_language_else_english():
    """The Puma's named configurations come with their description in the tab's language, from the robot
    file's translations (robots/data/puma560.toml); a robot whose file has only English shows English."""
    import robots

    puma = robots.load("puma560")
    wrist = next(c for c in puma.configurations if c.name == "wrist_singular")
    with running_lab(robot="puma560") as (_lab, session, _ws):
        session.dispatch(GoTo("wrist_singular"))
        session.settle()
        assert wrist.description.split(":")[0] in session.panel.status.content  # English first
        report(session, address="?lang=pl&robot=puma560")
        assert session.language == "pl"
        status = session.panel.status.content
        assert wrist.translations["pl"]["description"].split(":")[0] in status
        assert "zgięciem nadgarstka q5 = 0" in status and "efektor traci" in status
        assert wrist.description.split(":")[0] not in status
        # the View tab's list of named configurations: every description in Polish
        listing = session.panel.about.content
        for c in puma.configurations:
            assert fmt.escape(c.translations["pl"]["description"]) in listing, c.name
            assert fmt.escape(c.description) not in listing, c.name
        report(session, address="?lang=es&robot=puma560")
        assert "la flexión de muñeca q5 = 0" in session.panel.status.content
        assert "La pose nominal de Corke" in session.panel.about.content
        # the Motion tab's note on the preset: the robot file's Spanish
        preset = robots.motions("puma560")[0]
        assert fmt.escape(preset.translations["es"]["description"]) in session.panel.motion.about.content


def test_a_robot_file_without_translations_shows_english_in_every_language():
    import dataclasses

    import robots
    from app.core.i18n import translations as tr_of
    from app.core.robot_texts import configuration_description, robot_description, robot_title

    puma = robots.load("puma560")
    bare = dataclasses.replace(
        puma,
        translations={},
        configurations=tuple(dataclasses.replace(c, translations={}) for c in puma.configurations),
    )
    for code in ("pt", "es", "pl"):
        tr = tr_of(code)
        assert robot_title(bare, tr) == puma.title and robot_description(bare, tr) == puma.description
        assert [configuration_description(c, tr) for c in bare.configurations] == [
            c.description for c in puma.configurations
        ]
        assert robot_description(puma, tr) == puma.translations[code]["description"] != puma.description


def test_the_build_tab_takes_a_decimal_comma_in_portuguese_and_refuses_a_thousands_point_in_words():
    with running_lab() as (_lab, session, _ws):
        report(session, address="?lang=pt")
        editor = session.panel.editor
        editor.start.value = "tabela vazia (uma junta)"
        session.settle()
        assert editor.kind.value == "rotacional"
        editor.a.value = "0,3"  # in Portuguese simply 0.3 (English refuses it: "use a point")
        session.settle()
        assert editor.error == "" and session.state.robot.dh[0].a == pytest.approx(0.3)
        assert "0,3" in editor.summary.content and "1 junta, DH padrão" in editor.summary.content
        good = session.state.robot
        editor.a.value = "1.234"  # one thousand two hundred and thirty-four, or 1.234? refused
        session.settle()
        assert session.state.robot is good
        assert editor.error == (
            "Linha 1, a [m]: “1.234”: escreva as casas decimais depois da vírgula (1,234), sem separar os milhares"
        )
        editor.a.value = "0,5"
        editor.kind.value = "prismática"
        session.settle()
        assert session.state.robot.dh[0].joint == "prismatic" and session.state.robot.dh[0].a == 0.5


def test_record_lang_pl_writes_the_demos_words_in_polish(tmp_path):
    from test_record import RECORDING, _last, read_viser

    from app.cli.main import main

    out = tmp_path / "demo"
    assert main(["record", "ur5", "-o", str(out), "--seconds", "1", "--fps", "10", "--lang", "pl"]) == 0
    f = read_viser((out / RECORDING).read_bytes())
    assert _last(f["messages"], "/demo/readout", "text").startswith("konfiguracja osobliwa")
    title = _last(f["messages"], "/demo/title", "text")
    assert "— home →" in title and "osobliwość" in title  # "UR5 — home → … (osobliwość: …)"
    lost = [_last(f["messages"], f"/demo/lab/jacobian/lost_label_{i}", "text") for i in range(3)]
    assert any(t and ("utracon" in t) for t in lost), lost
    assert main(["record", "ur5", "-o", str(out), "--lang", "fr"]) == 2


def test_the_robot_menu_lists_the_library_robots_by_their_title_in_the_tabs_language():
    """The Robot dropdown names each library robot by its file's title in the tab's language (the TRR is
    'Robot TRR (przykład z wykładu) (trr)' in Polish), and a picked translated label loads that robot."""
    import robots

    with running_lab(robot="puma560") as (_lab, session, _ws):
        english = set(session.panel.robot.options)
        assert "TRR robot (course example) (trr)" in english
        report(session, address="?lang=pl&robot=puma560")
        options = session.panel.robot.options
        for name in robots.names():
            title = robots.info(name)["translations"]["pl"]["title"]
            assert f"{title} ({name})" in options, name
        assert "Robot TRR (przykład z wykładu) (trr)" in options
        assert "TRR robot (course example) (trr)" not in options
        session.panel.robot.value = "Robot TRR (przykład z wykładu) (trr)"
        wait_until(lambda: session.state.robot_name == "trr")


def test_the_motion_presets_are_named_in_the_tabs_language_and_a_translated_name_plays_the_preset():
    """The Puma's preset menu in Polish lists 'ruch po prostej do osobliwości nadgarstka' (the robot
    file's translations.pl.name), and picking it applies the preset whose name is the English one."""
    import robots

    preset = robots.motions("puma560")[0]
    polish = preset.translations["pl"]["name"]
    with running_lab(robot="puma560") as (_lab, session, _ws):
        report(session, address="?lang=pl&robot=puma560")
        menu = session.panel.motion.preset
        assert polish in menu.options and preset.name not in menu.options
        assert menu.value == polish  # the robot's first preset is shown first, by its Polish name
        from app.views.panel.motion import OWN_TWIST

        session.panel.motion.preset.value = translations("pl").gettext(OWN_TWIST)
        wait_until(lambda: session.panel.motion.preset.value != polish)
        session.panel.motion.preset.value = polish
        wait_until(lambda: session.state.motion.preset == preset.name)
