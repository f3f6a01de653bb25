"""Qualisys Track Manager (QTM) TSV exports of 3D marker data.

The file starts with tab-separated ``KEY<TAB>value…`` lines (``NO_OF_FRAMES``,
``FREQUENCY``, ``NO_OF_MARKERS``, ``MARKER_NAMES``, …), then, in newer QTM
versions, a column header (``Frame  Time  <marker> X  <marker> Y  <marker> Z …``),
then one row per frame. Rows may end with a tab. A gap is an empty field, ``nan``,
or a point whose three coordinates are exactly 0 (what older QTM versions write).
Positions are millimetres unless ``units`` says otherwise. ``first_frame`` is the
first value of the ``Frame`` column (QTM counts from 1). Groups: by name prefix
(``pillow_top`` → ``pillow``; see :func:`~oacdsl.segmentation.grouping.prefix_groups`).
The file is read in bounded memory (:mod:`~oacdsl.segmentation.readers.textrows`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from oacdsl.errors import InvalidRecording
from oacdsl.segmentation.grouping import prefix_groups
from oacdsl.segmentation.readers._common import clip, metres_per_unit, rate_from_times, unique_names
from oacdsl.segmentation.readers.limits import (
    check_coordinates,
    check_frame_numbers,
    check_rate,
    check_size,
    check_times,
)
from oacdsl.segmentation.readers.textrows import Lines, read_rows, scan_text
from oacdsl.segmentation.recording import Recording

__all__ = ["read_tsv"]


def _fields(line: str, _line_no: int = 0) -> list[str]:
    fields = line.split("\t")
    if len(fields) > 1 and fields[-1].strip() == "":
        fields.pop()  # the trailing tab QTM writes
    return fields


def _number(text: str, what: str, line_no: int, location: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise InvalidRecording(
            f"line {line_no}: {what} {clip(text)} is not a number", location=location
        ) from None


def _is_number(text: str) -> bool:
    """Whether ``text`` reads as a float (``nan`` and ``inf`` too): a data row, not a header key."""
    try:
        float(text)
    except ValueError:
        return False
    return True


def _header(lines: Lines, location: str) -> tuple[dict[str, tuple[int, list[str]]], int]:
    """The ``KEY<TAB>value…`` lines: KEY → (line number, values); and how many lines they took."""
    header: dict[str, tuple[int, list[str]]] = {}
    taken = 0
    while (line := lines.peek()) is not None:
        fields = _fields(line[1])
        key = fields[0].strip()
        if not key or _is_number(key) or key.lower() == "frame":
            break
        header[key.upper()] = (line[0], [f.strip() for f in fields[1:]])
        next(lines)
        taken += 1
    for key in ("NO_OF_FRAMES", "NO_OF_MARKERS", "FREQUENCY"):
        if key in header and not (header[key][1] and header[key][1][0]):
            raise InvalidRecording(f"line {header[key][0]}: {key} has no value", location=location)
    return header, taken


def _first_data_line(lines: Lines) -> tuple[int, str] | None:
    """Skip blank lines; the first data line, not taken."""
    while (line := lines.peek()) is not None and not line[1].strip():
        next(lines)
    return line


def read_tsv(path: str | Path, units: str = "mm", *, allow_truncated: bool = False) -> Recording:
    """Read a QTM TSV export into a :class:`Recording` (metres, NaN gaps; limits.py checked).

    A file cut inside its last line is a :class:`~oacdsl.errors.TruncatedRecording`
    unless ``allow_truncated`` (that line is left out, with a warning).
    """
    path = Path(path)
    location = str(path)
    to_m = metres_per_unit(units, location)
    text = scan_text(path)
    lines = Lines(text, allow_truncated=allow_truncated)
    header, taken = _header(lines, location)
    if "MARKER_NAMES" not in header:
        raise InvalidRecording("not a Qualisys TSV export: no MARKER_NAMES line", location=location)
    n_markers = len(header["MARKER_NAMES"][1])
    check_size(0, n_markers, location)
    names = unique_names(header["MARKER_NAMES"][1], "marker")
    if not n_markers:
        raise InvalidRecording(
            f"line {header['MARKER_NAMES'][0]}: MARKER_NAMES lists no markers", location=location
        )
    if "NO_OF_MARKERS" in header and header["NO_OF_MARKERS"][1][0] != str(n_markers):
        line, value = header["NO_OF_MARKERS"][0], header["NO_OF_MARKERS"][1][0]
        raise InvalidRecording(
            f"line {line}: NO_OF_MARKERS is {clip(value, quoted=False)} but MARKER_NAMES lists {n_markers}",
            location=location,
        )
    has_frame_time = False
    first = _first_data_line(lines)
    if first is not None and _fields(first[1])[0].strip().lower() == "frame":
        columns = [c.strip().lower() for c in _fields(first[1])]
        has_frame_time = columns[:2] == ["frame", "time"]
        next(lines)
        taken += 1
        first = _first_data_line(lines)
    width = 3 * n_markers + (2 if has_frame_time else 0)
    if first is not None and not has_frame_time and len(_fields(first[1])) == 3 * n_markers + 2:
        has_frame_time, width = True, 3 * n_markers + 2  # no column header, but Frame and Time columns
    capacity = text.nonblank - taken  # data rows at most
    check_size(capacity, n_markers, location, extra_values=2 * capacity)
    positions = np.empty((max(capacity, 0), n_markers, 3))
    lead = np.empty((max(capacity, 0), 2))  # Frame and Time columns
    line_of = np.empty(max(capacity, 0), dtype=np.int64)

    def take(row: int, numbers: np.ndarray, values: np.ndarray) -> None:
        k = len(numbers)
        line_of[row : row + k] = numbers
        block = positions[row : row + k]
        block[...] = (values[:, 2:] if has_frame_time else values).reshape(k, n_markers, 3)
        block *= to_m
        check_coordinates(block, names, location, lambda i: f"line {numbers[i]}")
        block[np.all(block == 0.0, axis=-1) | np.isnan(block).any(axis=-1)] = np.nan
        if has_frame_time:
            lead[row : row + k] = values[:, :2]

    n = read_rows(lines, _fields, width, capacity, take, sep="\t", trailing_sep=True)
    if not n:
        raise InvalidRecording("the recording has no frames", location=location)
    positions, lead, line_of = positions[:n], lead[:n], line_of[:n]
    if "NO_OF_FRAMES" in header and header["NO_OF_FRAMES"][1][0] != str(n + lines.dropped):
        line, value = header["NO_OF_FRAMES"][0], header["NO_OF_FRAMES"][1][0]
        raise InvalidRecording(
            f"line {line}: NO_OF_FRAMES is {clip(value, quoted=False)} but the file holds {n} data rows",
            location=location,
        )

    def label(i: int) -> str:
        return f"line {line_of[i]}"

    if has_frame_time:
        check_frame_numbers(lead[:, 0], location, label)
    if "FREQUENCY" in header:
        line, value = header["FREQUENCY"][0], header["FREQUENCY"][1][0]
        rate = check_rate(_number(value, "FREQUENCY", line, location), location, f"line {line}: FREQUENCY")
        if has_frame_time:
            check_times(lead[:, 1], location, label)
        times = lead[:, 1] - lead[0, 1] if has_frame_time else np.arange(n) / rate
    elif has_frame_time:
        times = lead[:, 1] - lead[0, 1]
        rate = rate_from_times(lead[:, 1], location, label)
    else:
        raise InvalidRecording(
            "no FREQUENCY line and no Time column: the frame rate is unknown", location=location
        )
    first_frame = int(lead[0, 0]) if has_frame_time else 0
    groups = prefix_groups(names)
    index = {name: k for k, name in enumerate(names)}
    by_index = {g: tuple(index[name] for name in members) for g, members in groups.items()}
    return Recording(location, float(rate), times, names, positions, by_index, first_frame)
