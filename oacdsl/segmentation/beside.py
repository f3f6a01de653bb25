"""Side by side: two objects near each other touch only where one is over the other.

Step 4 of the adaptive detector runs the paper's rule at each pair's own distance; two objects
that never move together nor rest on top of each other have none to learn, and fall back to the
static distance (80 mm in the reference's length, :class:`~oacdsl.segmentation.comotion.AdaptiveSettings`).
That distance is for what goes *into* another object without being carried with it: liquid poured
into a bowl (its markers 34 mm from the bowl's in the synthetic dough scene). Two objects set
down side by side on the table, neither over the other and nothing moving them together, came
within it too and touched however they stood: a fixed distance between markers says nothing of
where the objects' surfaces are.

The objects' own footprints do: :func:`side_by_side` vetoes, for such a pair, the frames within the
static distance where neither object's centre is over the other (inside the convex hull of its
visible markers seen from above, :func:`~oacdsl.segmentation.liftoff.over_frames`), outside the pair's
tool contacts. A frame where a marker of either is missing is not judged (a hidden marker shrinks
the hull: the synthetic dough's liquid, in its bowl, left it for 0.06 s where a rim marker was
hidden), and a pair of which neither has a footprint (fewer than three markers) is left to the
distance, as before. Lifted-off pairs (a rest on top) have their own rule,
:func:`~oacdsl.segmentation.liftoff.set_down_beside`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from oacdsl.segmentation.episodes import true_runs
from oacdsl.segmentation.liftoff import over_frames
from oacdsl.segmentation.pairs import PairTable

__all__ = ["side_by_side"]

Spans = list[tuple[int, int]]


def _columns(table: PairTable, instance: int) -> np.ndarray:
    return table.marker_order[table.marker_offsets[instance] : table.marker_offsets[instance + 1]]


def _footprint(table: PairTable, instance: int) -> bool:
    """Has the instance markers enough for a footprint (three)?"""
    return int(table.marker_offsets[instance + 1] - table.marker_offsets[instance]) >= 3


def side_by_side(
    table: PairTable, positions_m: np.ndarray, closest: Mapping[int, np.ndarray], pairs: Sequence[int],
    distance_m: float, kept: Mapping[int, Spans],
) -> dict[int, Spans]:
    """Object pair → frame intervals ``[a, b)`` in which it is vetoed (module doc): of ``pairs`` (the
    object pairs at the static distance), the frames whose closest marker distance (``closest``,
    (F,) metres; NaN unseen, inf beyond the scan) is within ``distance_m`` while neither object's
    centre is over the other's markers, outside the pair's intervals ``kept`` (tool contacts)."""
    n = positions_m.shape[0]
    out: dict[int, Spans] = {}
    for q in pairs:
        if q not in closest:
            continue
        i, j = (int(x) for x in table.instance_pairs[q])
        if not (_footprint(table, i) or _footprint(table, j)):
            continue
        with np.errstate(invalid="ignore"):
            near = np.asarray(closest[q]) <= distance_m
        for a, b in kept.get(q, []):
            near[a:b] = False
        frames = np.flatnonzero(near)
        cols = np.concatenate([_columns(table, i), _columns(table, j)])
        frames = frames[np.isfinite(positions_m[frames][:, cols]).all(axis=(1, 2))]  # a gap: unknown
        if frames.size == 0:
            continue
        on = over_frames(positions_m, table, i, j, frames) | over_frames(positions_m, table, j, i, frames)
        veto = np.zeros(n, dtype=bool)
        veto[frames[~on]] = True
        spans = true_runs(veto)
        if spans:
            out[q] = spans
    return out
