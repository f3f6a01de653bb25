"""Reading a small document (a segmentation or result ``.json``) named on the command line.

Only a regular file is opened: a FIFO would wait for a writer for ever, ``/dev/zero``
never ends, a folder is no document. The type is checked before opening and again on
the open descriptor, and at most ``max_bytes`` are read, so no path makes the reader
hang or exhaust memory. Failures are :class:`~oacdsl.errors.InputError` (exit status
2) naming the file.
"""

from __future__ import annotations

import os
import stat

from oacdsl.errors import InputError

__all__ = ["MAX_DOCUMENT_BYTES", "read_document"]

#: The largest document read, bytes (segmentations and results are well under 1 MiB).
MAX_DOCUMENT_BYTES = 64 * 2**20

_KINDS = [
    (stat.S_ISDIR, "a folder"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISSOCK, "a socket"),
]


def _refuse_special(mode: int, location: str, what: str) -> None:
    if not stat.S_ISREG(mode):
        kind = next((name for test, name in _KINDS if test(mode)), "a special file")
        raise InputError(f"is {kind}, not {what}", location=location)


def read_document(path: str | os.PathLike[str], what: str, max_bytes: int = MAX_DOCUMENT_BYTES) -> str:
    """The UTF-8 text of the regular file ``path`` of at most ``max_bytes`` (``what`` names the
    expected content in messages, e.g. ``"a result document"``)."""
    location = str(path)
    try:
        _refuse_special(os.stat(path).st_mode, location, what)
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except FileNotFoundError:
        raise InputError("no such file", location=location) from None
    except OSError as error:
        raise InputError(f"cannot read: {error.strerror or error}", location=location) from None
    with os.fdopen(fd, "rb") as fh:
        info = os.fstat(fh.fileno())
        _refuse_special(info.st_mode, location, what)  # replaced between the check and the open
        if info.st_size > max_bytes:
            raise InputError(f"larger than {max_bytes // 2**20} MiB; not {what}", location=location)
        try:
            data = fh.read(max_bytes + 1)
        except OSError as error:
            raise InputError(f"cannot read: {error.strerror or error}", location=location) from None
    if len(data) > max_bytes:  # grew while being read
        raise InputError(f"larger than {max_bytes // 2**20} MiB; not {what}", location=location)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        raise InputError(f"not UTF-8 text (byte {error.start}); not {what}", location=location) from None
