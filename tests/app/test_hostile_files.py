"""Point 8 and part of 9 of issue 18: no open that can block on an output or cache path, no output
written through a link the user did not name, bounded ``--fps``, ``--seconds`` and ``--timeout``,
cache entries that are not private regular files ignored with a warning."""

from __future__ import annotations

import logging
import os
import threading
from pathlib import Path

import pytest

from app.cli.main import main
from kinematics.files import write_user_file
from kinematics.symbolic import cache


def _bounded(fn, timeout: float = 60.0):
    """``fn()`` in a thread; fail if it has not returned within ``timeout`` (it would hang for ever)."""
    result: list = []
    thread = threading.Thread(target=lambda: result.append(fn()), daemon=True)
    thread.start()
    thread.join(timeout)
    assert result, f"still running after {timeout} s"
    return result[0]


@pytest.mark.parametrize(
    "command", [["export", "planar2", "--format", "latex"], ["handout", "planar2", "--format", "html"]]
)
def test_an_output_that_is_a_fifo_is_refused_without_blocking(tmp_path, capsys, command):
    fifo = tmp_path / "out.fifo"
    os.mkfifo(fifo)
    assert _bounded(lambda: main([*command, "-o", str(fifo)])) == 1
    assert "FIFO (named pipe), not a regular file" in capsys.readouterr().err


def test_a_device_or_a_directory_is_not_written(tmp_path):
    with pytest.raises(OSError, match="character device, not a regular file"):
        write_user_file("/dev/null", b"x")
    with pytest.raises(OSError):
        write_user_file(tmp_path, b"x")
    target = tmp_path / "named.txt"
    write_user_file(target, b"first, longer")
    write_user_file(target, b"second")
    assert target.read_bytes() == b"second"  # truncated, then written


def test_record_writes_no_file_through_a_link_left_in_its_folder(tmp_path, capsys):
    out, victim = tmp_path / "demo", tmp_path / "victim.txt"
    out.mkdir()
    victim.write_text("keep me")
    (out / "index.html").symlink_to(victim)
    assert main(["record", "planar2", "-o", str(out), "--seconds", "0.5", "--fps", "4"]) == 2
    assert "symbolic link (not followed)" in capsys.readouterr().err
    assert victim.read_text() == "keep me"


@pytest.mark.parametrize(
    "flags, expected",
    [
        (["--fps", "1e6"], "--fps: expected a number more than 0 up to 120"),
        (["--seconds", "1e9"], "--seconds: expected a number more than 0 up to 600 s"),
        (["--fps", "nan"], "--fps: expected a number"),
    ],
)
def test_record_refuses_a_frame_rate_or_length_out_of_bounds(tmp_path, capsys, flags, expected):
    assert _bounded(lambda: main(["record", "planar2", "-o", str(tmp_path / "d"), *flags])) == 2
    assert expected in capsys.readouterr().err


def test_export_refuses_an_endless_timeout(capsys):
    assert main(["export", "planar2", "--timeout", "inf"]) == 2
    assert "--timeout: expected a number more than 0 up to 3600 s" in capsys.readouterr().err


@pytest.mark.parametrize("kind", ["fifo", "directory", "link"])
def test_a_cache_entry_that_is_not_a_private_regular_file_is_ignored(tmp_path, monkeypatch, caplog, kind):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    cache.clear_memory()
    monkeypatch.setattr(cache, "_warned", set())
    key = f"hostile-{kind}"
    cache.store(key, 42)
    cache.clear_memory()
    path = cache.path_for(key)
    assert cache.load(key) == 42
    cache.clear_memory()
    path.unlink()
    if kind == "fifo":
        os.mkfifo(path, 0o600)
    elif kind == "directory":
        path.mkdir(mode=0o700)
    else:
        (tmp_path / "elsewhere.json").write_text("{}")
        path.symlink_to(tmp_path / "elsewhere.json")
    with caplog.at_level(logging.WARNING):
        assert _bounded(lambda: cache.load(key)) is None
    assert "symbolic cache: ignoring" in caplog.text
    cache.store(key, 43)  # replaced by a regular file again (or left alone), never an error
    cache.clear_memory()
    assert Path(path).exists()
