"""Shared test settings and fixtures: hypothesis profiles, a private cache, and a running lab per module
(with the immediate fake symbolic service, or the real one for the tests of the symbolic J)."""

from __future__ import annotations

import os
import tempfile
import time

import pytest
from hypothesis import HealthCheck, settings

settings.register_profile(
    "default", max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
# CI: same budget, but derandomised so a red CI run can be reproduced exactly.
settings.register_profile(
    "ci", max_examples=25, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow]
)
settings.load_profile("ci" if os.environ.get("CI") else "default")


# Keep the tests' on-disk caches (symbolic Jacobians) out of the user's ~/.cache, and start
# every run cold so that cached results never hide a fresh computation's failure.
_CACHE_ROOT = tempfile.mkdtemp(prefix="jacobian-lab-test-cache-")
os.environ["XDG_CACHE_HOME"] = _CACHE_ROOT


@pytest.fixture(autouse=True, scope="session")
def _deadlines_on_cpu_time():
    """Symbolic time limits count the work done (this process's CPU time), not the wall clock: another
    job on the machine makes the suite slower, never cuts its symbolic work short. (Worker processes
    the app spawns keep the wall clock; their tests poll for the result.)"""
    from kinematics.symbolic import trig

    mp = pytest.MonkeyPatch()
    mp.setattr(trig, "clock", time.process_time)
    yield
    mp.undo()


@pytest.fixture(autouse=True, scope="module")
def _private_cache(tmp_path_factory):
    """A cold, private cache folder for every test module."""
    mp = pytest.MonkeyPatch()
    mp.setenv("XDG_CACHE_HOME", str(tmp_path_factory.mktemp("cache")))
    yield
    mp.undo()


@pytest.fixture(scope="module")
def lab_client():
    """One running lab (a free port) and one websocket client per test module; always stopped. Its
    symbolic service is :class:`fakes.FakeSymbolicService` (immediate placeholders, no worker)."""
    from app_helpers import running_lab

    with running_lab() as (lab, session, ws):
        yield lab, session, ws


@pytest.fixture(scope="module")
def symbolic_lab_client():
    """:func:`lab_client` with the real symbolic service (worker processes): for the tests of the
    symbolic J, J⁻¹, steps and exports in the app (mark them ``slow``)."""
    from app_helpers import running_lab

    from app.services.symbolic_service import SymbolicService

    with running_lab(symbolic=SymbolicService()) as (lab, session, ws):
        yield lab, session, ws


def _fresh(lab_client):
    from app.core.actions import ReplaceState
    from app.core.state import LabState

    lab, session, _ = lab_client
    session.dispatch(ReplaceState(LabState.initial(lab.default_robot, lab.catalog.load(lab.default_robot))))
    session.settle()
    assert session.state.configuration == "home"
    return session


@pytest.fixture
def session(lab_client):
    """The module's session, reset to a fresh state of the default robot, so each test stands alone."""
    return _fresh(lab_client)


@pytest.fixture
def symbolic_session(symbolic_lab_client):
    """:func:`session` of the lab with the real symbolic service."""
    return _fresh(symbolic_lab_client)


@pytest.fixture
def checked():
    """A viser server created with the app's input checks installed (as a Lab's: they check every value
    a tab sends, relay none to its own connection and run callbacks marked ``on_event_loop`` inline)."""
    import viser

    from app import viser_adapter as va
    from app.viser_adapter import gate

    installed = bool(gate._original)
    va.install_input_checks()
    srv = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        yield srv
    finally:
        srv.stop()
        if not installed:
            va.uninstall_input_checks()
