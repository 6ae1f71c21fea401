"""`jacobian-lab record --lang es` (issue 27): the recorded demo's labels speak the course's language: the
robot file's translated title, the status in the panel's words, κ and the joint rates with decimal
commas; the folder's index.html says it in that language too."""

from __future__ import annotations

import re

from test_record import _last, read_viser

import robots
from app.cli.main import main
from app.core.i18n import translations
from app.core.snapshot import compute
from app.core.words import status_words
from app.demo.rates import rates_readout
from app.demo.record import plan, readout, record


def test_a_recorded_demo_in_spanish_has_spanish_labels_and_decimal_commas():
    robot, es = robots.load("trr"), translations("es")
    preset = robots.motions("trr")[0]
    rec = record("trr", robot, seconds=1.0, fps=10.0, tr=es)
    assert rec.language == "es"
    assert rec.title == f"Robot TRR (ejemplo de la cátedra) — {preset.name}"
    f = read_viser(rec.data)
    assert _last(f["messages"], "/demo/title", "text") == rec.title
    state = rec.states[-1]
    snap = compute(state)
    text, rates = _last(f["messages"], "/demo/readout", "text").split("\n")
    assert text == readout(snap, state, es) and rates == rates_readout(state, es)
    words = status_words(robot, snap.report.status, tuple(snap.report.kinds), state.configuration, es)
    assert text.startswith(f"{words}   κ = ")
    assert words.startswith(("configuración", "cerca de una singularidad"))  # not "regular" / "near singular"
    kappa = re.search(r"κ = (\S+)", text)[1]
    assert re.fullmatch(r"\d+(,\d+)?|∞", kappa), kappa
    numbers = re.findall(r"-?\d+[.,]\d+", rates)
    assert numbers and all("," in n for n in numbers), rates  # "q2 1,23 °/s": commas, units kept
    assert "°/s" in rates and "m/s" in rates
    english = record("trr", robot, seconds=1.0, fps=10.0)
    assert english.language == "en" and english.title == f"{robot.title} — {preset.name}"
    assert "." in rates_readout(english.states[-1]) and "," not in rates_readout(english.states[-1])


def test_a_path_demo_names_its_singularity_in_polish():
    robot, pl = robots.load("stanford"), translations("pl")
    demo = plan("stanford", robot, frames=10, tr=pl)
    singular = next(c for c in robot.configurations if c.singular)
    assert demo.title == f"Manipulator Stanford (Scheinman) — home → {singular.name} (osobliwość: nadgarstek)"
    assert plan("stanford", robot, frames=10).title.endswith(f"({singular.singular} singularity)")


def test_record_lang_writes_the_folder_in_that_language(tmp_path, capsys):
    out = tmp_path / "demo"
    assert main(["record", "trr", "-o", str(out), "--seconds", "0.5", "--fps", "10", "--lang", "es"]) == 0
    index = (out / "index.html").read_text(encoding="utf-8")
    assert '<html lang="es">' in index
    assert (
        "Robot TRR (ejemplo de la cátedra)" in index and "(una demostración grabada de Jacobian Lab)" in index
    )
    assert "(a recorded Jacobian Lab demo)" not in index
    assert main(["record", "trr", "-o", str(out), "--lang", "xx"]) == 2
    assert "invalid choice: 'xx'" in capsys.readouterr().err
