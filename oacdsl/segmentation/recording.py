"""The one in-memory form of a motion-capture recording, whatever its file format."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from oacdsl.errors import RecordingError, did_you_mean

__all__ = ["Recording", "column_index"]


def column_index(columns: np.ndarray) -> slice | np.ndarray:
    """Marker columns (indices into ``positions_m``'s axis 1) as a slice when they are consecutive
    and increasing (the usual layout of an instance's markers: reading them is then a strided
    view, without numpy's fancy indexing), else as they are; either indexes the same values."""
    columns = np.asarray(columns, dtype=np.intp)
    if columns.size and bool(np.all(np.diff(columns) == 1)):
        return slice(int(columns[0]), int(columns[-1]) + 1)
    return columns


@dataclass(frozen=True)
class Recording:
    """Marker trajectories grouped into instances.

    Attributes:
        source: file path (or a name) the recording came from, for messages.
        rate_hz: frame rate, Hz.
        times_s: (F,) time of each frame, seconds, 0 at the file's first frame.
        marker_names: (M,) marker labels as in the file.
        positions_m: (F, M, 3) float64 marker positions, metres, world frame; NaN in gaps.
        groups: instance name → indices into ``marker_names`` (an instance's marker group).
        first_frame: the file's own number of its first frame (C3D first_frame, TSV frame column).
    """

    source: str
    rate_hz: float
    times_s: np.ndarray
    marker_names: tuple[str, ...]
    positions_m: np.ndarray
    groups: Mapping[str, tuple[int, ...]] = field(default_factory=dict)
    first_frame: int = 0

    def __post_init__(self) -> None:
        f = self.positions_m.shape[0] if self.positions_m.ndim == 3 else -1
        if self.positions_m.ndim != 3 or self.positions_m.shape[1:] != (len(self.marker_names), 3):
            raise RecordingError(
                f"positions have shape {self.positions_m.shape},"
                f" expected (frames, {len(self.marker_names)}, 3)",
                location=self.source,
            )
        if self.times_s.shape != (f,):
            raise RecordingError(f"{self.times_s.shape[0]} frame times for {f} frames", location=self.source)
        if f == 0:
            raise RecordingError("the recording has no frames", location=self.source)
        if not (self.rate_hz > 0):
            raise RecordingError(f"frame rate must be positive, got {self.rate_hz}", location=self.source)
        for name, idx in self.groups.items():
            bad = [i for i in idx if not 0 <= i < len(self.marker_names)]
            if bad or not idx:
                raise RecordingError(f"marker group {name!r} has no valid markers", location=self.source)

    @property
    def n_frames(self) -> int:
        return int(self.positions_m.shape[0])

    @property
    def instances(self) -> tuple[str, ...]:
        """Instance names (marker groups), sorted."""
        return tuple(sorted(self.groups))

    def group_positions(self, name: str) -> np.ndarray:
        """(F, k, 3) positions of the markers of instance ``name``, metres."""
        if name not in self.groups:
            raise RecordingError(
                f"no marker group {name!r}{did_you_mean(name, self.groups)}", location=self.source
            )
        return self.positions_m[:, list(self.groups[name]), :]

    def with_groups(self, groups: Mapping[str, Sequence[str]]) -> Recording:
        """A copy whose groups are given by marker names; unknown markers are an error."""
        index = {n: i for i, n in enumerate(self.marker_names)}
        new: dict[str, tuple[int, ...]] = {}
        for inst, names in groups.items():
            missing = [n for n in names if n not in index]
            if missing:
                raise RecordingError(
                    f"instance {inst!r}: marker {missing[0]!r} is not in the recording"
                    f"{did_you_mean(missing[0], index)}",
                    location=self.source,
                )
            new[inst] = tuple(index[n] for n in names)
        return Recording(
            self.source,
            self.rate_hz,
            self.times_s,
            self.marker_names,
            self.positions_m,
            new,
            self.first_frame,
        )
