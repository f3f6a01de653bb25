"""A plain CSV layout for marker trajectories, for data from any other tool.

Accepted layout (comma-separated, one header row, one row per frame)::

    # units: mm          optional comment lines before the header:
    # rate_hz: 100       units (mm, cm, m; default m) and frame rate (Hz)
    frame,time,hand_x,hand_y,hand_z,cup_1_x,cup_1_y,cup_1_z
    0,0.00,412.0,18.5,903.1,500.2,20.0,880.0
    1,0.01,412.3,,,500.2,20.1,880.0

* ``frame`` (optional): the file's frame numbers; the first one is ``first_frame``.
* ``time`` or ``time_s`` (optional): seconds; the rate is the inverse of the median
  step unless ``# rate_hz:`` gives it. Without either, the rate is an error.
* Every other column is ``<marker>_x``, ``_y``, ``_z`` (also ``.x`` or `` X``; case
  does not matter); each marker needs all three, in any column order.
* A gap is an empty field or ``nan`` (one missing coordinate blanks the point).
* Groups: by name prefix (``cup_1`` → ``cup``).

The ``units`` argument overrides the ``# units:`` line. A column named twice is an
error (one would hide the other). The file is read in bounded memory
(:mod:`~oacdsl.segmentation.readers.textrows`).
"""

from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np

from oacdsl.errors import InvalidRecording
from oacdsl.segmentation.grouping import prefix_groups
from oacdsl.segmentation.readers._common import clip, metres_per_unit, rate_from_times
from oacdsl.segmentation.readers.limits import (
    check_coordinates,
    check_frame_numbers,
    check_rate,
    check_size,
    check_times,
)
from oacdsl.segmentation.readers.textrows import Lines, read_rows, scan_text
from oacdsl.segmentation.recording import Recording

__all__ = ["read_csv"]

_AXIS = re.compile(r"^(?P<marker>.+?)(?:[_.]| )(?P<axis>[xyz])$", re.IGNORECASE)
_META = re.compile(r"^#\s*(?P<key>[a-z_]+)\s*[:=]\s*(?P<value>\S+)\s*$", re.IGNORECASE)


def _split(line: str, line_no: int, location: str = "") -> list[str]:
    """The fields of one line: a quote never joins lines (a recording's fields hold no line breaks)."""
    if '"' not in line:
        return line.split(",")  # what csv.reader gives for a line without quotes
    try:
        return next(csv.reader((line,)))
    except csv.Error as err:
        raise InvalidRecording(f"line {line_no}: {err}", location=location) from None


Columns = tuple[int | None, int | None, dict[str, dict[str, int]]]


def _columns(header: list[str], line_no: int, location: str) -> Columns:
    """The frame column, the time column and each marker's x, y, z columns (0-based)."""
    frame_col = time_col = None
    axes: dict[str, dict[str, int]] = {}
    seen: dict[tuple[str, str], int] = {}
    for c, name in enumerate(header):
        low = name.lower()
        if low == "frame":
            key = ("frame", "")
        elif low in ("time", "time_s"):
            key = ("time", "")
        elif match := _AXIS.match(name):
            key = (match["marker"], match["axis"].lower())
        else:
            raise InvalidRecording(
                f"line {line_no}: column {clip(name)} is not frame, time or <marker>_x/_y/_z",
                location=location,
            )
        if key in seen:
            what = f"marker {clip(key[0])}'s {key[1]}" if key[1] else f"the {key[0]}"
            raise InvalidRecording(
                f"line {line_no}: columns {seen[key] + 1} and {c + 1} ({clip(header[seen[key]])},"
                f" {clip(name)}) both hold {what}; a column may appear once",
                location=location,
            )
        seen[key] = c
        if key[0] == "frame" and not key[1]:
            frame_col = c
        elif key[0] == "time" and not key[1]:
            time_col = c
        else:
            axes.setdefault(key[0], {})[key[1]] = c
    incomplete = [m for m, a in axes.items() if set(a) != {"x", "y", "z"}]
    if incomplete:
        raise InvalidRecording(
            f"line {line_no}: marker {clip(incomplete[0])} lacks some of its _x, _y, _z columns",
            location=location,
        )
    if not axes:
        raise InvalidRecording(f"line {line_no}: no marker columns (<marker>_x, _y, _z)", location=location)
    return frame_col, time_col, axes


def read_csv(path: str | Path, units: str | None = None, *, allow_truncated: bool = False) -> Recording:
    """Read the plain CSV layout described in this module into a :class:`Recording` (limits.py checked).

    A file cut inside its last line is a :class:`~oacdsl.errors.TruncatedRecording`
    unless ``allow_truncated`` (that line is left out, with a warning).
    """
    path = Path(path)
    location = str(path)
    text = scan_text(path)
    lines = Lines(text, allow_truncated=allow_truncated)
    meta: dict[str, tuple[int, str]] = {}
    taken = 0
    while (line := lines.peek()) is not None and (line[1].startswith("#") or not line[1].strip()):
        match = _META.match(line[1].strip())
        if match:
            meta[match["key"].lower()] = (line[0], match["value"])
        taken += bool(line[1].strip())
        next(lines)
    if line is None:
        raise InvalidRecording("no header row (expected frame,time,<marker>_x,…)", location=location)
    next(lines)
    header_line = line[0]
    header = [h.strip() for h in _split(line[1], header_line, location)]
    to_m = metres_per_unit(units or meta.get("units", (0, "m"))[1], location)
    check_size(0, len(header) // 3, location)  # before the columns are sorted out
    frame_col, time_col, axes = _columns(header, header_line, location)
    names = tuple(axes)
    order = [axes[m][a] for m in names for a in "xyz"]
    capacity = text.nonblank - taken - 1  # data rows at most
    check_size(capacity, len(axes), location, extra_values=2 * capacity)
    positions = np.empty((max(capacity, 0), len(names), 3))
    lead = np.full((max(capacity, 0), 2), np.nan)  # frame and time columns
    line_of = np.empty(max(capacity, 0), dtype=np.int64)

    def take(row: int, numbers: np.ndarray, values: np.ndarray) -> None:
        k = len(numbers)
        line_of[row : row + k] = numbers
        block = positions[row : row + k]
        block[...] = values[:, order].reshape(k, len(names), 3)
        block *= to_m
        check_coordinates(block, names, location, lambda i: f"line {numbers[i]}")
        block[np.isnan(block).any(axis=-1)] = np.nan  # a partial point is a gap
        for j, col in enumerate((frame_col, time_col)):
            if col is not None:
                lead[row : row + k, j] = values[:, col]

    n = read_rows(lines, lambda t, no: _split(t, no, location), len(header), capacity, take, sep=",")
    if not n:
        raise InvalidRecording("the recording has no frames", location=location)
    positions, lead, line_of = positions[:n], lead[:n], line_of[:n]

    def label(i: int) -> str:
        return f"line {line_of[i]}"

    if "rate_hz" in meta:
        line_no, value = meta["rate_hz"]
        try:
            rate = float(value)
        except ValueError:
            raise InvalidRecording(
                f"line {line_no}: rate_hz {clip(value)} is not a number", location=location
            ) from None
        check_rate(rate, location, f"line {line_no}: rate_hz")
        if time_col is not None:
            check_times(lead[:, 1], location, label)
    elif time_col is not None:
        rate = rate_from_times(lead[:, 1], location, label)
    else:
        raise InvalidRecording(
            "no time column and no '# rate_hz:' line: the frame rate is unknown", location=location
        )
    times = lead[:, 1] - lead[0, 1] if time_col is not None else np.arange(n) / rate
    first = 0
    if frame_col is not None:
        check_frame_numbers(lead[:, 0], location, label)
        first = int(lead[0, 0])
    index = {name: k for k, name in enumerate(names)}
    groups = {g: tuple(index[name] for name in members) for g, members in prefix_groups(names).items()}
    return Recording(location, rate, times, names, positions, groups, first)
