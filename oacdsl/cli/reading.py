"""Reading a recording on the command line: the options, the warnings, the windows' bounds.

``inspect``, ``segment``, ``match``, ``compose`` and ``reproduce`` read a recording
the same way: ``--allow-truncated`` (a C3D file that ends before its declared frames
is an error unless given), reader warnings printed as ``oacc: warning: …`` lines,
and ``--frames`` / ``--merge`` checked against the recording's length.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

__all__ = [
    "ALLOW_TRUNCATED_HELP",
    "add_reading_options",
    "check_windows",
    "printed_warnings",
    "allow_truncated",
]

ALLOW_TRUNCATED_HELP = (
    "read a C3D file that ends before its declared frames (cut short, or a writer that stopped):"
    " a warning naming the frames lost, and the complete frames; without it, such a file is an error"
)


def add_reading_options(group: Any) -> None:
    """``--allow-truncated`` (read by :func:`allow_truncated`)."""
    group.add_argument("--allow-truncated", action="store_true", help=ALLOW_TRUNCATED_HELP)


def allow_truncated(args: argparse.Namespace) -> bool:
    """Whether the command line accepts a truncated recording."""
    return bool(getattr(args, "allow_truncated", False))


@contextmanager
def printed_warnings() -> Iterator[None]:
    """Reader warnings (:class:`~oacdsl.errors.RecordingWarning`) as ``oacc: warning: …`` lines on stderr."""
    from oacdsl.errors import RecordingWarning

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", RecordingWarning)
        yield
    for w in caught:
        if issubclass(w.category, RecordingWarning):
            print(f"oacc: warning: {w.message}", file=sys.stderr)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)


def check_windows(args: argparse.Namespace, recording: Any) -> None:
    """``--frames``, ``--hold``, ``--change-window`` and ``--merge``, when given, must fit in the
    recording (a usage error otherwise).

    A window of more frames than the recording holds can never be complete, and one
    that large would be allocated before anything else (``--frames 1e12``: 1.8 TiB);
    a merge window longer than the recording merges every keyframe into one.
    """
    from oacdsl.errors import UsageError
    from oacdsl.units import parse_quantity

    frames = getattr(args, "frames", None)
    if frames is not None and parse_quantity(frames, "frames", what="--frames") > recording.n_frames:
        raise UsageError(
            f"--frames {frames}: more than the recording's {recording.n_frames} frames",
            location=recording.source,
        )
    merge = getattr(args, "merge", None)
    duration_s = float(recording.times_s[-1])
    if merge is not None and parse_quantity(merge, "s", what="--merge") > duration_s:
        raise UsageError(
            f"--merge {merge}: longer than the recording ({duration_s:g} s)", location=recording.source
        )
    for option, attr in (("--hold", "hold"), ("--change-window", "change_window")):  # n and the slope window
        value = getattr(args, attr, None)
        if value is not None and parse_quantity(value, "s", what=option) > duration_s:
            raise UsageError(
                f"{option} {value}: longer than the recording ({duration_s:g} s)", location=recording.source
            )
