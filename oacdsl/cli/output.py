"""Standard output that fails as one line: a full disk or a closed reader is no traceback.

``oacc`` writes its results to stdout; when stdout is a file on a full disk (or a
device such as ``/dev/full``, or a pipe whose reader is gone) every ``print`` raises
``OSError``. :func:`guarded_stdout` puts a thin proxy in front of ``sys.stdout`` for the
duration of a command: a failed write or flush becomes :class:`StdoutError` (an
:class:`~oacdsl.errors.InputError`, exit status 2, ``oacc: error: standard output: …``),
and :func:`silence_stdout` points the file descriptor at ``/dev/null`` so that the
interpreter's last flush at exit does not fail again with a second message.
"""

from __future__ import annotations

import errno
import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any, TextIO

from oacdsl.errors import InputError

__all__ = ["StdoutError", "guarded_stdout", "silence_stdout"]


class StdoutError(InputError):
    """Standard output cannot be written (disk full, I/O error); ``broken_pipe`` when the reader left."""

    def __init__(self, error: OSError) -> None:
        self.broken_pipe = isinstance(error, BrokenPipeError) or error.errno == errno.EPIPE
        super().__init__(f"cannot write: {error.strerror or error}", location="standard output")


class _Guarded:
    """A proxy of a text stream whose ``write``/``writelines``/``flush`` raise :class:`StdoutError`."""

    def __init__(self, stream: TextIO) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        try:
            return self._stream.write(text)
        except OSError as error:
            raise StdoutError(error) from None

    def writelines(self, lines: Any) -> None:
        for line in lines:
            self.write(line)

    def flush(self) -> None:
        try:
            self._stream.flush()
        except OSError as error:
            raise StdoutError(error) from None

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


@contextmanager
def guarded_stdout() -> Iterator[None]:
    """``sys.stdout`` guarded for the block (and flushed at its end, inside the guard)."""
    original = sys.stdout
    guarded = _Guarded(original)
    sys.stdout = guarded  # type: ignore[assignment]
    try:
        yield
        guarded.flush()
    finally:
        if sys.stdout is guarded:
            sys.stdout = original


def silence_stdout() -> None:
    """After a failed write: drop what is buffered by sending stdout's descriptor to ``/dev/null``."""
    try:
        fd = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):  # not a real file (a test's capture)
        return
    try:
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, fd)
        os.close(null)
    except OSError:
        pass
