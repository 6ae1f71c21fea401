"""Jacobian Lab's browser app: a viser server where every tab explores its own robot and its Jacobian.

Start it with ``jacobian-lab serve`` or :func:`app.server.serve`. The app only
draws and wires the GUI: every quantity comes from :mod:`kinematics`
(:mod:`app.core.snapshot` is the one place that calls it), every client has its
own :class:`app.tab.session.ClientSession`.
"""

from __future__ import annotations

__all__ = ["serve"]


def serve(*args, **kwargs):
    """Start the app (see :func:`app.server.serve`)."""
    from .server import serve as _serve

    return _serve(*args, **kwargs)
