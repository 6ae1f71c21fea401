"""Course 002's third way to J⁻¹ in symbols: the closed-form inverse kinematics q = g(x) written with
SymPy and differentiated, J⁻¹ = ∂g/∂x (the numeric hand-differentiated version is
:func:`kinematics.motion.closed_form.closed_form_inverse_jacobian`; the tests hold one against the
other).

For a robot with a closed form (:func:`kinematics.motion.closed_form.closed_form`: a planar two-link
pair, optionally after a slide along the base z), in the pair's plane (x′, y′):
cos qₖ₊₁ = (x′² + y′² − a₁² − a₂²) / (2 a₁ a₂), qₖ₊₁ = ± acos(·),
qₖ = atan2(y′, x′) − atan2(a₂ sin qₖ₊₁, a₁ + a₂ cos qₖ₊₁), and q₁ = z − offset for the slide.
"""

from __future__ import annotations

import sympy as sp

from ..errors import ConfigurationError
from ..model import Robot
from ..motion.closed_form import closed_form

__all__ = ["closed_form_symbols", "TOOL_POINT"]

TOOL_POINT = sp.symbols("x y z", real=True)
"""The tool point's coordinates in base axes, the variables of g."""


def closed_form_symbols(robot: Robot, elbow: int = 1) -> tuple[sp.Matrix, sp.Matrix]:
    """(g(x), ∂g/∂x): the closed-form IK of ``robot`` as SymPy expressions of :data:`TOOL_POINT`
    (the robot's numbers as exact rationals) and its derivative, J⁻¹ over the task rows (x, y[, z]).

    Args:
        robot: A robot with a closed form.
        elbow: The branch, the sign of sin qₖ₊₁ (+1 or −1).

    Raises:
        ConfigurationError: no closed form.
    """
    cf = closed_form(robot)
    if cf is None:
        raise ConfigurationError(f"{robot.name} has no closed-form inverse kinematics here")
    x, y, z = TOOL_POINT
    a1, a2 = sp.nsimplify(cf.a1), sp.nsimplify(cf.a2)
    if cf.slide:
        row = robot.dh[0]  # type: ignore[index]
        th, flip = sp.nsimplify(row.theta, [sp.pi]), sp.nsimplify(cf.flip)
        ux, uy = x - sp.nsimplify(row.a) * sp.cos(th), y - sp.nsimplify(row.a) * sp.sin(th)
        px, py = sp.cos(th) * ux + sp.sin(th) * uy, flip * (-sp.sin(th) * ux + sp.cos(th) * uy)
        variables = [x, y, z]
    else:
        px, py = x, y
        variables = [x, y]
    c2 = (px**2 + py**2 - a1**2 - a2**2) / (2 * a1 * a2)
    q2 = elbow * sp.acos(c2)
    q1 = sp.atan2(py, px) - sp.atan2(a2 * sp.sin(q2), a1 + a2 * sp.cos(q2))
    pair = [q1 - sp.nsimplify(cf.theta1, [sp.pi]), q2 - sp.nsimplify(cf.theta2, [sp.pi])]
    g = sp.Matrix([z - sp.nsimplify(cf.z_offset), *pair] if cf.slide else pair)
    return g, g.jacobian(variables)
