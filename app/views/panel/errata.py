"""The four places where the course notes are wrong, said in the app where each item is shown.

Each note names the course file, its slide or section and lines (as the README's "Where the
course is wrong" does), what the course prints and what the app does instead.
``tests/test_course_errata.py`` checks each with numbers.
"""

from __future__ import annotations

from dataclasses import dataclass

from .. import fmt

__all__ = ["Erratum", "ERRATA", "erratum_html"]


@dataclass(frozen=True)
class Erratum:
    """One course error.

    Attributes:
        where: The course note, its slide or section and lines.
        printed: What the course prints (quoted or paraphrased).
        app: What the app does instead, and why.
    """

    where: str
    printed: str
    app: str


ERRATA: dict[str, Erratum] = {
    "M": Erratum(
        "course 004, slide 12 “Związek pomiędzy jakobianem a macierzą Jacobiego”, lines 355–370",
        "M(y) = [m₁ m₂ m₃] with unit rotation axes mᵢ (so ω = M ẏ), but the matrix printed for "
        "Euler angles (−cos φ ctg θ, …, cos φ / sin θ, …) has no unit columns: it is M⁻¹",
        "M(φ) below is the text's M (unit columns, ω = M(φ) φ̇), and J_A = diag(I, M⁻¹) J",
    ),
    "gradient": Erratum(
        "course 004, slide 17 “Metoda jakobianowa – inwers uogólniony”, lines 484–495",
        "ω = grad_q(−√det(AAᵀ)) in q̇ = A⁺ẏ + (I − A⁺A) ω: that step lowers w, towards a singularity",
        "the climb moves up the gradient, q̇ = (I − J⁺J) ∇w, so w rises",
    ),
    "forces": Erratum(
        "course 002, slide “Matriz Jacobiana Inversa – Singularidades”, line 237",
        "finite forces at the tool may need infinite joint torques",
        "τ = Jᵀ F is finite for every finite F; it is the other way round: near a singularity small "
        "torques balance large tool forces, and a force along the lost direction needs no torque "
        "(004, slide 23, lines 677–678, says it the right way)",
    ),
    "jdot": Erratum(
        "course 000, §7 “Mapeamento de Acelerações”, lines 112–138",
        "J̇ᵢ = [⁰Rᵢ₋₁(ẑ × (ẑ × ⁱ⁻¹Pₙ)) q̇ᵢ; 0] per joint, derived for joint i moving alone",
        "J̇ q̇ here counts every moving joint (zᵢ₋₁ turns and pₙ − pᵢ₋₁ changes with the joints "
        "beyond i), checked against finite differences of J",
    ),
}
"""Key → erratum: "M" (J(q) tab, analytic J), "gradient" (Motion, climb), "forces" (τ = Jᵀ F tab),
"jdot" (v = J q̇ tab, J̇ q̇)."""


def erratum_html(key: str) -> str:
    """One erratum as a small boxed note: "The course is wrong here (where): printed. The app: app."."""
    e = ERRATA[key]
    return (
        f'<div class="jl-erratum"><b>The course is wrong here</b> ({fmt.escape(e.where)}): '
        f"{fmt.escape(e.printed)}. <b>The app</b>: {fmt.escape(e.app)}.</div>"
    )
