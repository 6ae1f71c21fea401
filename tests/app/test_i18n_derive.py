"""The Derive tab in the tab's language (issue 27), server level: the Whitney walk and the DH walk on the
Puma in Portuguese, Spanish and Polish show that language at every step (no word left that only the
English catalog ids use: names, symbols and numbers aside), numbers with a decimal comma, and the 3-D
labels at the Puma's wrist singularity (the lost direction, a step's own labels) in the tab's language."""

from __future__ import annotations

import json
import re

import pytest
from app_helpers import running_lab, scene_node
from i18n_words import english_only, plain, words

from app.core.actions import GoTo, SetWrench
from app.core.commands import ChooseRobot
from app.core.i18n import translations
from app.core.snapshot.derive import METHODS
from app.views.scene.overlays import MAX_LOSSES

LANGUAGES = ("pt", "es", "pl")


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
    if session.page.tab != "Derive":  # the user opens the tab first: its step is drawn only then
        _report(session, kind="tab", tab="Derive")
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
    formula = re.sub(r"fake (step \S+|J|det J)", " ", plain(fake))
    parts = [
        d.method.label,
        str(d.method.value),
        *map(str, d.method.options),
        d.step.label,
        d.buttons.label,
        *map(str, d.buttons.options),
        plain(d.body.content),
        plain(d.table.content),
        formula,
    ]
    return "\n".join(parts)


def _numbers(text: str) -> list[str]:
    return re.findall(r"\d+[.,]\d+", text)


@pytest.mark.parametrize("code", LANGUAGES)
@pytest.mark.parametrize("method", ["whitney", "dh"])
def test_every_step_of_the_walk_speaks_the_tabs_language(code, method):
    english = english_only(code)
    tr = translations(code)
    with running_lab() as (_lab, session, _ws):
        _open(session, code)
        robot = session.state.robot
        names = words(" ".join([robot.name, *(j.name for j in robot.joints)]))
        steps = robot.dof + 1 if method == "dh" else robot.dof  # the DH walk ends with the tool frame's row
        for step in range(steps):
            _walk(session, code, method, step)
            shown = _shown(session)
            left = sorted((words(shown) - names) & english)
            assert not left, f"{method} step {step + 1} in {code}: English left {left}\n{shown}"
            if step == robot.dof:
                head = tr.gettext("Step {i} of {n}: the tool frame, row {i} of the DH table")
                head = head.format(i=step + 1, n=steps)
            else:
                head = tr.gettext("Step {i} of {n}: joint {i} ({name})").format(
                    i=step + 1, n=steps, name=robot.joints[step].name
                )
            assert head in shown and head != f"Step {step + 1} of {steps}"
            numbers = _numbers(shown)
            assert numbers and all("," in x for x in numbers), numbers  # the DH table's and the step's
            body = plain(session.panel.derive.body.content)
            if method == "whitney":
                assert tr.gettext("equals column {i} of J(q)").format(i=step + 1) in body
                # a vector's components parted by semicolons where the decimal mark is a comma
                assert re.search(r"\(−?\d+,\d{3}; −?\d+,\d{3}; −?\d+,\d{3}\)", body), body
            elif step < robot.dof:
                assert tr.gettext("{A} = {T} at q").split("{")[-1].split("}")[-1] in body
            else:
                assert tr.gettext("{T} = the tool transform (constant)").split("}")[-1] in body


@pytest.mark.parametrize("code", LANGUAGES)
def test_the_3d_labels_at_the_pumas_wrist_singularity_are_in_the_tabs_language(code):
    tr = translations(code)
    with running_lab() as (_lab, session, _ws):
        _open(session, code)
        session.dispatch(GoTo("wrist_singular"))
        session.settle()
        labels = [scene_node(session, f"/lab/jacobian/lost_label_{i}") for i in range(MAX_LOSSES)]
        shown = [" ".join(label.text.split()) for label in labels if label.visible]  # a long one wraps
        wrist = tr.gettext("wrist: lost rotation axis")
        assert wrist != "wrist: lost rotation axis" and wrist in shown, shown
        # the force walk's step at the wrist: its label names the torque about the axis in the language
        session.dispatch(SetWrench(2, 10.0))
        _walk(session, code, "force", 4)
        texts = {scene_node(session, f"/lab/derive/label_{k}").text for k in range(6)}
        about = tr.gettext("{tau} about {z}").format(tau="τ₅", z="z₄")
        assert about in texts and "τ₅ about z₄" not in texts, texts
        english = english_only(code)
        left = sorted(words(" ".join(shown + sorted(texts))) & english)
        assert not left, left


@pytest.mark.slow
@pytest.mark.parametrize("code", LANGUAGES)
@pytest.mark.parametrize("method", ["whitney", "differentiation", "propagation", "force"])
def test_the_symbolic_steps_of_a_walk_are_captioned_in_the_tabs_language(method, code):
    """What the symbolic worker sends for a walk (planar 2R, in process): every joint's 'In symbols'
    captions (Whitney's z, p, pₙ − p and column; ∂p/∂q and [ω]×; ω and v of each link; f, n and τ of
    each joint; ⁰Tᵢ) in the tab's language, escaped, no English left."""
    from app.services.symbolic_requests import _steps_mathml
    from app.views.methods import METHODS as VIEWS
    from app.views.panel.derive_html import formulas_html
    from robots import load

    steps = _steps_mathml(load("planar2"), method, 120.0)
    ours = [s for s in steps if s[0] is not None and s[1].startswith(VIEWS[method].symbols)]
    assert ours and all(s[4][0] for s in ours), [s[1] for s in ours if not s[4][0]]  # each has its id
    tr = translations(code)
    english = english_only(code)
    for joint in range(2):
        html = formulas_html(steps, "", method, joint, last=False, tr=tr)
        captions = " ".join(re.findall(r'<div class="jl-note">(.*?)</div>', html))
        assert captions
        left = sorted(words(plain(captions)) & english)
        assert not left, f"{method}, joint {joint + 1} in {code}: English left {left}: {captions}"
    whole = next(s for s in steps if s[1] == "J")  # the assembled J under the last joint's steps
    assert whole[4][0] and tr.gettext(whole[4][0]) != whole[4][0]
    assert plain(formulas_html(steps, "", method, 1, last=True, tr=tr)).count(tr.gettext(whole[4][0])) == 1
