"""The bounds every reader enforces at its boundary, before and after reading a recording.

A recording is refused, with one :class:`~oacdsl.errors.InvalidRecording` (exit 1)
naming the file and where in it (byte, line, frame), when

- its frame rate is not finite or outside :data:`MIN_RATE_HZ` … :data:`MAX_RATE_HZ`;
- a frame number is not a whole number in ``±MAX_FRAME_NUMBER`` or the numbers do not
  increase; a frame time is not a finite number, does not increase, or the recording
  spans more than :data:`MAX_DURATION_S`;
- a coordinate is infinite or farther than :data:`MAX_COORDINATE_M` from the origin on an
  axis (NaN stays a gap);
- it needs more than :data:`MAX_POSITION_BYTES` for its positions
  (frames × markers × 3 × 8 bytes) or holds more than :data:`MAX_MARKERS` markers,
  checked before the array is allocated; or the file is larger than :data:`MAX_FILE_BYTES`.

What is not a regular file (a folder, ``/dev/zero``, a FIFO, a socket) is refused before
it is opened for reading (:class:`~oacdsl.errors.RecordingError`, exit 2): reading it
would never end. ``docs/readers.md`` lists the same limits.
"""

from __future__ import annotations

import math
import os
import stat
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import BinaryIO

import numpy as np

from oacdsl.errors import InvalidRecording, RecordingError

__all__ = [
    "MAX_COORDINATE_M",
    "MAX_DURATION_S",
    "MAX_FILE_BYTES",
    "MAX_FRAME_NUMBER",
    "MAX_MARKERS",
    "MAX_POSITION_BYTES",
    "MAX_RATE_HZ",
    "MIN_RATE_HZ",
    "check_coordinates",
    "check_frame_numbers",
    "check_rate",
    "check_regular",
    "check_size",
    "check_times",
    "clip",
    "open_regular",
    "read_regular",
]

MIN_RATE_HZ = 1.0  # Hz; slower is not motion capture
MAX_RATE_HZ = 10_000.0  # Hz; faster than any marker system (high-speed Vicon: 2 kHz)
MAX_COORDINATE_M = 1e4  # metres (10 km): a millimetre file read as metres (~2 km) still passes
MAX_POSITION_BYTES = 1 << 30  # bytes (1 GiB) for frames × markers × 3 float64 coordinates
MAX_MARKERS = 10_000  # markers in one recording (a full-body set has ~60)
MAX_FILE_BYTES = 1 << 30  # bytes (1 GiB): a recording file larger than this is refused
MAX_FRAME_NUMBER = 2**31 - 1  # the file's own frame numbers
MAX_DURATION_S = 1e6  # seconds (11.6 days) from the first frame to the last

_KINDS = [
    (stat.S_ISDIR, "a folder"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISSOCK, "a socket"),
]  # anything else: "a special file"

Label = Callable[[int], str]


_SHOWN = 40  # characters of an input value shown in a message


def clip(text: str, limit: int = _SHOWN, *, quoted: bool = True) -> str:
    """``repr(text)`` (or ``text``), clipped to ``limit`` characters, with its length when longer:
    a 6 MB field is not echoed whole into a message."""
    show = repr if quoted else str
    if len(text) <= limit:
        return show(text)
    return f"{show(text[:limit])}… ({len(text)} characters)"


def _kind(mode: int) -> str:
    return next((name for test, name in _KINDS if test(mode)), "a special file")


def check_regular(path: Path) -> None:
    """Refuse, without opening it, what is not a regular file of at most MAX_FILE_BYTES."""
    location = str(path)
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise RecordingError("no such file", location=location) from None
    except OSError as err:
        raise RecordingError(f"cannot read: {err.strerror or err}", location=location) from None
    if not stat.S_ISREG(info.st_mode):
        raise RecordingError(f"is {_kind(info.st_mode)}, not a recording file", location=location)
    _check_file_size(info.st_size, location)


def open_regular(path: Path) -> BinaryIO:
    """Open ``path`` for reading once it is known to be a regular file of at most MAX_FILE_BYTES.

    The type is checked before opening (opening a FIFO would wait for a writer) and
    again on the open descriptor (the path may have been replaced in between).
    """
    location = str(path)
    check_regular(path)
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as err:
        raise RecordingError(f"cannot read: {err.strerror or err}", location=location) from None
    info = os.fstat(fd)
    if not stat.S_ISREG(info.st_mode):
        os.close(fd)
        raise RecordingError(f"is {_kind(info.st_mode)}, not a recording file", location=location)
    _check_file_size(info.st_size, location)
    return os.fdopen(fd, "rb")


def read_regular(path: Path) -> bytes:
    """The bytes of the regular file ``path`` (see :func:`open_regular`)."""
    with open_regular(path) as fh:
        try:
            return fh.read(MAX_FILE_BYTES + 1)
        except OSError as err:
            raise RecordingError(f"cannot read: {err.strerror or err}", location=str(path)) from None


def _check_file_size(size: int, location: str) -> None:
    if size > MAX_FILE_BYTES:
        raise InvalidRecording(
            f"the file is {size / 2**30:.1f} GiB, more than the limit of {MAX_FILE_BYTES / 2**30:g} GiB",
            location=location,
        )


def check_rate(rate_hz: float, location: str, what: str = "frame rate") -> float:
    """``rate_hz`` when finite and within MIN_RATE_HZ … MAX_RATE_HZ (Hz), else an error."""
    if not (math.isfinite(rate_hz) and MIN_RATE_HZ <= rate_hz <= MAX_RATE_HZ):
        raise InvalidRecording(
            f"{what} is {rate_hz:g} Hz; a recording's rate must lie within"
            f" {MIN_RATE_HZ:g}..{MAX_RATE_HZ:g} Hz",
            location=location,
        )
    return float(rate_hz)


def check_size(frames: int, markers: int, location: str, *, extra_values: int = 0) -> None:
    """Refuse a recording whose positions need more than MAX_POSITION_BYTES (before allocating them).

    Positions take ``frames × markers × 3 × 8`` bytes; ``extra_values`` counts further
    float64 values read with them (a C3D file's analog samples).
    """
    if markers > MAX_MARKERS:
        raise InvalidRecording(f"{markers} markers, more than the limit of {MAX_MARKERS}", location=location)
    needed = (frames * markers * 3 + extra_values) * 8  # bytes of float64
    if needed > MAX_POSITION_BYTES:
        extra = " (with its analog samples)" if extra_values else ""
        raise InvalidRecording(
            f"{frames} frames × {markers} markers need {needed / 2**30:.1f} GiB{extra}, more than the limit"
            f" of {MAX_POSITION_BYTES / 2**30:g} GiB",
            location=location,
        )


def check_frame_numbers(numbers: np.ndarray, location: str, label: Label) -> None:
    """The file's frame numbers: whole, within ±MAX_FRAME_NUMBER, strictly increasing."""
    ok = np.isfinite(numbers) & (np.abs(numbers) <= MAX_FRAME_NUMBER)
    ok[ok] = numbers[ok] == np.round(numbers[ok])
    if not ok.all():
        i = int(np.flatnonzero(~ok)[0])
        raise InvalidRecording(
            f"{label(i)}: frame number {_show(numbers[i])} is not a whole number within ±{MAX_FRAME_NUMBER}",
            location=location,
        )
    steps = np.diff(numbers)
    if (steps <= 0).any():
        i = int(np.flatnonzero(steps <= 0)[0]) + 1
        raise InvalidRecording(
            f"{label(i)}: frame number {numbers[i]:.0f} does not follow {numbers[i - 1]:.0f}",
            location=location,
        )


def check_times(times_s: np.ndarray, location: str, label: Label) -> None:
    """Frame times (s): numbers, strictly increasing, spanning at most MAX_DURATION_S."""
    finite = np.isfinite(times_s)
    if not finite.all():
        i = int(np.flatnonzero(~finite)[0])
        raise InvalidRecording(f"{label(i)}: time {_show(times_s[i])} is not a number", location=location)
    steps = np.diff(times_s)
    if (steps <= 0).any():
        i = int(np.flatnonzero(steps <= 0)[0]) + 1
        raise InvalidRecording(
            f"{label(i)}: time {times_s[i]:g} s does not follow {times_s[i - 1]:g} s"
            " (frame times must increase)",
            location=location,
        )
    if times_s.size and times_s[-1] - times_s[0] > MAX_DURATION_S:
        raise InvalidRecording(
            f"the recording spans {times_s[-1] - times_s[0]:g} s, more than the limit"
            f" of {MAX_DURATION_S:g} s",
            location=location,
        )


def check_coordinates(positions_m: np.ndarray, names: Sequence[str], location: str, label: Label) -> None:
    """(F, M, 3) metres: each coordinate NaN (a gap) or finite within ±MAX_COORDINATE_M."""
    bad = ~(np.abs(positions_m) <= MAX_COORDINATE_M) & ~np.isnan(positions_m)
    if bad.any():
        frame, marker, axis = (int(v) for v in np.argwhere(bad)[0])
        value = positions_m[frame, marker, axis]
        raise InvalidRecording(
            f"{label(frame)}: marker {clip(names[marker])} has {'xyz'[axis]} = {_show(value)} m; a coordinate"
            f" must be finite and within ±{MAX_COORDINATE_M:g} m (NaN or an empty field is a gap)",
            location=location,
        )


def _show(value: float) -> str:
    return "NaN" if math.isnan(value) else f"{value:g}"
