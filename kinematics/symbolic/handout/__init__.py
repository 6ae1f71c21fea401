"""A handout: the derivation of a robot's J as a teacher hands it out, as HTML (MathML) or LaTeX.

:func:`handout` returns the text of a document (no file is written): the robot and its DH
table, each link transform Aᵢ, the products ⁰Tᵢ, the steps of the chosen method(s), the assembled
J, det J factored with its singular sets named, and a worked numeric example. The package is in
layers without a circle: :mod:`.content` (the data, :func:`build_handout`), :mod:`.parts` (pieces
both writers share), the writers :mod:`.html` and :mod:`.tex` (each takes the content), and
:mod:`.document` (:func:`handout`: the content written in the format asked). This module only
re-exports.
"""

from __future__ import annotations

from .content import HANDOUT_FORMATS, HANDOUT_METHODS, Example, Handout, HandoutError, build_handout
from .document import handout
from .html import render_html
from .tex import render_tex
from .words import ENGLISH, Words

__all__ = [
    "HANDOUT_FORMATS",
    "HANDOUT_METHODS",
    "HandoutError",
    "Handout",
    "Example",
    "handout",
    "build_handout",
    "render_html",
    "render_tex",
    "Words",
    "ENGLISH",
]
