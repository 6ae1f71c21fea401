"""Writers of a :class:`.handout.Handout`: one self-contained HTML page (MathML, no script, no
network) or one complete LaTeX document. Every name from the robot file is escaped here
(:func:`.escape.xml_text`, :func:`.escape.latex_text`)."""

from __future__ import annotations

from ...text import translated
from ..steps.layout import OMITTED
from ..steps.step import DH_COLUMNS, Step, lhs_mathml
from ..typeset.escape import NOTE_CHARS, xml_text
from ..typeset.printing import Notation
from ..typeset.render import MATH_STYLE
from .content import INTRO, TITLES, Handout
from .parts import (
    ASSEMBLED,
    JOINT_COLUMN,
    NO_DH_TABLE,
    NOTATION,
    NOTE,
    RESULT_TITLE,
    SINGULAR_SETS,
    WHERE,
    contents,
    contents_sentence,
    dh_cell,
    example_lines,
    example_math,
    handout_notation,
    handout_title,
    intro,
    jacobian_sentence,
    singular_texts,
)
from .words import Words, mathml_decimals, say

__all__ = ["render_html", "HTML_MATH_PX"]

HTML_MATH_PX = 780
"""Width [px] the HTML handout gives a formula (the page's text column is 60rem)."""

CSS = f"""
body {{ margin: 0; background: #fff; color: #1d1d1d; font: 17px/1.55 Georgia, 'DejaVu Serif', serif; }}
main {{ max-width: 60rem; margin: 0 auto; padding: 1.5rem 2rem 4rem; box-sizing: border-box; }}
h1 {{ font-size: 1.7rem; line-height: 1.25; margin-bottom: 0.3rem; }}
h2 {{ font-size: 1.3rem; border-bottom: 1px solid #bbb; margin-top: 2.4rem; }}
h3 {{ font-size: 1.05rem; margin: 1.6rem 0 0.4rem; }}
p {{ margin: 0.5rem 0; overflow-wrap: anywhere; }}
.sub {{ color: #555; }}
.cap {{ margin: 1.1rem 0 0.1rem; }}
.note {{ color: #555; font-size: 0.92rem; }}
math {{ {MATH_STYLE}; }}
math[display="block"] {{ margin: 0.35rem 0 0.35rem 1.5rem; }}
table.dh {{ border-collapse: collapse; margin: 0.6rem 0 0.6rem 1.5rem; }}
table.dh th, table.dh td {{ padding: 0.2rem 0.9rem; border-bottom: 1px solid #ddd; text-align: center; }}
table.dh td.name {{ text-align: left; max-width: 16rem; overflow-wrap: anywhere; }}
"""


def _mblock(inner: str) -> str:
    return f'<math display="block"><mrow>{inner}</mrow></math>'


def render_html(h: Handout) -> str:
    """The handout as one HTML page with MathML."""
    N, w = handout_notation(h), h.words
    sections = dict(contents(h))
    out = [f"<h1>{xml_text(handout_title(h))}</h1>"]
    out += [f'<p class="sub">{xml_text(t, NOTE_CHARS)}</p>' for t in intro(h)]
    # The result first (what a reader looks for), the derivation after it.
    out.append(f"<h2>{xml_text(say(w, RESULT_TITLE))}</h2>")
    for s in h.result:
        out += _html_steps([s], N, w)
        if s.key == "J":
            out.append(f"<p>{xml_text(jacobian_sentence(h))}</p>")
        if s.key == "detJ" and s.singular:
            out.append(f"<p>{xml_text(say(w, SINGULAR_SETS))}</p>")
            out += [mathml_decimals(w, _mblock(t)) for t in singular_texts(N, s, False, w)]
    out.append(f'<p class="note">{xml_text(contents_sentence(h), NOTE_CHARS)}</p>')
    out.append(f"<h2>2. {xml_text(sections[2])}</h2>")
    if h.table:
        heads = "".join(f"<th><math>{lhs_mathml(c)}</math></th>" for c in DH_COLUMNS[h.table[0].convention])
        rows = []
        for r in h.table:
            cells = "".join(
                f"<td><math>{mathml_decimals(w, dh_cell(N, e, a, False, w))}</math></td>"
                for e, a in zip(r.cells(), r.is_angle(), strict=True)
            )
            rows.append(f'<tr><td>{r.index}</td>{cells}<td class="name">{xml_text(r.name)}</td></tr>')
        conv = (
            say(
                w,
                "Convention: standard (Aᵢ = Rz(θᵢ) Tz(dᵢ) Tx(aᵢ) Rx(αᵢ)). Lengths in metres, angles in "
                "degrees.",
            )
            if h.table[0].convention == "standard"
            else say(
                w,
                "Convention: modified, Craig's (Aᵢ = Rx(αᵢ₋₁) Tx(aᵢ₋₁) Rz(θᵢ) Tz(dᵢ)). Lengths in metres, "
                "angles in degrees.",
            )
        )
        out.append(f"<p>{xml_text(conv)}</p>")
        joint = xml_text(say(w, JOINT_COLUMN))
        out.append(f'<table class="dh"><tr><th>i</th>{heads}<th>{joint}</th></tr>{"".join(rows)}</table>')
    else:
        out.append(f"<p>{xml_text(say(w, NO_DH_TABLE))}</p>")
    parts = [
        (f"3. {sections[3]}", [s for s in h.transforms if not s.key.startswith("T0_")]),
        (f"4. {sections[4]}: ⁰Tᵢ = A₁ A₂ ⋯ Aᵢ", [s for s in h.transforms if s.key.startswith("T0_")]),
    ]
    for head, steps in parts:
        out.append(f"<h2>{xml_text(head)}</h2>")
        out += _html_steps(steps, N, w)
    number = 5
    for m in h.methods:
        # ᵀ as a superscript T: the bold serif of headings draws the modifier letter like an ˢ.
        title = xml_text(w.gettext(TITLES[m])).replace("ᵀ", "<sup>T</sup>")
        out.append(f"<h2>{number}. {title}</h2><p>{xml_text(w.gettext(INTRO[m]))}</p>")
        out += _html_steps(h.method_steps[m], N, w)
        out.append(f"<p>{xml_text(say(w, ASSEMBLED))}</p>")
        number += 1
    out.append(f"<h2>{number}. {xml_text(sections[number])}</h2>")
    for line in example_lines(h):
        out.append(f"<p>{xml_text(line, NOTE_CHARS)}</p>")
    for cap, formula in example_math(h, False):
        if cap:
            out.append(f'<p class="cap">{xml_text(cap)}</p>')
        if formula:
            out.append(_mblock(formula))
    out.append(f"<h2>{xml_text(say(w, NOTATION))}</h2>")
    items = N.mathml_legend_items(w)
    if items:
        before, _, after = xml_text(say(w, WHERE)).partition("{items}")
        legend = ", ".join(f"<math>{mathml_decimals(w, i)}</math>" for i in items)
        out.append(f"<p>{before}{legend}{after}</p>")
    notes = h.notes + ([OMITTED] if any("<mo>∗</mo>" in x for x in out) else [])
    out += [f'<p class="note">{xml_text(say(w, NOTE, note=n), NOTE_CHARS)}</p>' for n in notes]
    title = xml_text(handout_title(h))
    head = (
        f'<!DOCTYPE html>\n<html lang="{xml_text(w.code)}">\n<head>\n<meta charset="utf-8">\n'
        f'<meta name="viewport" content="width=device-width, initial-scale=1">\n<title>{title}</title>\n'
        f"<style>{CSS}</style>\n</head>\n<body>\n<main>\n"
    )
    return head + "\n".join(out) + "\n</main>\n</body>\n</html>\n"


def _html_steps(steps: list[Step], N: Notation, w: Words) -> list[str]:
    out = []
    for s in steps:
        out.append(f'<p class="cap">{xml_text(translated(s.title, w), 2000)}</p>')
        out.append(mathml_decimals(w, s.mathml(HTML_MATH_PX, N)))
    return out
