"""On-disk cache of symbolic results under ``kinematics.cache_dir() / "symbolic"``, in plain JSON.

Security: nothing read from the cache can run code. Entries are JSON documents
``{"key": ..., "value": ...}`` decoded by :mod:`.cachecodec`, which rebuilds only a
whitelist of SymPy node types (numbers, symbols, sums, products, powers, a few
elementary functions) and of registered result dataclasses; no pickle, no ``eval``,
no ``sympify``. The stored key is compared with the request before the value is
decoded. The folder is created with mode 0o700 and is refused (a warning in the log,
no disk caching) unless it, and the ``jacobian-lab`` folder above it, are directories
owned by the current user and not writable by group or others (the ``jacobian-lab`` folder,
ours, loses group/other write if a umask of 002 gave it). Files are written
atomically (a temporary file, then ``os.replace``) with mode 0o600, and read only if
they are regular files owned by the user and at most :data:`MAX_BYTES` long.

Entries are named by a SHA-256 of the request key (robot fingerprint, options,
:data:`FORMAT_VERSION` and the SymPy version). A file that fails any check, fails to
decode, or holds another key, is ignored (and rewritten by the next store).
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import logging
import os
import stat
import tempfile
from pathlib import Path

import sympy as sp

from .. import cache_dir
from .cachecodec import CodecError, decode, encode, register_dataclass

__all__ = [
    "FORMAT_VERSION",
    "MAX_BYTES",
    "load",
    "store",
    "path_for",
    "folder",
    "clear_memory",
    "stats",
    "register_dataclass",
]

FORMAT_VERSION = 2
"""Bump when the layout or the meaning of a cached result changes (2: JSON, snapped values)."""

MAX_BYTES = 64 * 1024 * 1024
"""Cache files larger than this are not read [bytes]."""

log = logging.getLogger(__name__)

_memory: dict[str, object] = {}
stats = {"memory_hits": 0, "disk_hits": 0, "misses": 0, "rejected": 0, "stored": 0}
"""Counters of what :func:`load` and :func:`store` did (observable by tests and benchmarks)."""

_warned: set[str] = set()


def _full_key(key: str) -> str:
    return f"v{FORMAT_VERSION}|sympy {sp.__version__}|{key}"


def _root() -> Path:
    return cache_dir() / "symbolic"


def path_for(key: str) -> Path:
    """File that holds (or would hold) the entry for ``key``."""
    digest = hashlib.sha256(_full_key(key).encode()).hexdigest()[:32]
    return _root() / f"{digest}.json"


def _warn(message: str) -> None:
    if message not in _warned:
        _warned.add(message)
        log.warning(message)


def _private_dir(path: Path) -> bool:
    """True if ``path`` is a real directory owned by this user and not writable by group/others."""
    try:
        st = os.lstat(path)
    except OSError:
        return False
    if not stat.S_ISDIR(st.st_mode):
        _warn(f"symbolic cache disabled: {path} is not a directory")
        return False
    if hasattr(os, "getuid") and st.st_uid != os.getuid():
        _warn(f"symbolic cache disabled: {path} is owned by another user (uid {st.st_uid})")
        return False
    if st.st_mode & 0o022:
        _warn(f"symbolic cache disabled: {path} is writable by group or others (mode {st.st_mode & 0o777:o})")
        return False
    return True


def _tighten(path: Path) -> None:
    """Remove group/other write from our own ``jacobian-lab`` folder (made under a umask of 002)."""
    with contextlib.suppress(OSError):
        st = os.lstat(path)
        mine = not hasattr(os, "getuid") or st.st_uid == os.getuid()
        if stat.S_ISDIR(st.st_mode) and mine and st.st_mode & 0o022:
            os.chmod(path, stat.S_IMODE(st.st_mode) & ~0o022)


def folder(create: bool = True) -> Path | None:
    """The cache folder if it is safe to use (created private if missing), else ``None``."""
    try:
        root = _root()
    except OSError:
        return None
    if create and not root.exists():
        with contextlib.suppress(FileExistsError, OSError):
            os.mkdir(root, 0o700)
    _tighten(root.parent)
    if not (_private_dir(root.parent) and _private_dir(root)):
        return None
    return root


def _read(path: Path) -> bytes | None:
    """The bytes of a cache entry, or ``None``: never through a link, never blocking (a FIFO or a
    device there is ignored with a warning, as is anything but a private regular file of this user)."""
    flags = os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0)
    try:
        fd = os.open(path, flags)
    except FileNotFoundError:
        return None
    except OSError as exc:  # a link, or a socket
        _warn(f"symbolic cache: ignoring {path} ({exc.strerror})")
        return None
    try:
        st = os.fstat(fd)
        mine = not hasattr(os, "getuid") or st.st_uid == os.getuid()
        if not stat.S_ISREG(st.st_mode) or not mine or st.st_mode & 0o022 or st.st_size > MAX_BYTES:
            _warn(f"symbolic cache: ignoring {path} (not a private regular file of this user)")
            return None
        with os.fdopen(os.dup(fd), "rb") as f:
            return f.read(MAX_BYTES + 1)
    except OSError:
        return None
    finally:
        os.close(fd)


def load(key: str) -> object | None:
    """The cached value for ``key`` (memory first, then disk), or ``None``."""
    full = _full_key(key)
    if full in _memory:
        stats["memory_hits"] += 1
        return _memory[full]
    root = folder(create=False)
    data = None if root is None else _read(path_for(key))
    if data is None:
        stats["misses"] += 1
        return None
    try:
        doc = json.loads(data)
        if not isinstance(doc, dict) or doc.get("key") != full:  # the key is checked before decoding
            raise CodecError("another key")
        value = decode(doc["value"])
    except (ValueError, KeyError, TypeError, RecursionError, CodecError):  # JSONDecodeError is a ValueError
        stats["rejected"] += 1
        return None
    stats["disk_hits"] += 1
    _memory[full] = value
    return value


def store(key: str, value: object) -> None:
    """Save ``value`` for ``key`` in memory and, atomically, on disk.

    Values that cannot be encoded (a SymPy node outside the whitelist) are kept in memory
    only; failures to write are ignored.
    """
    full = _full_key(key)
    _memory[full] = value
    try:
        text = json.dumps({"key": full, "value": encode(value)}, allow_nan=False, separators=(",", ":"))
    except (CodecError, ValueError, RecursionError):
        return
    root = folder(create=True)
    if root is None:
        return
    try:
        fd, tmp = tempfile.mkstemp(dir=root, suffix=".tmp")  # mode 0o600
    except OSError:
        return
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.chmod(tmp, 0o600)
        os.replace(tmp, path_for(key))
        stats["stored"] += 1
    except OSError:
        with contextlib.suppress(OSError):
            os.unlink(tmp)


def clear_memory() -> None:
    """Forget the in-memory copies (the disk cache stays): for tests and benchmarks."""
    _memory.clear()
