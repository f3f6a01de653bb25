"""Build a :class:`Recording` from per-frame 3D points of named groups (virtual markers).

Used for synthetic demonstrations and for the closed loop: points recorded from a
simulation (one group per tracked body) become a recording that the same AAS
segments as a motion capture.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from oacdsl.errors import RecordingError
from oacdsl.segmentation.recording import Recording

__all__ = ["recording_from_points"]


def recording_from_points(
    groups: Mapping[str, np.ndarray],
    rate_hz: float,
    source: str = "<points>",
    labels: Mapping[str, Sequence[str]] | None = None,
    first_frame: int = 0,
) -> Recording:
    """A recording whose instances are the keys of ``groups``.

    Args:
        groups: instance name → (F, k, 3) positions in metres, world frame; NaN marks a
            missing point. Every group has the same F and at least one point.
        rate_hz: frame rate, Hz; frame f is at f / rate_hz seconds.
        source: the name messages and the segmentation report use.
        labels: instance → k point labels (default ``m1 … mk``). Marker names are
            ``instance:label``, the subject-prefix convention of Vicon C3D files.
        first_frame: the frame number of the first frame, kept as metadata.

    Raises:
        RecordingError: empty input, shapes that do not agree, infinite values, a bad rate.
    """
    if not groups:
        raise RecordingError("no point groups given", location=source)
    if not (np.isfinite(rate_hz) and rate_hz > 0):
        raise RecordingError(f"frame rate must be positive, got {rate_hz}", location=source)
    n_frames: int | None = None
    names: list[str] = []
    blocks: list[np.ndarray] = []
    index: dict[str, tuple[int, ...]] = {}
    for inst in groups:
        pts = np.asarray(groups[inst], dtype=float)
        if pts.ndim != 3 or pts.shape[2] != 3 or pts.shape[1] == 0:
            raise RecordingError(
                f"group {inst!r}: points have shape {pts.shape}, expected (frames, k ≥ 1, 3)", location=source
            )
        if n_frames is None:
            n_frames = pts.shape[0]
        elif pts.shape[0] != n_frames:
            raise RecordingError(
                f"group {inst!r} has {pts.shape[0]} frames, the others {n_frames}", location=source
            )
        if np.isinf(pts).any():
            raise RecordingError(
                f"group {inst!r} has infinite coordinates (use NaN for gaps)", location=source
            )
        if labels is not None and inst in labels:
            own = [str(lab) for lab in labels[inst]]
        else:
            own = [f"m{i + 1}" for i in range(pts.shape[1])]
        if len(own) != pts.shape[1]:
            raise RecordingError(
                f"group {inst!r}: {len(own)} labels for {pts.shape[1]} points", location=source
            )
        index[inst] = tuple(range(len(names), len(names) + len(own)))
        names.extend(f"{inst}:{lab}" for lab in own)
        blocks.append(pts)
    if len(set(names)) != len(names):
        raise RecordingError("marker labels are not unique within a group", location=source)
    positions = np.concatenate(blocks, axis=1)
    times = np.arange(positions.shape[0]) / float(rate_hz)
    return Recording(source, float(rate_hz), times, tuple(names), positions, index, first_frame)
