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

The ``units`` argument overrides the ``# units:`` line.
"""

from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np

from oacdsl.errors import InvalidRecording
from oacdsl.segmentation.grouping import prefix_groups
from oacdsl.segmentation.readers._common import metres_per_unit, rate_from_times
from oacdsl.segmentation.readers.limits import (
    check_coordinates,
    check_frame_numbers,
    check_rate,
    check_size,
    check_times,
)
from oacdsl.segmentation.readers.qualisys_tsv import line_label, parse_table, read_text
from oacdsl.segmentation.recording import Recording

__all__ = ["read_csv"]

_AXIS = re.compile(r"^(?P<marker>.+?)(?:[_.]| )(?P<axis>[xyz])$", re.IGNORECASE)
_META = re.compile(r"^#\s*(?P<key>[a-z_]+)\s*[:=]\s*(?P<value>\S+)\s*$", re.IGNORECASE)


def _split(line: str, line_no: int, location: str) -> list[str]:
    """The fields of one line: a quote never joins lines (a recording's fields hold no line breaks)."""
    try:
        return next(csv.reader((line,)))
    except csv.Error as err:
        raise InvalidRecording(f"line {line_no}: {err}", location=location) from None


def read_csv(path: str | Path, units: str | None = None) -> Recording:
    """Read the plain CSV layout described in this module into a :class:`Recording` (limits.py checked)."""
    path = Path(path)
    location = str(path)
    lines = read_text(path)
    meta: dict[str, tuple[int, str]] = {}
    i = 0
    while i < len(lines) and (lines[i].startswith("#") or not lines[i].strip()):
        match = _META.match(lines[i].strip())
        if match:
            meta[match["key"].lower()] = (i + 1, match["value"])
        i += 1
    if i == len(lines):
        raise InvalidRecording("no header row (expected frame,time,<marker>_x,…)", location=location)
    header = [h.strip() for h in _split(lines[i], i + 1, location)]
    to_m = metres_per_unit(units or meta.get("units", (0, "m"))[1], location)
    check_size(0, len(header) // 3, location)  # before the columns are sorted out

    frame_col = time_col = None
    axes: dict[str, dict[str, int]] = {}
    for c, name in enumerate(header):
        low = name.lower()
        if low == "frame":
            frame_col = c
        elif low in ("time", "time_s"):
            time_col = c
        elif match := _AXIS.match(name):
            axes.setdefault(match["marker"], {})[match["axis"].lower()] = c
        else:
            raise InvalidRecording(
                f"line {i + 1}: column {name!r} is not frame, time or <marker>_x/_y/_z", location=location
            )
    incomplete = [m for m, a in axes.items() if set(a) != {"x", "y", "z"}]
    if incomplete:
        raise InvalidRecording(
            f"line {i + 1}: marker {incomplete[0]!r} lacks some of its _x, _y, _z columns", location=location
        )
    if not axes:
        raise InvalidRecording(f"line {i + 1}: no marker columns (<marker>_x, _y, _z)", location=location)
    text_rows = [(i + 2 + k, line) for k, line in enumerate(lines[i + 1 :]) if line.strip()]
    if not text_rows:
        raise InvalidRecording("the recording has no frames", location=location)
    check_size(len(text_rows), len(axes), location, extra_values=2 * len(text_rows))
    rows = [(n, _split(t, n, location)) for n, t in text_rows]
    table = parse_table(rows, len(header), location)
    label = line_label(rows)

    names = tuple(axes)
    order = [axes[m][a] for m in names for a in "xyz"]
    positions = table[:, order].reshape(len(rows), len(names), 3) * to_m
    check_coordinates(positions, names, location, label)
    positions[np.isnan(positions).any(axis=-1)] = np.nan  # a partial point is a gap
    if "rate_hz" in meta:
        line, value = meta["rate_hz"]
        try:
            rate = float(value)
        except ValueError:
            raise InvalidRecording(
                f"line {line}: rate_hz {value!r} is not a number", location=location
            ) from None
        check_rate(rate, location, f"line {line}: rate_hz")
        if time_col is not None:
            check_times(table[:, time_col], location, label)
    elif time_col is not None:
        rate = rate_from_times(table[:, time_col], location, label)
    else:
        raise InvalidRecording(
            "no time column and no '# rate_hz:' line: the frame rate is unknown", location=location
        )
    times = table[:, time_col] - table[0, time_col] if time_col is not None else np.arange(len(rows)) / rate
    first = 0
    if frame_col is not None:
        check_frame_numbers(table[:, frame_col], location, label)
        first = int(table[0, frame_col])
    index = {n: k for k, n in enumerate(names)}
    groups = {g: tuple(index[n] for n in members) for g, members in prefix_groups(names).items()}
    return Recording(location, rate, times, names, positions, groups, first)
