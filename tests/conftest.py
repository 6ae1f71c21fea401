"""Shared test settings: hypothesis profiles."""

from __future__ import annotations

import os
import tempfile

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


@pytest.fixture(autouse=True, scope="module")
def _private_cache(tmp_path_factory):
    """A cold, private cache folder for every test module."""
    mp = pytest.MonkeyPatch()
    mp.setenv("XDG_CACHE_HOME", str(tmp_path_factory.mktemp("cache")))
    yield
    mp.undo()
