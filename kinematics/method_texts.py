"""The titles and introductions of the course's derivations of J (a handout's sections), marked for
the app's catalogs (:func:`kinematics.text.N_`; the app and the handouts translate them where they show
them). :data:`kinematics.steps.METHODS` holds them with each method."""

from __future__ import annotations

from .text import N_

__all__ = ["TITLES", "INTROS"]

TITLES = {
    "whitney": N_("Whitney's method: the columns of J"),
    "differentiation": N_("Differentiating the forward kinematics"),
    "propagation": N_("Velocity propagation, link by link"),
    "force": N_("Force propagation: τ = Jᵀ F"),
}
"""Each method's heading, by key."""

INTROS = {
    "whitney": N_(
        "Whitney's method (course 000, section 4): column i of J is [zᵢ₋₁ × (pₙ − pᵢ₋₁); zᵢ₋₁] for "
        "a revolute joint and [zᵢ₋₁; 0] for a prismatic one, where zᵢ₋₁ is the axis of joint i and "
        "pᵢ₋₁ a point on it (the third column and the origin of ⁰Tᵢ₋₁), and pₙ the tool origin."
    ),
    "differentiation": N_(
        "Differentiating the forward kinematics (course 001, method 1; course 004): the v part of "
        "column i is ∂p/∂qᵢ of the tool position p; the ω part comes from S = (∂R/∂qᵢ) Rᵀ, a skew "
        "matrix [ω]×, as ω = (S₃₂, S₁₃, S₂₁)."
    ),
    "propagation": N_(
        "Velocity propagation (course 000, section 3; course 001, method 2; Craig's outward "
        "iteration): from the base outward, each link's angular velocity ω and the velocity v of "
        "its origin, in the link's own axes: ω' = Rᵀ(ω + θ̇ ẑ), v' = Rᵀ(v + ω × p) (plus ḋ ẑ for a "
        "prismatic joint). J holds the coefficients of the joint rates q̇ in the tool's [v; ω]."
    ),
    "force": N_(
        "Force propagation (course 001, method 3; course 000, section 6; Craig's inward "
        "iteration): a wrench [f; n] on the tool, in the tool axes, carried inward link by link (f "
        "= R f', n = R n' + p × f); joint i's torque is the component along its axis. Since τ = Jᵀ "
        "F, the coefficients of the wrench are Jᵀ: the transpose view of the same J."
    ),
}
"""The paragraph that opens each method's section, by key."""
