"""Symbolic (SymPy) kinematics from the same :class:`~kinematics.Robot` model as the numeric code.

* :func:`fk`, :func:`jacobian`: ``T_base_tool(q)`` and J(q) (rows [v; ω]) as
  ``sympy.Matrix`` in the real symbols ``q1 … qn``, simplified the way a
  person writes them (sums of angles collapsed, common factors pulled out)
  within a time limit, and cached on disk (:func:`derive`).
* The course's four derivations (:mod:`.derivations`) and
  :func:`check_derivations`, which shows they agree exactly and numerically.
* :func:`determinant`: det J (or det(J Jᵀ)) factored, and its singular sets.
* :func:`derivation_steps`: each derivation step by step (:class:`Step`: Aᵢ, ⁰Tᵢ, Whitney's
  vectors, ∂p/∂qᵢ, ωᵢ and vᵢ link by link, fᵢ, nᵢ, τᵢ, J, det J), :func:`dh_rows` the DH table as
  symbols, and :func:`handout`: all of it as an HTML or LaTeX handout.
* :func:`analytic_jacobian`: J_A for ZYX or ZYZ Euler angles, with its
  representation singularity.
* Printing in the course's compact notation (cᵢ, sᵢ, cᵢⱼ, …):
  :class:`Notation`, :func:`jacobian_latex`, :func:`jacobian_mathml`.

Numeric link parameters stay exact (π/2 stays π/2, 0.4318 becomes 2159/5000
and prints as 0.4318); rounded angles of robot files (1.5708, 3.14159) are
snapped to multiples of π/12 and every output says so (:mod:`.snap`);
``symbolic_params=True`` keeps the DH lengths and offsets as symbols (a2, d4, …;
l1, l2, l3 for the course's robots). Every step keeps to one time limit, results
are cached as JSON that cannot run code (:mod:`.cache`), and names from robot
files are escaped for every output (:mod:`.escape`). Nothing here imports viser,
and nothing parses user text into SymPy.
"""

from __future__ import annotations

from .analytic import AnalyticJacobian, analytic_jacobian, euler_rate_matrix
from .core import DEFAULT_TIMEOUT, Derivation, derive, fk, jacobian, joint_symbols
from .derivations import (
    DERIVATIONS,
    Agreement,
    check_derivations,
    jacobian_differentiation,
    jacobian_force_propagation,
    jacobian_velocity_propagation,
    jacobian_whitney,
)
from .handout import handout
from .model import SymbolicError, SymbolicModel, build_model
from .singular import Determinant, SingularSet, det_rows, determinant, singular_sets
from .snap import SNAP_TOL, Snap
from .steps import METHODS, Step, derivation_steps, dh_rows
from .trig import is_zero, normal_form
from .typeset.codegen import numeric_function, python_source
from .typeset.printing import Notation
from .typeset.render import jacobian_latex, jacobian_mathml, latex_parts, mathml_parts

__all__ = [
    "fk",
    "jacobian",
    "derive",
    "Derivation",
    "joint_symbols",
    "DEFAULT_TIMEOUT",
    "jacobian_differentiation",
    "jacobian_whitney",
    "jacobian_velocity_propagation",
    "jacobian_force_propagation",
    "DERIVATIONS",
    "check_derivations",
    "Agreement",
    "determinant",
    "Determinant",
    "singular_sets",
    "SingularSet",
    "det_rows",
    "analytic_jacobian",
    "AnalyticJacobian",
    "euler_rate_matrix",
    "Notation",
    "jacobian_latex",
    "jacobian_mathml",
    "latex_parts",
    "mathml_parts",
    "numeric_function",
    "python_source",
    "build_model",
    "SymbolicModel",
    "SymbolicError",
    "normal_form",
    "is_zero",
    "Snap",
    "SNAP_TOL",
    "derivation_steps",
    "dh_rows",
    "Step",
    "METHODS",
    "handout",
]
