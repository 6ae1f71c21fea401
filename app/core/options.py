"""The option table: every display option of a tab in one row (name, kind, default, range or choices,
label, hint, tab).

:class:`~app.core.state.Options` takes its defaults from here, the reducer its validation (a float
clamped to its range, a choice checked against its choices, a bool refused unless it is one) and the
panel its widgets (:func:`app.views.panel.common.option_widget`: a checkbox, slider or dropdown with
this label and hint). A new option is one row here and one field in ``Options``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

from kinematics.steps import METHODS as STEP_METHODS

from .i18n import N_

__all__ = ["Option", "OPTIONS", "OPTION", "Kind", "Tab", "default", "options_of", "Options", "Frame"]

Kind = Literal["bool", "float", "choice", "joint", "step"]
"""bool: on or off; float: a number clamped to ``lo``…``hi``; choice: one of ``choices``;
joint: a joint index (refused outside 0…n−1); step: a joint index clamped to 0…n−1 (never refused)."""
Tab = Literal["view", "matrix", "forward", "inverse", "motion", "maps", "derive"]


@dataclass(frozen=True)
class Option:
    """One display option.

    Attributes:
        name: The field of :class:`~app.core.state.Options` and of :class:`~app.core.actions.SetOption`.
        kind: See :data:`Kind`.
        default: Its value in a fresh tab (glyphs: before the robot's task chooses, see ``default_options``).
        label: The widget's label.
        hint: The widget's tooltip ("" for none).
        tab: The panel tab that shows its widget.
        lo, hi, step: Range and slider step of a float.
        choices: The values of a choice; ``labels`` what its dropdown shows for each (same order).
        widget: How the panel shows it: "" the widget its kind gives (checkbox, slider, dropdown),
            "button" a button that flips a bool, "own" a widget its tab builds itself.
    """

    name: str
    kind: Kind
    default: Any
    label: str
    hint: str = ""
    tab: Tab = "view"
    lo: float = 0.0
    hi: float = 1.0
    step: float = 0.0
    choices: tuple[str, ...] = ()
    labels: tuple[str, ...] = ()
    widget: Literal["", "button", "own"] = ""

    def label_of(self, value: str) -> str:
        """The dropdown label of choice ``value``."""
        return (self.labels or self.choices)[self.choices.index(value)]

    def value_of(self, label: str) -> str | None:
        """The choice whose dropdown label is ``label`` (``None`` for an unknown label)."""
        shown = self.labels or self.choices
        return self.choices[shown.index(label)] if label in shown else None


def _choice(name: str, pairs: dict[str, str], label: str, hint: str, tab: Tab, default: str) -> Option:
    return Option(
        name, "choice", default, label, hint, tab, choices=tuple(pairs), labels=tuple(pairs.values())
    )


OPTIONS: tuple[Option, ...] = (
    # The View tab's glyph toggles, in the order they are listed there.
    Option(
        "velocity_ellipsoid",
        "bool",
        True,
        N_("Velocity ellipsoid"),
        N_(
            "Translational manipulability ellipsoid at the tool point: "
            "semi-axes σᵢ along the left singular vectors of the base-frame linear rows of J."
        ),
    ),
    Option(
        "rotational_ellipsoid",
        "bool",
        False,
        N_("Rotational ellipsoid"),
        N_("Angular-velocity ellipsoid (ω rows of J)."),
    ),
    Option(
        "force_ellipsoid",
        "bool",
        False,
        N_("Force ellipsoid"),
        N_("Semi-axes 1/σᵢ along the same directions (capped at a singularity)."),
    ),
    Option(
        "columns",
        "bool",
        True,
        N_("Columns Jᵢ (linear part)"),
        N_("Tool-point velocity produced by each joint alone at unit rate."),
    ),
    Option(
        "angular_columns", "bool", False, N_("Columns Jᵢ (angular part)"), N_("Drawn on each joint axis.")
    ),
    Option(
        "frames",
        "bool",
        False,
        N_("Frames 0…n and tool"),
        N_("A triad for every DH / link frame and the tool frame."),
    ),
    Option("labels", "bool", True, N_("Joint labels"), N_("Name each joint axis in the 3-D view.")),
    Option(
        "scale",
        "float",
        1.0,
        N_("Glyph scale"),
        N_("1: a column of 1 m/rad is drawn 0.5 m long"),
        lo=0.1,
        hi=3.0,
        step=0.05,
    ),
    # J(q)
    _choice(
        "jacobian_frame",
        {"base": N_("base"), "tool": N_("tool")},
        N_("Frame of J"),
        N_("Axes in which J is written"),
        "matrix",
        "base",
    ),
    _choice(
        "representation",
        {
            "geometric": N_("geometric J"),
            "zyx": N_("analytic J_A, roll-pitch-yaw (ZYX)"),
            "zyz": N_("analytic J_A, Euler ZYZ"),
        },
        N_("Representation"),
        N_("Geometric J (rows [v; ω]) or the analytic J_A (rows [v; φ̇], φ: Euler angles)"),
        "matrix",
        "geometric",
    ),
    Option(
        "course_letters",
        "bool",
        False,
        N_("Course letters (l₁, a₂, d₄ …)"),
        N_("DH lengths and offsets as letters; det J, its factors, singular sets below J"),
        "matrix",
    ),
    # v = J q̇
    Option(
        "jdot_arrow",
        "bool",
        True,
        N_("Acceleration arrows at the tool (J q̈, J̇ q̇)"),
        N_(
            "The two terms of the tool's acceleration ẍ = J q̈ + J̇ q̇: "
            "from the joint accelerations and from the rates"
        ),
        "forward",
    ),
    # q̇ = J⁺ v
    Option(
        "damping",
        "float",
        0.0,
        N_("damping λ"),
        N_("0: pseudo-inverse J⁺; > 0: damped least squares (bounded rates, less accuracy)"),
        "inverse",
        lo=0.0,
        hi=0.5,
        step=0.005,
    ),
    Option(
        "symbolic_inverse", "bool", False, N_("Symbolic J⁻¹ = adj J / det J"), "", "inverse", widget="button"
    ),
    # Motion
    _choice(
        "twist_frame",
        {"base": N_("base"), "tool": N_("tool")},
        N_("v in axes"),
        N_("tool: v is held in the moving tool's own axes"),
        "motion",
        "base",
    ),
    Option(
        "speed",
        "float",
        1.0,
        N_("Speed"),
        N_("1: real time; 0.1: ten times slower"),
        "motion",
        lo=0.05,
        hi=2.0,
        step=0.05,
    ),
    Option("gizmo", "bool", False, N_("Drag handle at the tool"), "", "motion"),
    _choice(
        "ik_method",
        {"dls": N_("DLS (damped)"), "newton": N_("Newton (J⁻¹, J⁺)")},
        N_("Method"),
        N_("q_{k+1} = q_k + J⁺ (y_d − k(q_k))"),
        "motion",
        "dls",
    ),
    _choice(
        "ik_mode",
        {"position": N_("tool position"), "pose": N_("tool pose")},
        N_("Follow"),
        "",
        "motion",
        "position",
    ),
    # Maps
    Option(
        "workspace",
        "bool",
        False,
        N_("Workspace cloud"),
        N_("20,000 tool points of random configurations, coloured by w (yellow: high, purple: low)"),
        "maps",
    ),
    Option("joint_map", "bool", False, N_("Joint-space map of w"), "", "maps"),
    Option("map_i", "joint", 1, N_("x axis"), "", "maps", widget="own"),
    Option("map_j", "joint", 2, N_("y axis"), "", "maps", widget="own"),
    # Derive
    _choice(
        "derive",
        {"": N_("Nothing (DH table only)"), **{k: m.label for k, m in STEP_METHODS.items()}},
        N_("Walk through"),
        N_("Pick one of the course's derivations of J and step through it joint by joint."),
        "derive",
        "",
    ),
    Option("derive_step", "step", 0, N_("Joint i"), "", "derive", widget="own"),
)
"""Every option, in the order the panel lists its widgets within a tab."""

OPTION: dict[str, Option] = {o.name: o for o in OPTIONS}
"""The rows by name."""


def default(name: str) -> Any:
    """The default of option ``name`` (what ``Options`` declares its field with)."""
    return OPTION[name].default


def options_of(tab: Tab) -> tuple[Option, ...]:
    """The rows whose widgets ``tab`` shows, in order."""
    return tuple(o for o in OPTIONS if o.tab == tab)


Frame = Literal["base", "tool"]


@dataclass(frozen=True)
class Options:
    """What the tab chose to see (defaults, ranges, choices and widgets: :mod:`app.core.options`).

    Attributes:
        frames: Draw a triad at every DH/link frame and at the tool.
        labels: Name the joint axes in the 3-D view.
        columns: Draw the linear parts of J's columns as arrows from the tool point.
        angular_columns: Draw the angular parts of J's columns on the joint axes.
        velocity_ellipsoid: Draw the translational manipulability ellipsoid.
        rotational_ellipsoid: Draw the rotational (angular velocity) ellipsoid.
        force_ellipsoid: Draw the translational force ellipsoid (semi-axes 1/σ).
        scale: Multiplier on the automatic arrow and ellipsoid size.
        jacobian_frame: Frame of the Jacobian shown in the panel ("base" or "tool").
        damping: λ of damped least squares for q̇ = J⁺ v (0: the pseudo-inverse) [same units as J].
        twist_frame: Axes of the desired tool twist v ("base", or "tool": held in the moving tool axes).
        speed: Playback speed of every motion (1: real time; 0.1: ten times slower).
        gizmo: Show the drag handle at the tool ("drive the tool": IK every frame).
        ik_method: "dls" (damped least squares) or "newton" (the course's J⁻¹, J⁺ when not square).
        ik_mode: "position" (the tool point follows the handle) or "pose" (the whole tool frame).
        workspace: Show the workspace cloud (tool points of random configurations coloured by w).
        joint_map: Compute and show the map of w over two joints.
        map_i, map_j: The two joints of the map (indices).
        derive: The course derivation the Derive tab walks through ("" none, "dh", "whitney",
            "differentiation", "propagation", "force"; see :mod:`app.core.snapshot.derive`).
        derive_step: Its step: joint i (0-based), row i + 1 of the DH table.
        representation: What the J(q) tab shows: "geometric" J, or the analytic J_A with
            roll-pitch-yaw ("zyx") or Euler ZYZ ("zyz") angles.
        jdot_arrow: Draw J q̈ and J̇ q̇ (the terms of the tool's acceleration ẍ = J q̈ + J̇ q̇) at the
            tool while joint rates are set.
        course_letters: Write the symbolic J, det J and J⁻¹ with the DH parameters as letters (l₁, a₂, d₄ …).
        symbolic_inverse: Show the symbolic J⁻¹ = adj(J) / det J (asked for with a button: it takes seconds).
    """

    frames: bool = default("frames")
    labels: bool = default("labels")
    columns: bool = default("columns")
    angular_columns: bool = default("angular_columns")
    velocity_ellipsoid: bool = default("velocity_ellipsoid")
    rotational_ellipsoid: bool = default("rotational_ellipsoid")
    force_ellipsoid: bool = default("force_ellipsoid")
    scale: float = default("scale")
    jacobian_frame: Frame = default("jacobian_frame")
    damping: float = default("damping")
    twist_frame: Frame = default("twist_frame")
    speed: float = default("speed")
    gizmo: bool = default("gizmo")
    ik_method: Literal["dls", "newton"] = default("ik_method")
    ik_mode: Literal["position", "pose"] = default("ik_mode")
    workspace: bool = default("workspace")
    joint_map: bool = default("joint_map")
    map_i: int = default("map_i")
    map_j: int = default("map_j")
    derive: str = default("derive")
    derive_step: int = default("derive_step")
    representation: Literal["geometric", "zyx", "zyz"] = default("representation")
    jdot_arrow: bool = default("jdot_arrow")
    course_letters: bool = default("course_letters")
    symbolic_inverse: bool = default("symbolic_inverse")
