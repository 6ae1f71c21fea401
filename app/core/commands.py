"""Session commands: what a tab asks for that is not a change of its state.

A command needs the world outside the pure core: the robot catalogue (:class:`ChooseRobot`,
:class:`ChooseChain`, :class:`UploadRobot`), a worker (:class:`RequestDownload`,
:class:`FindSingularity`, :class:`FindIkSolutions`, :class:`ToggleRecording`), the classroom
(:data:`CLASSROOM`), or the session's own drawing (:class:`Mirror`, :class:`Redraw`,
:class:`SymbolicResult`). The session's command runner (:class:`app.tab.commands.CommandRunner`)
carries out the others; some end in a reducible action (:mod:`app.core.actions`), which the reducer
then takes like any other.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .actions import Action

if TYPE_CHECKING:
    from .state import LabState

__all__ = [
    "Command",
    "Message",
    "CLASSROOM",
    "AnswerHandover",
    "ChooseRobot",
    "ChooseChain",
    "UploadRobot",
    "RequestDownload",
    "FindSingularity",
    "FindIkSolutions",
    "ToggleRecording",
    "ClaimPresenter",
    "StopPresenting",
    "ExploreAlone",
    "FollowPresenter",
    "Mirror",
    "LabelsPlaced",
    "ChooseLanguage",
    "Redraw",
    "ResetView",
    "PageReport",
    "OpenTab",
    "SymbolicResult",
    "AskRoom",
    "AnswerRoom",
    "EndQuestion",
    "QuestionShown",
]


@dataclass(frozen=True)
class ChooseRobot:
    """The user picked robot ``name`` of the catalogue (the session loads it and reduces
    :class:`~app.core.actions.SetRobot`)."""

    name: str


@dataclass(frozen=True)
class ChooseChain:
    """The user picked the chain of the current URDF that ends at ``tip_link`` (the session
    loads that chain and reduces :class:`~app.core.actions.SetRobot`)."""

    tip_link: str


@dataclass(frozen=True)
class FindSingularity:
    """Find the nearest singularity from here (the session computes the descent away from the
    drawing thread, then dispatches :class:`~app.core.actions.FollowPath`)."""


@dataclass(frozen=True)
class FindIkSolutions:
    """Find the several IK solutions of the tool's pose (elbow up / down, wrist flip …): the session
    searches away from the drawing thread, then dispatches :class:`~app.core.actions.IkSolutionsFound`."""


@dataclass(frozen=True)
class ClaimPresenter:
    """The tab typed ``token`` into "Presenter token" (the classroom checks it once the
    typing has paused, ``settled``; a browser sends every keystroke, and five half-typed tokens must
    not use up the tab's tries)."""

    token: str
    settled: bool = False


@dataclass(frozen=True)
class StopPresenting:
    """The presenter hands the room back."""


@dataclass(frozen=True)
class ExploreAlone:
    """A follower leaves the presenter to explore on its own."""


@dataclass(frozen=True)
class FollowPresenter:
    """A tab follows the presenter again."""


@dataclass(frozen=True)
class AnswerHandover:
    """The presenter answers another tab that typed the token: it hands over (``accept``) or keeps
    presenting. Only the presenting tab's answer counts."""

    accept: bool


@dataclass(frozen=True, eq=False)
class Mirror:
    """Draw the presenter's ``state`` with the ``snapshot`` already computed for it (a follower's
    session takes it as it is: one computation per presenter change, not one per follower); ``scene``:
    the scene messages of the presenter's redraw, replayed instead of drawing the scene again (empty:
    the follower draws its own); ``shared``: a worker's :class:`~app.services.scene_slot.SceneSlot` for a
    relayed state (the first follower to draw it fills it, the others replay it)."""

    state: LabState
    snapshot: object
    scene: tuple = ()
    shared: object = None


@dataclass(frozen=True)
class Redraw:
    """Draw the tab again as it is (its classroom role changed, or refused input must be undone)."""


@dataclass(frozen=True)
class ResetView:
    """Frame the whole arm again from the robot's default direction (the camera is the tab's, not
    the state's), e.g. after a very large robot moved the camera far away."""


@dataclass(frozen=True)
class PageReport:
    """What the tab's page reports (JSON, hostile until checked by
    :func:`app.core.page_state.parse_report`): on (re)connection its address (robot, q, tab) and a
    presenter's reconnect key; later the tab the user opened."""

    text: str


@dataclass(frozen=True)
class OpenTab:
    """Open the panel tab ``label`` in this tab's page (a follower: the tab the presenter opened).

    The session draws the tab's readouts first and opens it in the same frame, so the page never
    shows what that tab held the last time it was open."""

    label: str


@dataclass(frozen=True)
class ChooseLanguage:
    """Speak language ``code`` in this tab (its Language menu): the tab's own choice, never the
    state's, so a follower keeps its language while it follows the presenter. The session redraws the
    whole page in that language and keeps it in the page's address (``?lang=``)."""

    code: str


@dataclass(frozen=True)
class ToggleRecording:
    """Start recording what this tab shows, or stop and download it as a demo that needs no server
    ."""


@dataclass(frozen=True)
class RequestDownload:
    """Send J(q) exported as ``label`` ("LaTeX", "Python" or "JSON") to this tab."""

    label: str


@dataclass(frozen=True, eq=False)
class UploadRobot:
    """The tab uploaded the file ``filename`` with ``content`` (the session reads it as a
    URDF into the tab's own robot list, then switches to it). ``refused_size``: the size [bytes] of a
    file refused as too large before it was sent (its content is then empty)."""

    filename: str
    content: bytes
    refused_size: int = 0


@dataclass(frozen=True, eq=False)
class SymbolicResult:
    """A symbolic result for this tab arrived from the worker: ``content`` (MathML, steps; ``None``
    when only the ``note`` is shown) for the panel ``part`` ("matrix", "inverse" or "derive"),
    computed for ``key``. The session keeps it only if ``key`` is still the one wanted
    (:class:`app.tab.symbols.TabSymbols`) and draws it; it is not part of the state."""

    part: str
    key: tuple
    content: object
    note: str


@dataclass(frozen=True)
class AskRoom:
    """The presenter asks the room about what is on screen (:mod:`app.core.questions`): ``kind`` is
    "kind", "blowup", "lost", "det", "kappa" or "custom" (``prompt``, ``choices`` and the indices of the
    ``right`` ones typed by the teacher). Only the presenting tab's question is asked."""

    kind: str
    prompt: str = ""
    choices: tuple[str, ...] = ()
    right: tuple[int, ...] = ()


@dataclass(frozen=True)
class AnswerRoom:
    """A follower answers round ``number``: a choice's id, a typed number as text, or a pointed direction
    (checked where it enters: :func:`app.core.poll.answer`)."""

    number: int
    value: object


@dataclass(frozen=True)
class EndQuestion:
    """The presenter closes the question (``reveal`` False: the counts are final) or reveals its answer."""

    reveal: bool


@dataclass(frozen=True)
class QuestionShown:
    """The room's question changed for this tab (new bars, its own answer taken): update its box only."""


CLASSROOM = (
    ClaimPresenter,
    StopPresenting,
    ExploreAlone,
    FollowPresenter,
    AnswerHandover,
    AskRoom,
    AnswerRoom,
    EndQuestion,
)
"""Classroom commands: a follower may always send these (its other inputs are read-only)."""


@dataclass(frozen=True, eq=False)
class LabelsPlaced:
    """The labels of a drawing this follower replays were placed again (``placed``: an
    :class:`app.tab.labels.Placement`): replayed after that drawing, in the order they came."""

    placed: Any


Command = (
    ChooseRobot
    | ChooseChain
    | UploadRobot
    | RequestDownload
    | FindSingularity
    | FindIkSolutions
    | ToggleRecording
    | ClaimPresenter
    | StopPresenting
    | ExploreAlone
    | FollowPresenter
    | AnswerHandover
    | Mirror
    | LabelsPlaced
    | Redraw
    | ResetView
    | PageReport
    | OpenTab
    | ChooseLanguage
    | SymbolicResult
    | AskRoom
    | AnswerRoom
    | EndQuestion
    | QuestionShown
)
"""Everything the session carries out itself (a union, told apart by type)."""

Message = Action | Command
"""What a tab's ``dispatch`` takes: a reducible action or a session command."""
