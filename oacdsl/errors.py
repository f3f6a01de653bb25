"""The package's exceptions: one root, one subclass per part of the pipeline.

Every error the command line can meet derives from :class:`OacError`; the CLI
prints ``str(error)`` on one line and exits with ``error.exit_code``, never a
traceback. Messages name the location (``file:line:col`` or ``file``) first
when there is one, and list the valid names when a name was wrong.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any


class OacError(Exception):
    """Root of every error raised on purpose by oacdsl."""

    #: Exit status the command line uses for this error (2 = usage or I/O).
    exit_code: int = 2

    def __init__(self, message: str, *, location: str | None = None) -> None:
        self.message = message
        self.location = location
        super().__init__(f"{location}: {message}" if location else message)


class UsageError(OacError):
    """A command was called with arguments that do not fit."""


class InputError(OacError):
    """A file could not be read: missing, undecodable, truncated or corrupt."""


class LanguageError(OacError):
    """The ``.oac`` text or library is invalid (carries diagnostics).

    ``diagnostics`` holds every :class:`oacdsl.compiler.Diagnostic` found, sorted by
    position; ``rendered`` the full report (source lines, carets, notes). The str
    of the error is the first error's line ``file:line:col: error[CODE]: message``.
    """

    exit_code = 1

    def __init__(
        self,
        message: str,
        *,
        location: str | None = None,
        diagnostics: Sequence[Any] = (),
        rendered: str | None = None,
    ) -> None:
        super().__init__(message, location=location)
        self.diagnostics: tuple[Any, ...] = tuple(diagnostics)
        self.rendered: str = rendered if rendered is not None else str(self)


class SourceEncodingError(LanguageError):
    """A ``.oac`` file is not UTF-8 text: a diagnostic (E024, at the first bad byte) like a
    language error, but exit status 2 like any input that cannot be read."""

    exit_code = 2


class RecordingError(InputError):
    """A motion-capture recording is unreadable or inconsistent."""


class InvalidRecording(RecordingError):
    """A recording's content is wrong (input error, exit 1): a bad rate, frame or time column,
    non-finite or implausible coordinates, too large to read, truncated.

    The message names the file and where in it (byte offset, line, frame).
    """

    exit_code = 1


class TruncatedRecording(InvalidRecording):
    """A recording ends before its declared frames: ``declared`` frames, ``complete`` present."""

    def __init__(
        self, message: str, *, location: str | None = None, declared: int = 0, complete: int = 0
    ) -> None:
        super().__init__(message, location=location)
        self.declared = declared
        self.complete = complete


class RecordingWarning(UserWarning):
    """A recording was read, but something in it deserves a look (e.g. fewer frames than declared)."""


class ResultError(InputError):
    """A result document (``result.json``) is JSON but not a valid result: a field missing, of the
    wrong type, or out of range (fidelity above 1, an index past its list, nesting too deep)."""

    exit_code = 1


class SegmentationError(OacError):
    """Segmentation parameters or inputs are invalid."""


class MatchingError(OacError):
    """A sub-action could not be matched or a composition is unsound."""

    exit_code = 1


class PlanningError(OacError):
    """A planning task cannot be built or solved: a planner is missing, or no plan exists."""

    exit_code = 1


class RuntimeFailure(OacError):
    """Execution on the simulated robot failed (unreachable target, force limit, …)."""

    exit_code = 1


class StoreError(OacError):
    """The run store (SQLite database of run outcomes) is unusable: foreign, newer, unreadable."""


def did_you_mean(name: str, valid: object) -> str:
    """Return `` (did you mean 'x'?)`` or a list of the valid names, for messages."""
    import difflib

    names = sorted(str(v) for v in valid)  # type: ignore[attr-defined]
    close = difflib.get_close_matches(name, names, n=1)
    if close:
        return f" (did you mean '{close[0]}'?)"
    if not names:
        return ""
    shown = ", ".join(names[:12]) + (", …" if len(names) > 12 else "")
    return f" (valid: {shown})"
