"""On-disk cache of symbolic results under ``kinematics.cache_dir() / "symbolic"``.

Entries are pickles of SymPy objects that this module wrote itself, named by
a SHA-256 of the request key (robot fingerprint, options, :data:`FORMAT_VERSION`
and the SymPy version). Security note: unpickling runs code chosen by whoever
wrote the file, so only our own files in the user's private cache directory
are ever loaded, never a file a user passes in; nothing is parsed from text
(no ``sympify``/``eval``). A file that fails to load, or whose stored key
differs from the request, is ignored and rewritten.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import pickle
import tempfile
from pathlib import Path

import sympy as sp

from .. import cache_dir

__all__ = ["FORMAT_VERSION", "load", "store", "path_for", "clear_memory"]

FORMAT_VERSION = 1
"""Bump when the layout or the meaning of a cached result changes."""

_memory: dict[str, object] = {}


def _full_key(key: str) -> str:
    return f"v{FORMAT_VERSION}|sympy {sp.__version__}|{key}"


def path_for(key: str) -> Path:
    """File that holds (or would hold) the entry for ``key``."""
    digest = hashlib.sha256(_full_key(key).encode()).hexdigest()[:32]
    return cache_dir() / "symbolic" / f"{digest}.pkl"


def load(key: str) -> object | None:
    """The cached value for ``key`` (memory first, then disk), or ``None``."""
    full = _full_key(key)
    if full in _memory:
        return _memory[full]
    path = path_for(key)
    try:
        with open(path, "rb") as f:
            stored_key, value = pickle.load(f)  # our own file, see the module docstring
    except (OSError, EOFError, pickle.UnpicklingError, ValueError, TypeError, AttributeError, ImportError):
        return None
    if stored_key != full:
        return None
    _memory[full] = value
    return value


def store(key: str, value: object) -> None:
    """Save ``value`` for ``key`` in memory and, atomically, on disk (failures to write are ignored)."""
    full = _full_key(key)
    _memory[full] = value
    path = path_for(key)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    except OSError:
        return
    try:
        with os.fdopen(fd, "wb") as f:
            pickle.dump((full, value), f, protocol=pickle.HIGHEST_PROTOCOL)
        os.replace(tmp, path)
    except (OSError, pickle.PicklingError, TypeError, AttributeError):
        with contextlib.suppress(OSError):
            os.unlink(tmp)


def clear_memory() -> None:
    """Forget the in-memory copies (the disk cache stays): for tests and benchmarks."""
    _memory.clear()
