"""Symbolic results reach a tab through its queue, as a message, and only the one still wanted is drawn."""

from __future__ import annotations

import dataclasses
from concurrent.futures import Future

import robots
from app.core.commands import SymbolicResult
from app.core.state import LabState
from app.tab.symbols import TabSymbols


class FakeService:
    """Futures the test completes by hand; records what is asked and released."""

    def __init__(self) -> None:
        self.asked: dict[tuple, Future] = {}
        self.released: list[tuple] = []

    def _ask(self, *key):
        return self.asked.setdefault(key, Future())

    mathml = inverse = steps = _ask

    def _release(self, *key):
        self.released.append(key)

    release = release_inverse = release_steps = _release


class FakePart:
    def __init__(self) -> None:
        self.shown: list[tuple] = []

    def show_symbolic(self, content, note):
        self.shown.append((content, note))

    show_formulas = show_symbolic


class FakePanel:
    def __init__(self) -> None:
        self.matrix, self.inverse, self.derive = FakePart(), FakePart(), FakePart()


PLANAR = LabState.initial("planar2", robots.load("planar2"))


def _state(frame: str = "base") -> LabState:
    """The same robot, J in ``frame`` axes."""
    return PLANAR.replace(options=dataclasses.replace(PLANAR.options, jacobian_frame=frame))


def test_a_result_comes_back_as_a_message_and_is_drawn_once():
    service, sent, panel = FakeService(), [], FakePanel()
    symbols = TabSymbols(service, sent.append)
    state = _state()
    symbols.update(state, None)
    symbols.draw(panel, everything=True)
    assert panel.matrix.shown == [(None, "computing the symbolic form… (the numeric J above is live)")]
    key = (state.robot, "base", False)
    service.asked[key].set_result("<math>J</math>")  # the worker's thread: only a message
    assert len(sent) == 1 and isinstance(sent[0], SymbolicResult)
    assert (sent[0].part, sent[0].key, sent[0].content) == ("matrix", key, "<math>J</math>")
    assert panel.matrix.shown[-1][0] is None  # nothing drawn until the loop takes the message
    assert symbols.take(sent[0])
    symbols.draw(panel, everything=False)
    assert panel.matrix.shown[-1] == ("<math>J</math>", "J(q) in base axes, from kinematics.symbolic.")
    symbols.draw(panel, everything=False)  # nothing new: nothing drawn again
    assert len(panel.matrix.shown) == 2
    assert panel.inverse.shown == [] and panel.derive.shown == []  # not asked for


def test_a_result_no_longer_wanted_is_dropped_and_its_request_released():
    service, sent, panel = FakeService(), [], FakePanel()
    symbols = TabSymbols(service, sent.append)
    base = _state("base")
    symbols.update(base, None)
    tool = _state("tool")
    symbols.update(tool, base)  # the frame changed before the first result came
    old = (base.robot, "base", False)
    assert old in service.released
    service.asked[old].set_result("<math>old</math>")
    assert not symbols.take(sent[-1])  # stale: not kept, not drawn
    symbols.draw(panel, everything=True)
    assert panel.matrix.shown == [(None, "computing the symbolic form… (the numeric J above is live)")]
    service.asked[(tool.robot, "tool", False)].set_exception(RuntimeError("worker gone"))
    assert symbols.take(sent[-1])
    symbols.draw(panel, everything=False)
    assert panel.matrix.shown[-1] == (None, "symbolic form not available: RuntimeError: worker gone")


def test_a_result_ready_at_once_is_drawn_without_a_message():
    service, sent, panel = FakeService(), [], FakePanel()
    state = _state()
    service.asked[(state.robot, "base", False)] = done = Future()
    done.set_result("<math>cached</math>")
    symbols = TabSymbols(service, sent.append)
    symbols.update(state, None)
    symbols.draw(panel, everything=True)
    assert sent == [] and panel.matrix.shown == [
        ("<math>cached</math>", "J(q) in base axes, from kinematics.symbolic.")
    ]


def test_a_computation_stopped_at_a_limit_is_told_in_the_panel_and_in_a_notice():
    from app.services.symbolic_requests import SymbolicStopped

    service, sent, panel, notices = FakeService(), [], FakePanel(), []
    symbols = TabSymbols(service, sent.append, lambda title, body: notices.append((title, body)))
    state = _state()
    symbols.update(state, None)
    service.asked[(state.robot, "base", False)].set_exception(SymbolicStopped("memory", 75.0, 110.0))
    sentence = (
        "The symbolic J of this 2-joint arm needed more than 110 MB of the server's memory and was stopped; "
        "the numeric J above is live."
    )
    assert notices == [("Symbolic form stopped", sentence)]
    assert symbols.take(sent[0])
    symbols.draw(panel, everything=False)
    assert panel.matrix.shown[-1] == (None, sentence)


def test_an_arm_too_large_is_told_at_once_and_the_notice_given_once_per_tab():
    """A Build table grown row by row past the rule: every row's panel says it, one notice says it."""
    from app.services.symbolic_requests import MAX_SYMBOLIC_JOINTS, SymbolicNotAttempted

    service, sent, panel, notices = FakeService(), [], FakePanel(), []
    symbols = TabSymbols(service, sent.append, lambda title, body: notices.append((title, body)))
    for joints in (8, 9):
        state = _state("tool" if joints == 9 else "base")  # a new key each time, as a new robot makes
        service.asked[(state.robot, state.options.jacobian_frame, False)] = failed = Future()
        failed.set_exception(SymbolicNotAttempted(joints, MAX_SYMBOLIC_JOINTS))
        symbols.update(state, None)
        symbols.draw(panel, everything=True)
        assert panel.matrix.shown[-1][1].startswith("The symbolic J of this 2-joint arm is not worked out")
    assert sent == []  # said before anything started: no message from a worker
    assert [title for title, _ in notices] == ["Symbolic form not attempted"]


def test_a_polish_tab_is_told_of_a_stopped_or_unattempted_symbolic_j_in_polish_once():
    """The limits' sentences go through the catalogs: a Polish tab reads them in Polish (with the
    figures in place), and the 'not attempted' notice is still given once, whatever its language."""
    from app.core.i18n import translations
    from app.services.symbolic_requests import MAX_SYMBOLIC_JOINTS, SymbolicNotAttempted, SymbolicStopped

    polish = translations("pl")
    service, sent, panel, notices = FakeService(), [], FakePanel(), []
    symbols = TabSymbols(
        service, sent.append, lambda title, body: notices.append((title, body)), lambda: polish
    )
    state = _state()
    symbols.update(state, None)
    service.asked[(state.robot, "base", False)].set_exception(SymbolicStopped("time", 75.0, 110.0))
    assert notices == [
        (
            "Obliczenia symboliczne przerwane",
            "Symboliczny jakobian J tego ramienia o 2 przegubach nie został obliczony w ciągu 75 s i przerwano "
            "obliczenia; numeryczny J powyżej jest aktualny.",
        )
    ]
    for frame in ("tool", "base"):
        state = _state(frame)
        service.asked[(state.robot, frame, False)] = failed = Future()
        failed.set_exception(SymbolicNotAttempted(9, MAX_SYMBOLIC_JOINTS))
        symbols.update(state, None)
        symbols.draw(panel, everything=True)
        assert panel.matrix.shown[-1][1].startswith(
            "Symboliczny jakobian J tego ramienia o 2 przegubach nie jest"
        )
    assert [title for title, _ in notices][1:] == ["Postać symboliczna nie jest obliczana"]
