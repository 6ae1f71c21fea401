"""Exceptions raised by Jacobian Lab.

Every error a user can provoke (a bad DH row, a URDF that is not a serial
chain, an unknown robot name, a configuration of the wrong length) raises a
subclass of :class:`JacobianLabError` whose message names what is wrong and
what was expected. They subclass :class:`ValueError` so generic callers can
catch them without importing this module.
"""

from __future__ import annotations

__all__ = [
    "JacobianLabError",
    "RobotDefinitionError",
    "UnknownRobotError",
    "UrdfError",
    "ConfigurationError",
    "OptionError",
    "ArrayError",
    "RepresentationSingularityError",
]


class JacobianLabError(ValueError):
    """Base class of every error Jacobian Lab raises on bad input."""


class RobotDefinitionError(JacobianLabError):
    """A robot definition (DH table, robot file, base/tool transform) is invalid."""


class UnknownRobotError(JacobianLabError):
    """A robot name is not in the library; the message lists the available ones."""


class UrdfError(RobotDefinitionError):
    """A URDF cannot be turned into a serial chain (unknown link, not a tree, ...)."""


class ConfigurationError(JacobianLabError):
    """A joint configuration (or joint rates) has the wrong shape, is not numeric, or holds a value
    that is not finite or beyond the range the model accepts."""


class OptionError(JacobianLabError):
    """An option argument (a frame, a part or rows of J, an Euler convention, a damping or a
    tolerance) is not one of its allowed values; the message lists them."""


class ArrayError(JacobianLabError):
    """An array argument other than ``q`` (a Jacobian ``J``, a task velocity ``v``) has the wrong
    shape or holds non-finite values; the message names the argument and the expected shape."""


class RepresentationSingularityError(JacobianLabError):
    """The Euler-angle representation is singular at this orientation.

    The analytic Jacobian maps Euler-angle rates through a matrix that loses
    rank there (e.g. pitch = ±90° for ZYX roll-pitch-yaw, or the middle angle
    = 0 or π for ZYZ); no finite Euler-angle rate represents every angular
    velocity.
    """
