"""The four places where the course notes are wrong, said in the app where each item is shown.

Each note names the course file, its slide or section and lines (as the README's "Where the
course is wrong" does), what the course prints and what the app does instead.
``tests/test_course_errata.py`` checks each with numbers.
"""

from __future__ import annotations

from dataclasses import dataclass

from ...core.i18n import N_, Translator, translations
from .. import fmt

__all__ = ["Erratum", "ERRATA", "erratum_html"]


@dataclass(frozen=True)
class Erratum:
    """One course error.

    Attributes:
        where: The course note, its slide or section and lines, ``{title}`` standing for the slide's
            title (the course's own words, quoted in its language whatever the tab's).
        title: The slide's or section's title.
        printed: What the course prints (quoted or paraphrased).
        app: What the app does instead, and why.
    """

    where: str
    title: str
    printed: str
    app: str


ERRATA: dict[str, Erratum] = {
    "M": Erratum(
        N_("course 004, slide 12 “{title}”, lines 355–370"),
        "Związek pomiędzy jakobianem a macierzą Jacobiego",
        N_(
            "M(y) = [m₁ m₂ m₃] with unit rotation axes mᵢ (so ω = M ẏ), but the matrix printed for "
            "Euler angles (−cos φ ctg θ, …, cos φ / sin θ, …) has no unit columns: it is M⁻¹"
        ),
        N_("M(φ) below is the text's M (unit columns, ω = M(φ) φ̇), and J_A = diag(I, M⁻¹) J"),
    ),
    "gradient": Erratum(
        N_("course 004, slide 17 “{title}”, lines 484–495"),
        "Metoda jakobianowa – inwers uogólniony",
        N_("ω = grad_q(−√det(AAᵀ)) in q̇ = A⁺ẏ + (I − A⁺A) ω: that step lowers w, towards a singularity"),
        N_("the climb moves up the gradient, q̇ = (I − J⁺J) ∇w, so w rises"),
    ),
    "forces": Erratum(
        N_("course 002, slide “{title}”, line 237"),
        "Matriz Jacobiana Inversa – Singularidades",
        N_("finite forces at the tool may need infinite joint torques"),
        N_(
            "τ = Jᵀ F is finite for every finite F; it is the other way round: near a singularity small "
            "torques balance large tool forces, and a force along the lost direction needs no torque "
            "(004, slide 23, lines 677–678, says it the right way)"
        ),
    ),
    "jdot": Erratum(
        N_("course 000, §7 “{title}”, lines 112–138"),
        "Mapeamento de Acelerações",
        N_("J̇ᵢ = [⁰Rᵢ₋₁(ẑ × (ẑ × ⁱ⁻¹Pₙ)) q̇ᵢ; 0] per joint, derived for joint i moving alone"),
        N_(
            "J̇ q̇ here counts every moving joint (zᵢ₋₁ turns and pₙ − pᵢ₋₁ changes with the joints "
            "beyond i), checked against finite differences of J"
        ),
    ),
}
"""Key → erratum: "M" (J(q) tab, analytic J), "gradient" (Motion, climb), "forces" (τ = Jᵀ F tab),
"jdot" (v = J q̇ tab, J̇ q̇)."""


def erratum_html(key: str, tr: Translator | None = None) -> str:
    """One erratum as a small boxed note: "The course is wrong here (where): printed. The app: app.",
    in ``tr``'s language (the English of :data:`ERRATA` is the catalogs' msgid)."""
    _ = (tr or translations()).gettext
    e = ERRATA[key]
    text = _("<b>The course is wrong here</b> ({where}): {printed}. <b>The app</b>: {app}.").format(
        where=fmt.escape(_(e.where).format(title=e.title)),
        printed=fmt.escape(_(e.printed)),
        app=fmt.escape(_(e.app)),
    )
    return f'<div class="jl-erratum">{text}</div>'
