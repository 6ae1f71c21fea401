"""The handout in each course's language (issue 27): `jacobian-lab handout trr --lang pl` (HTML and LaTeX)
speaks the catalog's words and the robot file's translated texts, writes decimal commas in pt, es and pl
(LaTeX: ``0{,}432``, so the comma is not spaced as punctuation in maths), escapes every translated text,
and asks the catalogs only for words the app lists for them."""

from __future__ import annotations

import ast
import html as html_lib
import importlib
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from browser_helpers import ARGS, CHROMIUM, new_page, require_browser
from test_export_latex import display_formulas, katex  # noqa: F401  (katex is a fixture)

import robots
from app.cli.main import main as cli_main
from app.core import handout_words
from app.core.i18n import translations
from kinematics.symbolic.handout import ENGLISH, handout
from kinematics.symbolic.typeset.render import KIND_TEXT
from kinematics.text import N_, translated
from kinematics.text import words as caption_words

HANDOUT = Path(importlib.import_module("kinematics.symbolic.handout").__file__).parent
SHOTS = Path("/work/notes/shots/s27/trobots")
WORDS = {  # a few of each catalog's words, and the course's worked example heading
    "pt": ("O Jacobiano do Robô TRR", "Exemplo resolvido", "A tabela de Denavit–Hartenberg", "junta"),
    "es": (
        "La Matriz Jacobiana del Robot TRR",
        "Ejemplo resuelto",
        "La tabla de Denavit–Hartenberg",
        "articulación",
    ),
    "pl": ("Macierz Jacobiego: Robot TRR", "Przykład obliczeniowy", "Tabela Denavita–Hartenberga", "przegub"),
}


def asked() -> tuple[set[str], set[tuple[str, str]]]:
    """Every msgid the handout's modules ask for with say() / say_n() (a name resolved in its module)."""
    singles: set[str] = set()
    plurals: set[tuple[str, str]] = set()
    for path in sorted(HANDOUT.glob("*.py")):
        module = importlib.import_module(f"kinematics.symbolic.handout.{path.stem}")
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)):
                continue
            if node.func.id not in ("say", "say_n"):
                continue
            values = []
            for arg in node.args[1 : 3 if node.func.id == "say_n" else 2]:
                if isinstance(arg, ast.Constant):
                    values.append(arg.value)
                elif isinstance(arg, ast.Name):
                    values.append(getattr(module, arg.id))
                elif isinstance(arg, ast.Subscript) and ast.unparse(arg.value) == "KIND_TEXT":
                    singles.update(KIND_TEXT.values())
                    continue
                else:
                    raise AssertionError(
                        f"{path.name}:{node.lineno}: say() of an expression the test cannot read"
                    )
            if node.func.id == "say" and values:
                singles.add(values[0])
            elif values:
                plurals.add((values[0], values[1]))
    return singles, plurals


def test_the_app_lists_exactly_the_words_the_handout_asks_for():
    singles, plurals = asked()
    assert len(singles) > 30 and len(plurals) == 3
    assert singles == set(handout_words.MESSAGES)
    assert plurals == set(handout_words.PLURALS)


def numbers_in(text: str) -> list[str]:
    return re.findall(r"\d+(?:\.|,|\{,\})\d+", text)


@pytest.mark.parametrize("code", ["pt", "es", "pl"])
def test_a_handout_in_each_language_html(tmp_path, code):
    out = tmp_path / f"trr_{code}.html"
    assert cli_main(["handout", "trr", "--lang", code, "-o", str(out)]) == 0
    html = out.read_text(encoding="utf-8")
    assert f'<html lang="{code}">' in html
    for words in WORDS[code]:
        assert words in html, words
    robot = robots.load("trr")
    assert robot.translations[code]["description"][:40] in html  # the robot file's own translation
    assert robot.description[:40] not in html
    example = html[html.index(WORDS[code][1]) :]
    cells = re.findall(r"<mn>([^<]*)</mn>", example)
    decimals = [c for c in cells if re.search(r"\d[.,]\d", c)]
    assert len(decimals) > 10 and all("," in c and "." not in c for c in decimals), decimals[:5]
    for math in re.findall(r"<math.*?</math>", html, flags=re.S):
        ET.fromstring(math)


@pytest.mark.parametrize("code", ["pt", "es", "pl"])
def test_a_handout_in_each_language_latex_typesets_in_katex(katex, tmp_path, code):  # noqa: F811
    out = tmp_path / f"trr_{code}.tex"
    assert cli_main(["handout", "trr", "--lang", code, "-o", str(out)]) == 0
    tex = out.read_text(encoding="utf-8")
    assert tex.startswith("\\documentclass") and tex.rstrip().endswith("\\end{document}")
    assert WORDS[code][1] in tex and WORDS[code][0] in tex
    formulas = display_formulas(tex)
    example = [f for f in formulas if "J(q) =" in f or "\\det J(q)" in f or "J^{-1}" in f]
    assert example, "the worked example's formulas"
    decimals = [n for f in example for n in numbers_in(f)]
    assert len(decimals) > 10 and all("{,}" in n for n in decimals), decimals[:5]  # 0{,}432: no space
    errors = [(f[:100], e) for f, e in zip(formulas, katex(formulas), strict=True) if e is not None]
    assert errors == []
    SHOTS.mkdir(parents=True, exist_ok=True)


def test_english_is_unchanged_and_the_app_english_is_the_handouts():
    robot = robots.load("planar2")
    for fmt in ("html", "tex"):
        assert handout(robot, fmt, "whitney") == handout(robot, fmt, "whitney", words=translations("en"))
    html = handout(robot, "html", "whitney", words=ENGLISH)
    assert "Worked example" in html and '<html lang="en">' in html and "0.000" in html


class Hostile:
    """A language whose every word is markup and LaTeX: the writers must escape what a catalog says."""

    code = "xx"
    EVIL = '</p><script>alert(1)</script> \\input{/etc/passwd} % $ & # _ ^ { } ~ "'

    def gettext(self, message: str) -> str:  # the steps' captions, the methods' titles, the legend
        return message + " " + self.EVIL

    def pgettext(self, context: str, message: str) -> str:
        return message + " " + self.EVIL

    def npgettext(self, context: str, singular: str, plural: str, n: int) -> str:
        return (singular if n == 1 else plural) + " " + self.EVIL

    def decimal(self, text: str) -> str:
        return text.replace(".", ",")


def test_translated_captions_are_escaped_in_html_and_latex(katex):  # noqa: F811
    robot = robots.load("planar2")
    html = handout(robot, "html", "whitney", words=Hostile())
    assert "<script" not in html and "&lt;script&gt;" in html
    for math in re.findall(r"<math.*?</math>", html, flags=re.S):
        ET.fromstring(math)
    assert html.count("&lt;script&gt;") > len(re.findall('<p class="cap">', html))  # every caption too
    tex = handout(robot, "tex", "whitney", words=Hostile())
    assert "\\input{" not in tex and "\\textbackslash{}input\\{/etc/passwd\\}" in tex
    assert "\\%" in tex and "\\$" in tex and "\\&" in tex
    formulas = display_formulas(tex)
    assert [e for e in katex(formulas) if e is not None] == []


def test_the_cli_refuses_a_language_it_does_not_have(capsys):
    assert cli_main(["handout", "trr", "--lang", "fr", "--format", "html"]) == 2
    assert "invalid choice: 'fr'" in capsys.readouterr().err


@pytest.mark.slow
@pytest.mark.browser
def test_the_polish_and_portuguese_handouts_fit_1280_px_in_chromium(tmp_path):
    sync_playwright = require_browser()
    pages = []
    for code in ("pl", "pt"):
        out = tmp_path / f"puma_{code}.html"
        assert cli_main(["handout", "puma560", "--method", "whitney", "--lang", code, "-o", str(out)]) == 0
        pages.append(out)
    SHOTS.mkdir(parents=True, exist_ok=True)
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=ARGS)
        try:
            for width, height in ((1280, 900), (390, 844)):
                page = new_page(browser, {"width": width, "height": height})
                for path in pages:
                    page.goto(path.as_uri())
                    if width == 1280:
                        assert page.evaluate("document.documentElement.scrollWidth") <= 1280, path.name
                    # the text (headings, captions, paragraphs) wraps within the page at either width
                    too_wide = page.evaluate(
                        f"[...document.querySelectorAll('main h1, main h2, main p:not(:has(math))')]"
                        f".filter(e => e.getBoundingClientRect().right > {width} + 0.5).length"
                    )
                    assert too_wide == 0, (path.name, width)
                    assert page.evaluate("document.querySelectorAll('math').length") > 50
                    shown = page.evaluate(
                        "getComputedStyle(document.querySelector('math[display=block]')).display"
                    )
                    assert shown == "block math"
                    page.screenshot(path=str(SHOTS / f"handout_{path.stem}_{width}.png"))
                page.close()
        finally:
            browser.close()


def test_every_number_of_the_derivation_has_the_decimal_comma():
    """The Puma's DH lengths (0.4318 m) in its symbolic formulas, its DH table and the worked example:
    every number of every formula is written with a comma in Polish (LaTeX: braced), none with a point."""
    robot = robots.load("puma560")
    pl = translations("pl")
    html = handout(robot, "html", "whitney", words=pl)
    cells = re.findall(r"<mn>([^<]*)</mn>", html)
    assert sum("0,4318" in c for c in cells) > 5
    assert [c for c in cells if re.search(r"\d\.\d", c)] == []
    formulas = display_formulas(handout(robot, "tex", "whitney", words=pl))
    assert sum("0{,}4318" in f for f in formulas) > 5
    assert [f[:80] for f in formulas if re.search(r"\d\.\d", f)] == []
    english = handout(robot, "html", "whitney")
    assert "<mn>0.4318</mn>" in english and "0,4318" not in english


# --------------------------------------------------------------- no English left in the derivation
CATALOG = Path(importlib.import_module("app").__file__).parent / "locale" / "messages.pot"


def english_runs() -> set[str]:
    """Every run of three or more English words (letters only) of every message of the catalogs: what
    a handout in another language must not show (placeholders, symbols and numbers split the runs)."""
    from babel.messages.pofile import read_po

    with CATALOG.open("rb") as f:
        catalog = read_po(f)
    runs: set[str] = set()
    for message in catalog:
        for text in message.id if isinstance(message.id, tuple) else (message.id,):
            runs.update(re.findall(r"[A-Za-z]+(?: [A-Za-z]+){2,}", re.sub(r"\{\w+\}", "\0", text)))
    return runs - {""}


def prose(document: str, fmt: str) -> str:
    """A handout's text without its maths, markup or LaTeX commands, one space between words."""
    if fmt == "html":
        text = re.sub(r"<(math|style|title)\b.*?</\1>", " ", document, flags=re.S)
        text = html_lib.unescape(re.sub(r"<[^>]+>", " ", text))
    else:
        text = document[document.index("\\maketitle") :]
        text = re.sub(r"\\\[.*?\\\]", " ", text, flags=re.S)
        text = re.sub(r"\\(textsubscript|textsuperscript|ensuremath)\{[^{}]*\}", " ", text)
        text = re.sub(r"^%.*$", " ", text, flags=re.M)
        text = re.sub(r"\\[A-Za-z]+\*?|[{}]", " ", text)
    return " ".join(text.split())


@pytest.mark.slow
@pytest.mark.parametrize("name", ["trr", "puma560"])
def test_no_english_message_is_left_in_a_translated_handout(name):
    """The derivation's captions (the steps', J's and det J's), the methods' titles and introductions
    and the legend in the handout's language: no run of English words of any catalog message is left in
    its text (maths aside; the robot file's source, a bibliographic reference, may stay English)."""
    robot = robots.load(name)
    runs = english_runs()
    assert "the DH link transform of joint" in runs and "Whitney" not in runs  # what is looked for
    english = {fmt: prose(handout(robot, fmt, "all"), fmt) for fmt in ("html", "tex")}
    assert "the DH link transform of joint" in english["html"] and "Whitney's method" in english["tex"]
    left = {}
    for code in ("pt", "es", "pl"):
        for fmt in ("html", "tex"):
            text = prose(handout(robot, fmt, "all", words=translations(code)), fmt)
            text = text.replace(" ".join(robot.source.split()), " ")
            found = sorted(r for r in runs if re.search(rf"\b{re.escape(r)}\b", text))
            if found:
                left[code, fmt] = found
    assert left == {}


class Comma:
    """A language that marks what it translates and writes a decimal comma."""

    def gettext(self, message: str) -> str:
        return "«" + message + "»"

    def decimal(self, text: str) -> str:
        return text.replace(".", ",")


def test_a_caption_is_translated_with_its_numbers_in_the_language():
    caption = caption_words(
        N_("{z}: the axis of joint {joint}, in the base axes"), z="a₂ = 0.4318 {x}", joint=2
    )
    assert caption == "a₂ = 0.4318 {x}: the axis of joint 2, in the base axes"
    assert translated(caption, Comma()) == "«a₂ = 0,4318 {x}: the axis of joint 2, in the base axes»"
    assert translated("Whitney's method: the columns of J", Comma()) == "«Whitney's method: the columns of J»"
