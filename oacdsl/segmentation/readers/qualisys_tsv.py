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

from oacdsl.errors import InvalidRecording
from oacdsl.segmentation.grouping import prefix_groups
from oacdsl.segmentation.readers._common import metres_per_unit, rate_from_times, unique_names
from oacdsl.segmentation.readers.limits import (
    Label,
    check_coordinates,
    check_frame_numbers,
    check_rate,
    check_size,
    check_times,
    read_regular,
)
from oacdsl.segmentation.recording import Recording

__all__ = ["line_label", "parse_table", "read_text", "read_tsv"]


def read_text(path: Path) -> list[str]:
    """The file's lines (UTF-8, else Latin-1), without line ends; a regular file only (limits.py)."""
    raw = read_regular(path)
    if b"\x00" in raw[:4096]:
        raise InvalidRecording("binary data in a text recording", location=str(path))
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
        raise InvalidRecording(
            f"line {line_no}: {what} {text!r} is not a number", location=location
        ) from None


_CHUNK_FIELDS = 1 << 20  # fields converted at once: bounds the temporary strings (~60 MB)


def parse_table(rows: list[tuple[int, list[str]]], width: int, location: str) -> np.ndarray:
    """(rows, width) floats from text fields; an empty field or ``nan`` is NaN.

    ``rows`` holds (1-based line number, fields); a row of another width or a
    field that is not a number is an error naming its line. The caller bounds
    ``rows × width`` (:func:`~oacdsl.segmentation.readers.limits.check_size`); the
    text is converted in chunks. Values are not range-checked here.
    """
    table = np.empty((len(rows), width), dtype=np.float64)
    step = max(1, _CHUNK_FIELDS // max(width, 1))
    for start in range(0, len(rows), step):
        chunk = rows[start : start + step]
        flat: list[str] = []
        for line_no, fields in chunk:
            if len(fields) != width:
                raise InvalidRecording(
                    f"line {line_no}: {len(fields)} fields, expected {width}", location=location
                )
            flat.extend(f.strip() or "nan" for f in fields)
        try:
            table[start : start + len(chunk)] = np.array(flat, dtype=np.float64).reshape(len(chunk), width)
        except ValueError:
            for line_no, fields in chunk:  # find the culprit for the message
                for text in fields:
                    _number(text.strip() or "nan", "value", line_no, location)
            raise InvalidRecording(f"line {chunk[0][0]}: unreadable numbers", location=location) from None
    return table


def line_label(rows: list[tuple[int, list[str]]]) -> Label:
    """``label(i)`` = ``line N`` of data row ``i``, for the checks of limits.py."""
    return lambda i: f"line {rows[i][0]}"


def _is_number(text: str) -> bool:
    """Whether ``text`` reads as a float (``nan`` and ``inf`` too): a data row, not a header key."""
    try:
        float(text)
    except ValueError:
        return False
    return True


def _header(lines: list[str], location: str) -> tuple[dict[str, tuple[int, list[str]]], int]:
    """The ``KEY<TAB>value…`` lines: KEY → (line number, values); and the index of the next line."""
    header: dict[str, tuple[int, list[str]]] = {}
    i = 0
    while i < len(lines):
        fields = _fields(lines[i])
        key = fields[0].strip()
        if not key or _is_number(key) or key.lower() == "frame":
            break
        header[key.upper()] = (i + 1, [f.strip() for f in fields[1:]])
        i += 1
    for key in ("NO_OF_FRAMES", "NO_OF_MARKERS", "FREQUENCY"):
        if key in header and not (header[key][1] and header[key][1][0]):
            raise InvalidRecording(f"line {header[key][0]}: {key} has no value", location=location)
    return header, i


def read_tsv(path: str | Path, units: str = "mm") -> Recording:
    """Read a QTM TSV export into a :class:`Recording` (metres, NaN gaps; limits.py checked)."""
    path = Path(path)
    location = str(path)
    to_m = metres_per_unit(units, location)
    lines = read_text(path)
    header, i = _header(lines, location)
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
            f"line {line}: NO_OF_MARKERS is {value} but MARKER_NAMES lists {n_markers}", location=location
        )
    has_frame_time = False
    if i < len(lines) and _fields(lines[i])[0].strip().lower() == "frame":
        columns = [c.strip().lower() for c in _fields(lines[i])]
        has_frame_time = columns[:2] == ["frame", "time"]
        i += 1
    text_rows = [(n + 1, lines[n]) for n in range(i, len(lines)) if lines[n].strip()]
    width = 3 * n_markers + (2 if has_frame_time else 0)
    if text_rows and not has_frame_time and len(_fields(text_rows[0][1])) == 3 * n_markers + 2:
        has_frame_time, width = True, 3 * n_markers + 2  # no column header, but Frame and Time columns
    if not text_rows:
        raise InvalidRecording("the recording has no frames", location=location)
    if "NO_OF_FRAMES" in header and header["NO_OF_FRAMES"][1][0] != str(len(text_rows)):
        line, value = header["NO_OF_FRAMES"][0], header["NO_OF_FRAMES"][1][0]
        raise InvalidRecording(
            f"line {line}: NO_OF_FRAMES is {value} but the file holds {len(text_rows)} data rows",
            location=location,
        )
    check_size(len(text_rows), n_markers, location, extra_values=2 * len(text_rows))
    rows = [(n, _fields(line)) for n, line in text_rows]
    table = parse_table(rows, width, location)
    label = line_label(rows)
    xyz = table[:, 2:] if has_frame_time else table
    positions = xyz.reshape(len(rows), n_markers, 3) * to_m
    check_coordinates(positions, names, location, label)
    positions[np.all(positions == 0.0, axis=-1) | np.isnan(positions).any(axis=-1)] = np.nan
    if has_frame_time:
        check_frame_numbers(table[:, 0], location, label)
    if "FREQUENCY" in header:
        line, value = header["FREQUENCY"][0], header["FREQUENCY"][1][0]
        rate = check_rate(_number(value, "FREQUENCY", line, location), location, f"line {line}: FREQUENCY")
        if has_frame_time:
            check_times(table[:, 1], location, label)
        times = table[:, 1] - table[0, 1] if has_frame_time else np.arange(len(rows)) / rate
    elif has_frame_time:
        times = table[:, 1] - table[0, 1]
        rate = rate_from_times(table[:, 1], location, label)
    else:
        raise InvalidRecording(
            "no FREQUENCY line and no Time column: the frame rate is unknown", location=location
        )
    first = int(table[0, 0]) if has_frame_time else 0
    groups = prefix_groups(names)
    index = {n: k for k, n in enumerate(names)}
    by_index = {g: tuple(index[n] for n in members) for g, members in groups.items()}
    return Recording(location, float(rate), times, names, positions, by_index, first)
