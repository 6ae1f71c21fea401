"""The course's derivation methods as the app shows them: one record each, one module each.

A record (:class:`~.common.MethodView`) holds the method's key, label, title and intro, its
numeric and symbolic steps (by reference to :mod:`kinematics.steps` and
:mod:`kinematics.symbolic.steps.methods`), its step in the Derive tab (HTML) and its scene drawer.
The Derive tab's dropdown, the reducer's choices (:mod:`app.core.options`), the panel
(:mod:`app.views.panel.derive_html`) and the 3-D view (:mod:`app.views.scene.derive`) all read
the same keys. A new method: its numbers in ``kinematics/steps.py``, its symbols in
``kinematics/symbolic/steps/methods.py``, one module here and one entry in :data:`METHODS`.
"""

from __future__ import annotations

from . import dh, differentiation, force, propagation, whitney
from .common import MethodView

__all__ = ["METHODS", "MethodView"]

METHODS: dict[str, MethodView] = {
    v.key: v for v in (dh.VIEW, whitney.VIEW, differentiation.VIEW, propagation.VIEW, force.VIEW)
}
"""Every method the Derive tab walks through, by key."""
