"""Helpers shared by the format readers: units, marker names, frame rates."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from oacdsl.errors import InvalidRecording, did_you_mean
from oacdsl.segmentation.readers.limits import Label, check_rate, check_times, clip

__all__ = ["UNIT_TO_M", "clip", "metres_per_unit", "unique_names", "rate_from_times"]

#: Length units a recording may declare, and their size in metres.
UNIT_TO_M: dict[str, float] = {"mm": 1e-3, "cm": 1e-2, "dm": 1e-1, "m": 1.0}


def metres_per_unit(unit: str, location: str, what: str = "unit") -> float:
    """Size of ``unit`` in metres; an unknown unit is an :class:`InvalidRecording`."""
    key = unit.strip().lower()
    if key not in UNIT_TO_M:
        raise InvalidRecording(
            f"unknown {what} {clip(unit)}{did_you_mean(key, UNIT_TO_M)}", location=location
        )
    return UNIT_TO_M[key]


def unique_names(names: Iterable[str], placeholder: str = "point") -> tuple[str, ...]:
    """Stripped names; empty ones become ``point1``…, repeats get ``#2``, ``#3``…."""
    out: list[str] = []
    seen: dict[str, int] = {}
    for i, raw in enumerate(names):
        name = raw.strip() or f"{placeholder}{i + 1}"
        if name in seen:
            seen[name] += 1
            name = f"{name}#{seen[name]}"
        seen.setdefault(name, 1)
        out.append(name)
    return tuple(out)


def _frame_label(i: int) -> str:
    return f"frame {i}"


def rate_from_times(times_s: np.ndarray, location: str, label: Label = _frame_label) -> float:
    """Frame rate (Hz) from frame times (s): the inverse of the median step, checked (limits.py).

    ``label(i)`` names frame ``i`` in messages (``line 12``; default ``frame i``).
    """
    check_times(times_s, location, label)
    if times_s.size < 2:
        raise InvalidRecording("cannot tell the frame rate from a single frame", location=location)
    rate = float(f"{1.0 / np.median(np.diff(times_s)):.9g}")  # 10 Hz, not 9.999999999999996 Hz
    return check_rate(rate, location, "the frame rate from the frame times")
