"""Lifted off: an object that rested on top of another stops touching it when it is lifted off.

A rest on top (:mod:`oacdsl.segmentation.stacking`) teaches a pair of objects the distance at
which they touch, and its contact grows from the rest until that distance is left. The tool rule
(:mod:`oacdsl.segmentation.tooluse`) knows no such distance: a held object touches another while
it stays within the tool reach ``d`` (150 mm in the reference's length), because a tool's markers
sit far from where it works. Without this rule a lid unscrewed and lifted 8 cm off its bottle,
held there, touched the bottle for as long as it was held (its markers 146 mm from the bottle's,
the synthetic Open turned 535°), and one held 156 mm off stopped touching it 0.5 s after it was
lifted, when it left the reach.

Physically, lifting an object off another ends their contact; what a held tool does afterwards
near that object is a new contact only if it arrives again. So, for each rest of a pair:

- **Lifted off.** The rest's contact ends at frame ``b`` (the closest marker distance leaves the
  rest's threshold, beyond the bridge) and the two objects separate vertically there: within the
  dwell after ``b`` the height of one above the other (each object's marker heights against their
  own at the end of the rest, the median over its markers: a marker gap does not move it) grows
  by more than what the threshold allows beyond the rest's distance (``margin`` of it: a lid
  turned on its bottle stays at its height; one lifted 8 cm rises 80 mm, the threshold allows
  11 mm). An object slid off sideways, or a rest that ends because the markers turn out of the
  threshold, is not lifted off: the tool rule carries on there.
- **Not extended.** A tool contact of the pair running through ``b`` ends at ``b``. It resumes
  where the lifted object comes back onto the other — within the rest's threshold, its centre over
  the other's markers seen from above, as it rested (a knife lifted off a board and brought down
  onto it again, a lid put back) — if what is left of it lasts the dwell; a lid put down beside
  its bottle, within the threshold but not over it, does not touch it. A tool contact that begins
  after ``b`` (the tool left the reach and came back) is a new arrival and stays.

- **Set down beside.** After a lift-off the pair's learned distance (the rest's) no longer makes
  it touch by the paper's rule (step 4 of the adaptive detector) where neither object is over the
  other: that distance was learned with one on top of the other, and two objects standing side by
  side on the table, neither on the other, with nothing moving them together, do not touch,
  however near (a lid set down 1.5 cm beside its bottle, its markers 84 mm from the bottle's,
  within the rest's 88 mm). :func:`set_down_beside` vetoes those frames; a rest, a tool contact
  (a new arrival, or resumed back on top) and the frames where one is over the other and within
  the rest's distance are left to the other rules.

A knife lying on a board, picked up and used on the cucumber on it, leaves the board as it is
lifted; a spoon lifted out of a cup and held above it (a tool contact without a rest) is
:mod:`oacdsl.segmentation.liftout`'s. Everything here is in frames and the
recording's own lengths: scale, rotation about the vertical, mirror and pace (the dwell and the
margin are the detector's rescaled ones) do not change it; it needs z up.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from typing import NamedTuple

import numpy as np

from oacdsl.segmentation.episodes import true_runs
from oacdsl.segmentation.medians import nanmedian0
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.recording import Recording

__all__ = ["LiftOff", "cut_at_lift_offs", "lift_offs", "over", "over_frames", "set_down_beside"]

Spans = list[tuple[int, int]]


def _heights(recording: Recording, table: PairTable, instance: int, lo: int, hi: int) -> np.ndarray:
    """(hi - lo, k) marker heights of ``instance``, metres (NaN in gaps)."""
    columns = np.asarray(recording.groups[table.instances[instance]], dtype=np.intp)
    return recording.positions_m[lo:hi, columns, 2].astype(np.float64)


def _rise(z: np.ndarray, split: int) -> np.ndarray:
    """Per frame after ``split`` (rows ``split:``), the median over markers of each marker's height
    above its own median over rows ``:split``, metres (NaN: nothing seen)."""
    # np.nanmedian's values (axis 0, then 1) without its masked arrays: the sorted middle rows
    base = nanmedian0(z[:split])
    with np.errstate(invalid="ignore"):
        return np.asarray(nanmedian0((z[split:] - base[None, :]).T), dtype=np.float64)


class LiftOff(NamedTuple):
    """A rest on top ended by a lift-off: at ``frame``, the pair's rest distance ``threshold``
    (metres), ``top`` the instance lifted off ``base`` (indices of the pair table's instances)."""

    frame: int
    threshold: float
    top: int
    base: int


def lift_offs(
    recording: Recording,
    table: PairTable,
    rests: Mapping[int, tuple[Spans, float]],
    dwell: int,
    margin: float,
) -> dict[int, list[LiftOff]]:
    """Object pair → each rest contact of ``rests`` (pair → (intervals ``[a, b)``, the pair's
    learned distance, metres; :func:`~oacdsl.segmentation.stacking.resting_on_top`) that ends by
    a lift-off (module doc); ``dwell``: frames in which the lift must show, ``margin``: the
    threshold's over the rest's distance."""
    n = recording.n_frames
    out: dict[int, list[LiftOff]] = {}
    for q, (spans, threshold) in rests.items():
        i, j = (int(x) for x in table.instance_pairs[q])
        allowed = threshold * margin / (1 + margin)  # metres the distance may grow within the contact
        for a, b in spans:
            if b >= n:
                continue
            lo, hi = max(a, b - dwell), min(n, b + max(1, dwell))
            rise_i = _rise(_heights(recording, table, i, lo, hi), b - lo)
            rise_j = _rise(_heights(recording, table, j, lo, hi), b - lo)
            with np.errstate(invalid="ignore"):
                apart = rise_i - rise_j
            if not np.isfinite(apart).any():
                continue
            k = int(np.nanargmax(np.abs(apart)))
            if abs(float(apart[k])) > allowed:
                top, base = (i, j) if apart[k] > 0 else (j, i)
                out.setdefault(q, []).append(LiftOff(b, threshold, top, base))
    return out


def _columns(table: PairTable, instance: int) -> np.ndarray:
    return table.marker_order[table.marker_offsets[instance] : table.marker_offsets[instance + 1]]


def _visible_xy(rows_m: np.ndarray, table: PairTable, instance: int) -> np.ndarray:
    """(R, k, 2) the instance's markers seen from above in ``rows_m`` ((R, M, 3) frames of the
    recording's positions); NaN where a marker is unseen."""
    xyz = rows_m[:, _columns(table, instance)]  # a copy
    xy = xyz[..., :2].astype(float, copy=True)
    seen = np.isfinite(xyz[..., 0]) & np.isfinite(xyz[..., 1]) & np.isfinite(xyz[..., 2])
    xy[~seen] = np.nan
    return xy


def over_frames(
    positions_m: np.ndarray, table: PairTable, top: int, base: int, frames: np.ndarray,
) -> np.ndarray:
    """(len(frames),) bool: at each of ``frames``, is the centre of ``top``'s visible markers over
    ``base``: inside (or on) the convex hull of ``base``'s visible markers seen from above? False
    where the hull has no area or ``top`` is unseen. A point is in the convex hull of points in the
    plane exactly when it is in a triangle of three of them (Carathéodory), so each frame is tested
    against every triangle with area of ``base``'s markers at once (the result of
    :func:`~oacdsl.segmentation.stacking.inside_hull`, per frame)."""
    frames = np.asarray(frames, dtype=np.intp)
    if frames.size == 0:
        return np.zeros(0, dtype=bool)
    return _over_rows(positions_m[frames], table, top, base)


def _over_rows(rows_m: np.ndarray, table: PairTable, top: int, base: int) -> np.ndarray:
    """:func:`over_frames` of the frames whose positions are ``rows_m`` ((R, M, 3), read once by
    the caller for both ways round)."""
    inside = np.zeros(rows_m.shape[0], dtype=bool)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # an unseen instance: a NaN centre
        centre = np.nanmean(_visible_xy(rows_m, table, top), axis=1)
    corners = _visible_xy(rows_m, table, base)
    k = corners.shape[1]

    def cross(o: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return (a[:, 0] - o[:, 0]) * (b[:, 1] - o[:, 1]) - (a[:, 1] - o[:, 1]) * (b[:, 0] - o[:, 0])

    with np.errstate(invalid="ignore"):
        for i in range(k):
            for j in range(i + 1, k):
                for m in range(j + 1, k):
                    a, b, c = corners[:, i], corners[:, j], corners[:, m]
                    area = cross(a, b, c)
                    d1, d2, d3 = cross(a, b, centre), cross(b, c, centre), cross(c, a, centre)
                    same = ((d1 >= 0) & (d2 >= 0) & (d3 >= 0)) | ((d1 <= 0) & (d2 <= 0) & (d3 <= 0))
                    inside |= (area != 0) & np.isfinite(area) & same
    return inside


def over(positions_m: np.ndarray, table: PairTable, top: int, base: int, frame: int) -> bool:
    """At ``frame``, is the centre of ``top``'s visible markers over ``base`` (:func:`over_frames`)?"""
    return bool(over_frames(positions_m, table, top, base, np.array([frame]))[0])


def cut_at_lift_offs(
    spans: Spans, lifts: list[LiftOff], closest_m: np.ndarray, dwell: int, positions_m: np.ndarray,
    table: PairTable,
) -> Spans:
    """A pair's tool contacts ``spans`` with each one that runs through a lift-off of ``lifts``
    ended there, and resumed where the lifted object comes back onto the other: ``closest_m``
    ((F,) the pair's closest marker distance, metres) within the rest's threshold and its centre
    over the other's markers (:func:`over`, in ``positions_m``, (F, M, 3)), if what is left of the
    contact from there lasts ``dwell`` frames (module doc)."""
    out = list(spans)
    for lift in lifts:
        cut: Spans = []
        for s, e in out:
            if not s < lift.frame < e:
                cut.append((s, e))
                continue
            cut.append((s, lift.frame))
            with np.errstate(invalid="ignore"):
                near = lift.frame + np.flatnonzero(closest_m[lift.frame : e - dwell + 1] <= lift.threshold)
            on = near[over_frames(positions_m, table, lift.top, lift.base, near)]
            back = int(on[0]) if on.size else None
            if back is not None:
                cut.append((back, e))
        out = cut
    return out


def set_down_beside(
    lifts: Mapping[int, list[LiftOff]], closest: Mapping[int, np.ndarray], kept: Mapping[int, Spans],
    positions_m: np.ndarray, table: PairTable,
) -> dict[int, Spans]:
    """Object pair → frame intervals ``[a, b)`` from its first lift-off of ``lifts`` on in which
    nothing makes it touch: outside its intervals ``kept`` (rests, tool contacts) and not within
    the rest's distance with one object over the other (:func:`over`, in ``positions_m``) —
    ``closest`` ((F,) the pair's closest marker distance, metres; NaN: unseen, inf: beyond the
    scan) — so the paper's rule at the rest's distance does not make two objects side by side
    touch (module doc)."""
    n = positions_m.shape[0]
    out: dict[int, Spans] = {}
    for q, pair_lifts in lifts.items():
        if not pair_lifts or q not in closest:
            continue
        lift = min(pair_lifts, key=lambda x: x.frame)
        veto = np.zeros(n, dtype=bool)
        veto[lift.frame :] = True
        for a, b in kept.get(q, []):
            veto[a:b] = False
        with np.errstate(invalid="ignore"):
            near = ~(np.asarray(closest[q]) > lift.threshold)  # within it or unseen: the rule may hold
        frames = np.flatnonzero(veto & near)  # only near frames need the footprint test
        rows = positions_m[frames]  # read once for both ways round
        on = _over_rows(rows, table, lift.top, lift.base) | _over_rows(rows, table, lift.base, lift.top)
        veto[frames[on]] = False
        spans = true_runs(veto)
        if spans:
            out[q] = spans
    return out
