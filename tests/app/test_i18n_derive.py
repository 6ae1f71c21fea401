"""The Derive tab in the tab's language (issue 27), server level: the Whitney walk and the DH walk on the
Puma in Portuguese, Spanish and Polish show that language at every step (no word left that only the
English catalog ids use: names, symbols and numbers aside), numbers with a decimal comma, and the 3-D
labels at the Puma's wrist singularity (the lost direction, a step's own labels) in the tab's language."""

from __future__ import annotations

import json
import re

import pytest
from app_helpers import running_lab, scene_node
from babel.messages.pofile import read_po

from app.core.actions import GoTo, SetWrench
from app.core.commands import ChooseRobot
from app.core.i18n import LOCALE_DIR, language_of, translations
from app.core.snapshot.derive import METHODS
from app.views.scene.overlays import MAX_LOSSES

LANGUAGES = ("pt", "es", "pl")
_WORD = re.compile(r"[^\W\d_]{3,}")


def _words(text: str) -> set[str]:
    return {w.lower() for w in _WORD.findall(text)}


def _plain(html: str) -> str:
    """An HTML fragment's text, its entities read (&lt;origin&gt; → <origin>)."""
    text = re.sub(r"<[^>]*>", " ", html)
    return text.replace("&lt;", "<").replace("&gt;", ">").replace("&amp;", "&").replace("&quot;", '"')


def _english_only(code: str) -> set[str]:
    """Words of the English catalog ids (three letters or more) that no translation of ``code`` uses:
    any of them on a ``code`` screen is English left over ("column", "joint", "equals", "step")."""
    with (LOCALE_DIR / "messages.pot").open("rb") as f:
        ids = [m.id for m in read_po(f) if m.id]
    with (LOCALE_DIR / language_of(code).locale / "LC_MESSAGES" / "messages.po").open("rb") as f:
        strings = [m.string for m in read_po(f, locale=language_of(code).locale) if m.id]
    english = set().union(*(_words(" ".join(i) if isinstance(i, tuple) else i) for i in ids))
    own = set().union(*(_words(" ".join(s) if isinstance(s, tuple) else s) for s in strings))
    return english - own


def _report(session, **fields) -> None:
    fields.setdefault("kind", "load")
    session.panel.report.value = json.dumps(fields)
    session.settle()
    session.settle()


def _open(session, code: str, robot: str = "puma560") -> None:
    _report(session, address=f"?lang={code}")
    assert session.language == code
    session.dispatch(ChooseRobot(robot))
    session.settle()


def _walk(session, code: str, method: str, step: int) -> None:
    derive = session.panel.derive
    derive.method.value = translations(code).gettext(METHODS[method])  # as the user picks it
    session.settle()
    derive.step.value = step + 1
    session.settle()
    assert session.state.options.derive == method and session.state.options.derive_step == step


def _shown(session) -> str:
    """Every word the Derive tab shows: its widgets' labels and choices, the step, the DH table and the
    'In symbols' part (the fake symbolic service's own captions and MathML, "fake step A1", taken out)."""
    d = session.panel.derive
    fake = re.sub(r'<div class="jl-mathml">.*?</div>', " ", d.formula.content)  # the fake's MathML
    formula = re.sub(r"fake (step \S+|J|det J)", " ", _plain(fake))
    parts = [
        d.method.label,
        str(d.method.value),
        *map(str, d.method.options),
        d.step.label,
        d.buttons.label,
        *map(str, d.buttons.options),
        _plain(d.body.content),
        _plain(d.table.content),
        formula,
    ]
    return "\n".join(parts)


def _numbers(text: str) -> list[str]:
    return re.findall(r"\d+[.,]\d+", text)


@pytest.mark.parametrize("code", LANGUAGES)
@pytest.mark.parametrize("method", ["whitney", "dh"])
def test_every_step_of_the_walk_speaks_the_tabs_language(code, method):
    english = _english_only(code)
    tr = translations(code)
    with running_lab() as (_lab, session, _ws):
        _open(session, code)
        robot = session.state.robot
        names = _words(" ".join([robot.name, *(j.name for j in robot.joints)]))
        for step in range(robot.dof):
            _walk(session, code, method, step)
            shown = _shown(session)
            left = sorted((_words(shown) - names) & english)
            assert not left, f"{method} step {step + 1} in {code}: English left {left}\n{shown}"
            head = tr.gettext("Step {i} of {n}: joint {i} ({name})").format(
                i=step + 1, n=robot.dof, name=robot.joints[step].name
            )
            assert head in shown and head != f"Step {step + 1} of {robot.dof}"
            numbers = _numbers(shown)
            assert numbers and all("," in x for x in numbers), numbers  # the DH table's and the step's
            body = _plain(session.panel.derive.body.content)
            if method == "whitney":
                assert tr.gettext("equals column {i} of J(q)").format(i=step + 1) in body
                # a vector's components parted by semicolons where the decimal mark is a comma
                assert re.search(r"\(−?\d+,\d{3}; −?\d+,\d{3}; −?\d+,\d{3}\)", body), body
            else:
                assert tr.gettext("{A} = {T} at q").split("{")[-1].split("}")[-1] in body


@pytest.mark.parametrize("code", LANGUAGES)
def test_the_3d_labels_at_the_pumas_wrist_singularity_are_in_the_tabs_language(code):
    tr = translations(code)
    with running_lab() as (_lab, session, _ws):
        _open(session, code)
        session.dispatch(GoTo("wrist_singular"))
        session.settle()
        labels = [scene_node(session, f"/lab/jacobian/lost_label_{i}") for i in range(MAX_LOSSES)]
        shown = [label.text for label in labels if label.visible]
        wrist = tr.gettext("wrist: lost rotation axis")
        assert wrist != "wrist: lost rotation axis" and wrist in shown, shown
        # the force walk's step at the wrist: its label names the torque about the axis in the language
        session.dispatch(SetWrench(2, 10.0))
        _walk(session, code, "force", 4)
        texts = {scene_node(session, f"/lab/derive/label_{k}").text for k in range(6)}
        about = tr.gettext("{tau} about {z}").format(tau="τ₅", z="z₄")
        assert about in texts and "τ₅ about z₄" not in texts, texts
        english = _english_only(code)
        left = sorted(_words(" ".join(shown + sorted(texts))) & english)
        assert not left, left
