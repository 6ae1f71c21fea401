"""Reading and writing a user's file safely: a regular file, under a size cap, UTF-8 text, never blocking.

Shared by the URDF reader and the robot-file loader (:mod:`robots`). A path
that names a directory, a FIFO, a socket or a device (``/dev/urandom``) is
refused from its ``os.stat`` before it is opened, so nothing blocks or reads
without end; a regular file is read with a bound, so a file that grows while
it is read cannot exceed the cap either.
"""

from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

from .errors import JacobianLabError

__all__ = ["read_user_file", "write_user_file", "decode_utf8", "MAX_FILE_BYTES"]

MAX_FILE_BYTES = 20 * 1024 * 1024
"""Largest robot file or URDF read [bytes] (the biggest real URDFs are a few hundred kB)."""

_KINDS = (
    (stat.S_ISDIR, "a directory"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


def read_user_file(
    path: str | os.PathLike[str],
    what: str,
    error: type[JacobianLabError],
    max_bytes: int = MAX_FILE_BYTES,
) -> bytes:
    """The bytes of the regular file ``path``, at most ``max_bytes`` of them.

    Args:
        path: The file (symbolic links are followed).
        what: What the file is, for messages (``"URDF"``, ``"robot file"``).
        error: The :class:`JacobianLabError` subclass to raise.
        max_bytes: Size cap [bytes].

    Raises:
        error: ``path`` is missing or unreadable, not a regular file, or larger than the cap.
    """
    p = Path(path)
    try:
        st = os.stat(p)
    except (OSError, ValueError) as exc:  # ValueError: a NUL byte in the path
        reason = getattr(exc, "strerror", None) or str(exc)
        raise error(f"cannot read {what} {str(path)!r}: {reason}") from None
    for check, kind in _KINDS:
        if check(st.st_mode):
            raise error(f"cannot read {what} {str(path)!r}: it is {kind}, not a regular file")
    if not stat.S_ISREG(st.st_mode):
        raise error(f"cannot read {what} {str(path)!r}: not a regular file")
    if st.st_size > max_bytes:
        raise error(f"{what} {p.name!r} is {st.st_size} bytes; the limit is {max_bytes}")
    try:
        # O_NONBLOCK: should the path be swapped for a FIFO after the stat, open() still returns.
        fd = os.open(p, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
        with os.fdopen(fd, "rb") as f:
            if not stat.S_ISREG(os.fstat(f.fileno()).st_mode):
                raise error(f"cannot read {what} {str(path)!r}: not a regular file")
            data = f.read(max_bytes + 1)
    except OSError as exc:
        raise error(f"cannot read {what} {str(path)!r}: {exc.strerror or exc}") from None
    if len(data) > max_bytes:
        raise error(f"{what} {p.name!r} is larger than the limit of {max_bytes} bytes")
    return data


def decode_utf8(data: bytes, what: str, error: type[JacobianLabError]) -> str:
    """``data`` decoded as UTF-8 (a leading byte-order mark is dropped).

    Raises:
        error: the bytes are not UTF-8; the message gives the line and column of the first bad byte.
    """
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        before = data[: exc.start]
        line = before.count(b"\n") + 1
        column = exc.start - (before.rfind(b"\n") + 1) + 1
        bad = data[exc.start : exc.start + 1].hex()
        raise error(
            f"{what} is not UTF-8 text: byte 0x{bad} at line {line}, column {column} (save the file as UTF-8)"
        ) from None


def write_user_file(path: str | os.PathLike[str], data: bytes, named: bool = True) -> None:
    """Write ``data`` to the regular file ``path`` (created, or truncated), never blocking.

    A FIFO, a device, a socket or a directory at ``path`` is refused without being written (the
    file is opened without blocking, then checked before a byte goes in). ``named``: the user
    named ``path`` (``-o FILE``), so a symbolic link there is followed; a file the program names
    inside an output folder (``named=False``) is never written through a link.

    Raises:
        OSError: ``path`` cannot be written, or is not a regular file (``strerror`` says which).
    """
    flags = os.O_WRONLY | os.O_CREAT | getattr(os, "O_NONBLOCK", 0)
    if not named:
        flags |= getattr(os, "O_NOFOLLOW", 0)
    try:
        fd = os.open(path, flags, 0o644)
    except OSError as exc:
        if exc.errno == errno.ENXIO:  # a FIFO with no reader
            raise OSError(exc.errno, "it is a FIFO (named pipe), not a regular file", str(path)) from None
        if exc.errno == errno.ELOOP and not named:
            raise OSError(exc.errno, "it is a symbolic link (not followed)", str(path)) from None
        raise
    try:
        mode = os.fstat(fd).st_mode
        if not stat.S_ISREG(mode):
            kind = next((k for check, k in _KINDS if check(mode)), "not a regular file")
            raise OSError(errno.EINVAL, f"it is {kind}, not a regular file", str(path))
        os.ftruncate(fd, 0)
        view = memoryview(data)
        while view:
            view = view[os.write(fd, view) :]
    finally:
        os.close(fd)
