"""Qualisys Track Manager (QTM) TSV exports of 3D marker data.

The file starts with tab-separated ``KEY<TAB>value…`` lines (``NO_OF_FRAMES``,
``FREQUENCY``, ``NO_OF_MARKERS``, ``MARKER_NAMES``, …), then, in newer QTM
versions, a column header (``Frame  Time  <marker> X  <marker> Y  <marker> Z …``),
then one row per frame. Rows may end with a tab. A gap is an empty field, ``nan``,
or a point whose three coordinates are exactly 0 (what older QTM versions write).
Positions are millimetres unless ``units`` says otherwise. ``first_frame`` is the
first value of the ``Frame`` column (QTM counts from 1). Groups: by name prefix
(``pillow_top`` → ``pillow``; see :func:`~oacdsl.segmentation.grouping.prefix_groups`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from oacdsl.errors import RecordingError
from oacdsl.segmentation.grouping import prefix_groups
from oacdsl.segmentation.readers._common import metres_per_unit, rate_from_times, unique_names
from oacdsl.segmentation.recording import Recording

__all__ = ["read_tsv", "read_text"]


def read_text(path: Path) -> list[str]:
    """The file's lines (UTF-8, else Latin-1), without line ends."""
    try:
        raw = path.read_bytes()
    except OSError as err:
        raise RecordingError(f"cannot read: {err.strerror or err}", location=str(path)) from None
    if b"\x00" in raw[:4096]:
        raise RecordingError("binary data in a text recording", location=str(path))
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    return text.splitlines()


def _fields(line: str) -> list[str]:
    fields = line.split("\t")
    if len(fields) > 1 and fields[-1].strip() == "":
        fields.pop()  # the trailing tab QTM writes
    return fields


def _number(text: str, what: str, line_no: int, location: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise RecordingError(f"line {line_no}: {what} {text!r} is not a number", location=location) from None


def parse_table(rows: list[tuple[int, list[str]]], width: int, location: str) -> np.ndarray:
    """(rows, width) floats from text fields; an empty field or ``nan`` is NaN.

    ``rows`` holds (1-based line number, fields); a row of another width or a
    field that is not a number is an error naming its line.
    """
    flat: list[str] = []
    for line_no, fields in rows:
        if len(fields) != width:
            raise RecordingError(f"line {line_no}: {len(fields)} fields, expected {width}", location=location)
        flat.extend(f.strip() or "nan" for f in fields)
    try:
        table = np.array(flat, dtype=np.float64).reshape(len(rows), width)
    except ValueError:
        for line_no, fields in rows:  # find the culprit for the message
            for text in fields:
                _number(text.strip() or "nan", "value", line_no, location)
        raise RecordingError("unreadable numbers", location=location) from None
    bad = np.argwhere(np.isinf(table))
    if bad.size:
        raise RecordingError(f"line {rows[bad[0][0]][0]}: infinite value", location=location)
    return table


def read_tsv(path: str | Path, units: str = "mm") -> Recording:
    """Read a QTM TSV export into a :class:`Recording` (metres, NaN gaps)."""
    path = Path(path)
    location = str(path)
    to_m = metres_per_unit(units, location)
    lines = read_text(path)
    header: dict[str, list[str]] = {}
    i = 0
    while i < len(lines):
        fields = _fields(lines[i])
        key = fields[0].strip()
        if not key or key[0].isdigit() or key[0] in "-." or key.lower() == "frame":
            break
        header[key.upper()] = [f.strip() for f in fields[1:]]
        i += 1
    if "MARKER_NAMES" not in header:
        raise RecordingError("not a Qualisys TSV export: no MARKER_NAMES line", location=location)
    names = unique_names(header["MARKER_NAMES"], "marker")
    n_markers = len(names)
    if not n_markers:
        raise RecordingError("MARKER_NAMES lists no markers", location=location)
    declared_markers = header.get("NO_OF_MARKERS", [str(n_markers)])[0]
    if declared_markers != str(n_markers):
        raise RecordingError(f"NO_OF_MARKERS is {declared_markers} but MARKER_NAMES lists {n_markers}",
                             location=location)
    has_frame_time = False
    if i < len(lines) and _fields(lines[i])[0].strip().lower() == "frame":
        columns = [c.strip().lower() for c in _fields(lines[i])]
        has_frame_time = columns[:2] == ["frame", "time"]
        i += 1
    rows = [(n + 1, lines[n]) for n in range(i, len(lines)) if lines[n].strip()]
    width = 3 * n_markers + (2 if has_frame_time else 0)
    if rows and not has_frame_time and len(_fields(rows[0][1])) == 3 * n_markers + 2:
        has_frame_time, width = True, 3 * n_markers + 2  # no column header, but Frame and Time columns
    if not rows:
        raise RecordingError("the recording has no frames", location=location)
    table = parse_table([(n, _fields(line)) for n, line in rows], width, location)
    declared = header.get("NO_OF_FRAMES", [""])[0]
    if declared and declared != str(len(rows)):
        raise RecordingError(f"NO_OF_FRAMES is {declared} but the file holds {len(rows)} data rows",
                             location=location)
    xyz = table[:, 2:] if has_frame_time else table
    positions = xyz.reshape(len(rows), n_markers, 3).copy()
    positions[np.all(positions == 0.0, axis=-1) | np.isnan(positions).any(axis=-1)] = np.nan
    frequency = header.get("FREQUENCY", [""])[0]
    if frequency:
        rate = _number(frequency, "FREQUENCY", list(header).index("FREQUENCY") + 1, location)
        if not rate > 0:
            raise RecordingError(f"FREQUENCY is {frequency}", location=location)
        times = table[:, 1] - table[0, 1] if has_frame_time else np.arange(len(rows)) / rate
    elif has_frame_time:
        times = table[:, 1] - table[0, 1]
        rate = rate_from_times(times, location)
    else:
        raise RecordingError("no FREQUENCY line and no Time column: the frame rate is unknown",
                             location=location)
    first = int(table[0, 0]) if has_frame_time else 0
    groups = prefix_groups(names)
    index = {n: k for k, n in enumerate(names)}
    by_index = {g: tuple(index[n] for n in members) for g, members in groups.items()}
    return Recording(location, float(rate), times, names, positions * to_m, by_index, first)
