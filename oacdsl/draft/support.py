"""What each drafted object stands on at the recording's first frame: the table, or another object.

A lid on its bottle, a knife lying on a board, a cucumber on a cutting board: its shape
reaches from its support, not from the table. At the first frame where the object is seen,
another object *supports* it when the object's marker centre lies over the other's marker
footprint (its markers' horizontal bounding box along the world axes, widened by
:data:`FOOTPRINT_SLACK_M`), the other's highest marker is no higher than the object's lowest
one plus :data:`TOUCH_SLACK_M`, and it rises at least :data:`MIN_RISE_M` above the table;
the highest such top is the object's base. Metres throughout.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from oacdsl.segmentation.recording import Recording

__all__ = ["FOOTPRINT_SLACK_M", "MIN_RISE_M", "TOUCH_SLACK_M", "Support", "supports"]

#: How far outside another object's marker footprint a centre may be and still stand on it (2 cm).
FOOTPRINT_SLACK_M = 0.02
#: How far a supporting object's top marker may be above the object's lowest marker (markers sit
#: on stalks and rims, 1 cm).
TOUCH_SLACK_M = 0.01
#: How far above the table a support's top must be to count (lower: the object is on the table, 2 cm).
MIN_RISE_M = 0.02


@dataclass(frozen=True)
class Support:
    """Where an object's base is: ``base_z_m`` (the table top or a support's top marker, metres)
    and the supporting object (None: the table), at ``frame``."""

    base_z_m: float
    on: str | None
    frame: int


def _first_seen(points: np.ndarray) -> int | None:
    seen = np.isfinite(points).all(axis=2).any(axis=1)
    return int(np.argmax(seen)) if seen.any() else None


def supports(recording: Recording, objects: list[str], table_z_m: float) -> dict[str, Support]:
    """Each object's :class:`Support` at the first frame it is seen (module doc)."""
    out: dict[str, Support] = {}
    positions = {g: recording.group_positions(g) for g in objects}
    for g in objects:
        frame = _first_seen(positions[g])
        if frame is None:
            out[g] = Support(table_z_m, None, 0)
            continue
        own = positions[g][frame]
        own = own[np.isfinite(own).all(axis=1)]
        centre, low = own[:, :2].mean(axis=0), float(own[:, 2].min())
        best = Support(table_z_m, None, frame)
        for other in objects:
            if other == g:
                continue
            pts = positions[other][frame]
            pts = pts[np.isfinite(pts).all(axis=1)]
            if len(pts) == 0:
                continue
            lo, hi = pts[:, :2].min(axis=0) - FOOTPRINT_SLACK_M, pts[:, :2].max(axis=0) + FOOTPRINT_SLACK_M
            top = float(pts[:, 2].max())
            over = bool(np.all(centre >= lo) and np.all(centre <= hi))
            if over and top <= low + TOUCH_SLACK_M and top >= table_z_m + MIN_RISE_M and top > best.base_z_m:
                best = Support(top, other, frame)
        out[g] = best
    return out
