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

from oacdsl.errors import RecordingError
from oacdsl.segmentation.grouping import prefix_groups
from oacdsl.segmentation.readers._common import metres_per_unit, rate_from_times
from oacdsl.segmentation.readers.qualisys_tsv import parse_table, read_text
from oacdsl.segmentation.recording import Recording

__all__ = ["read_csv"]

_AXIS = re.compile(r"^(?P<marker>.+?)(?:[_.]| )(?P<axis>[xyz])$", re.IGNORECASE)
_META = re.compile(r"^#\s*(?P<key>[a-z_]+)\s*[:=]\s*(?P<value>\S+)\s*$", re.IGNORECASE)


def read_csv(path: str | Path, units: str | None = None) -> Recording:
    """Read the plain CSV layout described in this module into a :class:`Recording`."""
    path = Path(path)
    location = str(path)
    lines = read_text(path)
    meta: dict[str, str] = {}
    i = 0
    while i < len(lines) and (lines[i].startswith("#") or not lines[i].strip()):
        match = _META.match(lines[i].strip())
        if match:
            meta[match["key"].lower()] = match["value"]
        i += 1
    if i == len(lines):
        raise RecordingError("no header row (expected frame,time,<marker>_x,…)", location=location)
    parsed = list(csv.reader(lines[i:]))
    header = [h.strip() for h in parsed[0]]
    to_m = metres_per_unit(units or meta.get("units", "m"), location)

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
            raise RecordingError(
                f"line {i + 1}: column {name!r} is not frame, time or <marker>_x/_y/_z", location=location
            )
    incomplete = [m for m, a in axes.items() if set(a) != {"x", "y", "z"}]
    if incomplete:
        raise RecordingError(f"line {i + 1}: marker {incomplete[0]!r} lacks some of its _x, _y, _z columns",
                             location=location)
    if not axes:
        raise RecordingError(f"line {i + 1}: no marker columns (<marker>_x, _y, _z)", location=location)
    rows = [(i + 1 + k, r) for k, r in enumerate(parsed) if k and any(f.strip() for f in r)]
    if not rows:
        raise RecordingError("the recording has no frames", location=location)
    table = parse_table(rows, len(header), location)

    names = tuple(axes)
    order = [axes[m][a] for m in names for a in "xyz"]
    positions = table[:, order].reshape(len(rows), len(names), 3) * to_m
    positions[np.isnan(positions).any(axis=-1)] = np.nan  # a partial point is a gap
    if "rate_hz" in meta:
        try:
            rate = float(meta["rate_hz"])
        except ValueError:
            rate = float("nan")
        if not rate > 0:
            raise RecordingError(f"rate_hz {meta['rate_hz']!r} is not a positive number", location=location)
    elif time_col is not None:
        rate = rate_from_times(table[:, time_col], location)
    else:
        raise RecordingError("no time column and no '# rate_hz:' line: the frame rate is unknown",
                             location=location)
    times = table[:, time_col] - table[0, time_col] if time_col is not None else np.arange(len(rows)) / rate
    if not np.all(np.isfinite(times)):
        raise RecordingError("the time column has empty or non-numeric entries", location=location)
    first = 0
    if frame_col is not None:
        if not np.isfinite(table[0, frame_col]):
            raise RecordingError(f"line {rows[0][0]}: empty frame number", location=location)
        first = int(table[0, frame_col])
    index = {n: k for k, n in enumerate(names)}
    groups = {g: tuple(index[n] for n in members) for g, members in prefix_groups(names).items()}
    return Recording(location, rate, times, names, positions, groups, first)
