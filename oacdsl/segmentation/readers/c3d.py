"""C3D files (Vicon, Qualisys, Optotrak, …) through ezc3d: read and write.

Reading: integer and float storage (ezc3d applies ``POINT:SCALE``), the length
unit from ``POINT:UNITS`` (mm, cm, m) converted to metres, the header's first
frame kept as ``first_frame``, labels beyond ``POINT:USED`` ignored. A point is a
gap (NaN) when its residual is negative (the C3D rule for an invalid point) or
when all three coordinates are exactly 0 (what several writers store for a
missing point). Groups come from the ``SUBJECTS`` group (``LABEL_PREFIXES`` or
``NAMES`` + ``:``) when present, else from label prefixes
(:func:`~oacdsl.segmentation.grouping.prefix_groups`).

Writing (:func:`write_c3d`, directly with numpy: :mod:`.c3d_write`): float storage,
millimetres, labels ``group:marker``, a ``SUBJECTS`` group naming the groups, gaps as
residual −1; written to a temporary file in the target folder and renamed.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from oacdsl.atomic import atomic_path
from oacdsl.errors import InvalidRecording, RecordingError
from oacdsl.segmentation.grouping import prefix_groups
from oacdsl.segmentation.readers._common import metres_per_unit, unique_names
from oacdsl.segmentation.readers.c3d_check import check_c3d_data_size, check_c3d_structure
from oacdsl.segmentation.readers.c3d_write import write_c3d_points
from oacdsl.segmentation.readers.limits import check_coordinates, check_rate, read_regular
from oacdsl.segmentation.recording import Recording

__all__ = ["read_c3d", "write_c3d"]


def _param(params: Any, group: str, name: str) -> Any:
    try:
        return params[group][name]["value"]
    except (KeyError, TypeError):
        return None


def _strings(value: Any) -> list[str]:
    if value is None:
        return []
    if isinstance(value, str):
        return [value]
    return [str(v) for v in value]


def _labels(params: Any) -> list[str]:
    """POINT:LABELS followed by LABELS2, LABELS3, … (files with more than 255 points)."""
    labels = _strings(_param(params, "POINT", "LABELS"))
    k = 2
    while (more := _param(params, "POINT", f"LABELS{k}")) is not None:
        labels += _strings(more)
        k += 1
    return labels


def _subject_groups(params: Any, names: Sequence[str]) -> dict[str, list[str]] | None:
    subjects = _strings(_param(params, "SUBJECTS", "NAMES"))
    if not subjects:
        return None
    prefixes = _strings(_param(params, "SUBJECTS", "LABEL_PREFIXES"))
    if len(prefixes) != len(subjects):
        prefixes = [f"{s.strip()}:" for s in subjects]
    groups: dict[str, list[str]] = {}
    for subject, prefix in zip(subjects, prefixes, strict=True):
        prefix, subject = prefix.strip(), subject.strip()
        members = [n for n in names if prefix and n.startswith(prefix)]
        if subject and members:
            groups[subject] = members
    return groups or None


def read_c3d(path: str | Path, *, allow_truncated: bool = False) -> Recording:
    """Read a C3D file into a :class:`Recording` (metres, NaN gaps).

    A file that ends before its declared frames is a
    :class:`~oacdsl.errors.TruncatedRecording`; ``allow_truncated`` reads its complete
    frames with a :class:`~oacdsl.errors.RecordingWarning` instead.
    """
    import ezc3d

    path = Path(path)
    location = str(path)
    raw = read_regular(path)
    layout = check_c3d_structure(path, raw)
    held = check_c3d_data_size(path, len(raw), layout, allow_truncated=allow_truncated)
    try:
        c3d = ezc3d.c3d(str(path))
    except (OSError, RuntimeError, ValueError) as err:
        reason = str(err).splitlines()[0] if str(err) else type(err).__name__
        raise InvalidRecording(f"not a valid C3D file: {reason}", location=location) from None
    params = c3d["parameters"]

    points = np.asarray(c3d["data"]["points"], dtype=np.float64)  # (4, M, F), file units
    n_markers, n_frames = points.shape[1], points.shape[2]
    if n_frames != held:
        raise InvalidRecording(f"ezc3d read {n_frames} frames where the file holds {held}", location=location)
    if n_frames == 0:
        raise InvalidRecording("the recording has no frames", location=location)
    if n_markers == 0:
        raise InvalidRecording("the file holds no 3D points (markers)", location=location)
    units = _strings(_param(params, "POINT", "UNITS"))
    unit = next((u for u in units if u.strip()), "mm")
    to_m = metres_per_unit(unit, location, "POINT:UNITS")

    xyz = np.moveaxis(points[:3], 0, -1).transpose(1, 0, 2).copy()  # (F, M, 3)
    gap = np.all(xyz == 0.0, axis=-1) | np.isnan(xyz).any(axis=-1)
    meta = c3d["data"].get("meta_points") or {}
    residuals = meta.get("residuals") if isinstance(meta, dict) else None
    if residuals is not None and np.shape(residuals)[1:] == (n_markers, n_frames):
        gap |= (np.asarray(residuals)[0] < 0).T
    xyz[gap] = np.nan
    xyz *= to_m
    frame_bytes = (4 * layout.points + layout.analog_per_frame) * (4 if layout.float_storage else 2)
    data_start = (layout.data_start_block - 1) * 512  # bytes

    def frame_label(i: int) -> str:
        return f"frame {i + 1} of {n_frames} (byte {data_start + i * frame_bytes})"

    labels = _labels(params)[:n_markers]
    names = unique_names(labels + [""] * (n_markers - len(labels)))
    check_coordinates(xyz, names, location, frame_label)
    rate = float(c3d["header"]["points"]["frame_rate"])  # ezc3d: POINT:RATE when set, else the header's
    if rate == 0:
        rate_param = _param(params, "POINT", "RATE")
        rate = float(np.ravel(rate_param)[0]) if rate_param is not None and np.size(rate_param) else 0.0
    check_rate(rate, location, "the frame rate (POINT:RATE)")
    first = int(c3d["header"]["points"]["first_frame"])  # ezc3d: the header's number, 0-based
    by_name = _subject_groups(params, names) or prefix_groups(names)
    index = {n: i for i, n in enumerate(names)}
    groups = {g: tuple(index[n] for n in members) for g, members in by_name.items()}
    times = np.arange(n_frames, dtype=np.float64) / rate
    return Recording(location, rate, times, names, xyz, groups, first)


def _labels_for_writing(recording: Recording) -> list[str]:
    owner: dict[int, str] = {}
    for group, idx in recording.groups.items():
        if ":" in group or not group.strip():
            raise RecordingError(
                f"cannot write group name {group!r} to C3D (no ':' allowed)", location=recording.source
            )
        for i in idx:
            if i in owner:
                raise RecordingError(
                    f"cannot write C3D: marker {recording.marker_names[i]!r} is in groups"
                    f" {owner[i]!r} and {group!r}",
                    location=recording.source,
                )
            owner[i] = group
    labels = []
    for i, name in enumerate(recording.marker_names):
        owning = owner.get(i)
        labels.append(name if owning is None or name.startswith(f"{owning}:") else f"{owning}:{name}")
    return labels


def write_c3d(recording: Recording, path: str | Path) -> Path:
    """Write ``recording`` as a float C3D in millimetres; atomically (temp file + rename)."""
    path = Path(path)
    labels = _labels_for_writing(recording)
    try:
        with atomic_path(path, suffix=".tmp.c3d") as tmp:
            write_c3d_points(tmp, labels, list(recording.groups), recording.rate_hz,
                             int(recording.first_frame), recording.positions_m)
    except (OSError, ValueError) as err:
        raise RecordingError(f"cannot write C3D: {err}", location=str(path)) from None
    return path
