"""What a tab can download of its symbolic J: the button label → the export format and extension.

The formats are those :func:`kinematics.symbolic.typeset.export.export` writes (its ``FORMATS``;
a test holds the two together). The table lives in the pure core rather than beside ``FORMATS``
because importing anything under :mod:`kinematics.symbolic` loads SymPy, which the server process
never does (the symbolic work runs in worker processes): the views that draw the buttons and the
service that runs the export both read it here.
"""

from __future__ import annotations

__all__ = ["EXPORT_FORMATS"]

EXPORT_FORMATS = {"LaTeX": ("latex", "tex"), "Python": ("python", "py"), "JSON": ("json", "json")}
"""Download button label → (:mod:`kinematics.symbolic.typeset.export` format, file extension)."""
