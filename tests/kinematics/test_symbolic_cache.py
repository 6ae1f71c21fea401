"""The symbolic cache: plain JSON that cannot run code, key checked first, private folder, atomic files."""

from __future__ import annotations

import json
import logging
import os
import pickle
import stat

import numpy as np
import pytest
import sympy as sp
from locations import DATA

import kinematics
import robots
from kinematics import symbolic
from kinematics.symbolic import cache
from kinematics.symbolic.cachecodec import CodecError, decode, encode


@pytest.fixture()
def fresh_cache(tmp_path, monkeypatch):
    """An empty cache root, with the in-memory copies and counters reset."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    cache.clear_memory()
    for k in cache.stats:
        cache.stats[k] = 0
    yield tmp_path / "jacobian-lab" / "symbolic"
    cache.clear_memory()


def derive_key(robot, frame="base", params=False):
    return f"derive|{symbolic.build_model(robot, params).cache_key()}|{frame}"


class Payload:
    """Unpickling this runs ``os.system(command)``."""

    def __init__(self, command):
        self.command = command

    def __reduce__(self):
        return (os.system, (self.command,))


def test_planted_pickle_never_runs(fresh_cache, tmp_path):
    robot = robots.load("planar2")
    marker = tmp_path / "MARKER"
    payload = pickle.dumps(Payload(f"touch {marker}"))
    path = cache.path_for(derive_key(robot))
    path.parent.mkdir(parents=True, mode=0o700)
    path.write_bytes(payload)
    path.with_suffix(".pkl").write_bytes(payload)  # where the pickle cache kept it
    d = symbolic.derive(robot)
    assert not marker.exists()
    assert not d.from_cache and cache.stats["rejected"] == 1
    assert d.J[0, 1] == -sp.sin(sp.Symbol("q1", real=True) + sp.Symbol("q2", real=True))


def test_file_with_another_key_is_ignored(fresh_cache):
    robot = robots.load("planar2")
    key = derive_key(robot)
    symbolic.derive(robot)
    path = cache.path_for(key)
    doc = json.loads(path.read_text())
    doc["key"] = doc["key"].replace("|base", "|tool")
    doc["value"]["d"][5][1] = encode(sp.zeros(6, 2))  # a wrong J under the wrong key
    path.write_text(json.dumps(doc))
    cache.clear_memory()
    d = symbolic.derive(robot)
    assert not d.from_cache and cache.stats["rejected"] == 1 and d.J != sp.zeros(6, 2)


@pytest.mark.parametrize(
    "value",
    [
        {"e": ["Function", "system", ["Symbol", "x", False]]},
        {"e": ["Symbol", "x"]},
        {"dc": "Robot", "f": {}},
        {"x": [1]},
        {"e": ["Integer", "1" * 5000]},
    ],
)
def test_decoder_refuses_what_is_not_whitelisted(value):
    with pytest.raises(CodecError):
        decode(value)


def test_encoder_refuses_unknown_nodes():
    with pytest.raises(CodecError, match="cannot cache"):
        encode(sp.exp(sp.Symbol("x")))
    with pytest.raises(CodecError, match="assumptions"):
        encode(sp.Symbol("x", positive=True))


def test_folder_is_private_and_files_are_0600(fresh_cache):
    symbolic.derive(robots.load("planar2"))
    assert stat.S_IMODE(os.stat(fresh_cache).st_mode) == 0o700
    files = list(fresh_cache.iterdir())
    assert [f.suffix for f in files] == [".json"]
    assert stat.S_IMODE(os.stat(files[0]).st_mode) == 0o600


def test_group_writable_folder_is_refused(fresh_cache, caplog):
    fresh_cache.mkdir(parents=True, mode=0o700)
    os.chmod(fresh_cache, 0o770)
    robot = robots.load("planar2")
    with caplog.at_level(logging.WARNING, logger="kinematics.symbolic.cache"):
        symbolic.derive(robot)
        cache.clear_memory()
        d = symbolic.derive(robot)
    assert list(fresh_cache.iterdir()) == [] and not d.from_cache
    assert cache.stats["stored"] == 0 and cache.stats["disk_hits"] == 0
    assert any("writable by group or others" in r.getMessage() for r in caplog.records)


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0, reason="needs root to chown")
def test_folder_of_another_user_is_refused(fresh_cache):
    fresh_cache.mkdir(parents=True, mode=0o700)
    os.chown(fresh_cache, 65534, -1)
    symbolic.derive(robots.load("planar2"))
    assert list(fresh_cache.iterdir()) == [] and cache.stats["stored"] == 0


@pytest.mark.slow
def test_every_cached_kind_round_trips(fresh_cache):
    """Derivations (with snapped values), determinants (square and Gram, with singular sets)."""
    iiwa = kinematics.robot_from_urdf(str(DATA / "iiwa14_like.urdf"))
    requests = [
        lambda: symbolic.derive(iiwa),
        lambda: symbolic.derive(robots.load("elbow3r"), "tool", symbolic_params=True),
        lambda: symbolic.determinant(robots.load("puma560")),
        lambda: symbolic.determinant(robots.load("elbow3r"), symbolic_params=True),
        lambda: symbolic.determinant(robots.load("planar3")),
    ]
    first = [r() for r in requests]
    assert first[0].snaps and cache.stats["stored"] == len(requests)
    cache.clear_memory()
    second = [r() for r in requests]
    assert cache.stats["disk_hits"] == len(requests) and cache.stats["rejected"] == 0
    for a, b in zip(first, second, strict=True):
        for name in a.__dataclass_fields__:
            if name not in ("from_cache", "robot"):
                assert getattr(a, name) == getattr(b, name), name
    assert second[0].from_cache and second[0].snap_note == first[0].snap_note
    assert (0, sp.pi) in [s.solutions for s in second[2].singular_sets]  # sin q5 = 0: the wrist


@pytest.mark.slow
def test_second_request_is_a_cache_hit(fresh_cache):
    robot = robots.load("stanford")
    first = symbolic.derive(robot)
    assert not first.from_cache and cache.stats["misses"] == 1
    second = symbolic.derive(robot)
    assert second.from_cache and cache.stats["memory_hits"] == 1
    cache.clear_memory()
    third = symbolic.derive(robot)
    assert third.from_cache and cache.stats["disk_hits"] == 1 and third.J == first.J


@pytest.mark.slow
def test_partial_result_is_cached_and_resumed(fresh_cache):
    robot = robots.load("puma560")
    partial = symbolic.derive(robot, timeout=1e-9)
    assert not partial.complete and partial.pending
    again = symbolic.derive(robot, timeout=1e-9)  # no more time than before: the cached result
    assert again.from_cache and again.pending == partial.pending
    done = symbolic.derive(robot, timeout=60)  # more time: resumed from the pending entries
    assert done.complete and not done.from_cache and done.pending == ()
    reference = symbolic.derive(robot, use_cache=False)
    assert done.J == reference.J and done.T == reference.T
    f = symbolic.numeric_function(done.J, symbolic.build_model(robot))
    q = np.array([0.1, -0.4, 0.7, 0.2, -1.1, 0.5])
    np.testing.assert_allclose(f(q), kinematics.jacobian(robot, q), atol=1e-12)


def test_own_app_folder_made_under_umask_002_is_tightened(fresh_cache):
    app_dir = fresh_cache.parent
    app_dir.mkdir(parents=True, mode=0o775)
    os.chmod(app_dir, 0o775)
    symbolic.derive(robots.load("planar2"))
    assert stat.S_IMODE(os.stat(app_dir).st_mode) == 0o755 and cache.stats["stored"] == 1
