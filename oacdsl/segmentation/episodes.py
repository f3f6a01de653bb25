"""Co-motion episodes and how far they grow: steps 1 (which runs are episodes) to 3 (extension)
of the adaptive touch detector, on one instance pair's per-frame signals.

:func:`oacdsl.segmentation.comotion.comotion` scans the recording for each pair's closest marker
distance and co-motion frames; this module turns those into episodes (:func:`_episodes`, the ones
that count: :func:`near_episodes`) and grows each into the interval in which the pair touches
(:func:`_extend`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["FAR_RATIO", "extend_episode", "find_episodes", "near_episodes", "true_runs", "union_spans"]


def _nanmedian1d(x: np.ndarray) -> float:
    """``float(np.nanmedian(x))`` of a 1-D float32 array (NaN if all are NaN), without its
    wrappers: the middle value, or the float32 mean of the two middle values, of the
    values present."""
    values = x[~np.isnan(x)]
    n = values.size
    if n == 0:
        return float("nan")
    k = n // 2
    if n % 2:
        return float(np.partition(values, k)[k])
    part = np.partition(values, [k - 1, k])
    return float((part[k - 1] + part[k]) / np.float32(2))  # as np.mean of the two, in float32


def true_runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """``[a, b)`` frame intervals where ``mask`` is True."""
    padded = np.concatenate([[False], mask, [False]])
    edges = np.flatnonzero(padded[1:] != padded[:-1])
    return list(zip(edges[::2].tolist(), edges[1::2].tolist(), strict=True))


def find_episodes(carry: np.ndarray, min_len: int, bridge: int) -> list[tuple[int, int]]:
    """The co-motion runs ``[a, b)`` of ``carry`` that are episodes: the runs of at least
    ``min_len`` frames, and the shorter runs that lead up to one — a run of ``min_len`` follows
    them after interruptions of at most ``bridge`` frames each.

    A grasp's first co-motion often flickers (the hand still closing its grip lifts the object in
    short jerks before it carries it): how long each piece lasts depends on the frame rate and the
    lag of the speeds (KIT Stir's cup: 2 frames at 10 Hz, 3 at 30 Hz, 9 + 1 at 100 Hz), and the
    carry's own, tighter grip does not reach back to where the hand arrived. Each piece keeps its
    own threshold (its median distance). Short pieces *after* a carry are not episodes: the object
    set down, the hand opening, its distance already growing (KIT Pour at 240 Hz: one frame at
    149 mm as the carton leaves the cup); the carry's extension covers the let-go."""
    runs = true_runs(carry)
    out: list[tuple[int, int]] = []
    leading: list[tuple[int, int]] = []  # short runs chained to the next run
    for a, b in runs:
        if leading and a - leading[-1][1] > bridge:
            leading = []
        if b - a >= min_len:
            out += leading
            out.append((a, b))
            leading = []
        else:
            leading.append((a, b))
    return out


#: An episode of co-motion farther than this many times the pair's closest one (their medians)
#: is two hands moving alike, not a grip: KIT Stir's spoon brought towards the cup moves with
#: it 160 mm away, four times its 41 mm in the cup. The development clips' and the synthetic
#: demonstrations' pairs co-move at up to 1.63 times their closest (Scoop: the cup held up to the
#: ladle at 143 mm, 1.58 times their 91 mm while it pours; the cup in the hand as it is lifted).
FAR_RATIO = 2.0


def near_episodes(dmin: np.ndarray, episodes: list[tuple[int, int]],
                   cap_m: float) -> list[tuple[int, int, float]]:
    """``(a, b, median closest distance)`` of the ``episodes`` that count: the pair co-moves
    within ``cap_m`` (``d``) somewhere, and each episode lies within :data:`FAR_RATIO` times the
    closest one.

    The scan finds co-motion up to ``d × (1 + margin)``, not ``d``: a cap that does not follow
    the scene's scale exactly (``d`` grows with the hands' size, and a subject's hands differ
    from the reference's by ±6 %) made the same co-motion count in one take and not in another
    (KIT Scoop's cup and ladle at 143-149 mm in the original, 165-171 mm in a take ×1.15 whose
    ``d`` is 163.5 mm; Stir's spoon at 155-165 mm out of ``d`` in the original, within it at ×0.9).
    The ratio to the pair's own closest co-motion is the same at every scale."""
    found = [(a, b, _nanmedian1d(dmin[a:b])) for a, b in episodes]
    closest = min((m for _, _, m in found if m == m), default=float("inf"))  # NaN: no distance
    if not closest < cap_m:
        return []
    return [(a, b, m) for a, b, m in found if m <= FAR_RATIO * closest]


_EXTEND_WINDOW = 2048  # frames either side of an episode looked at first by _extend


def extend_episode(dmin: np.ndarray, a: int, b: int, threshold: float, bridge: int = 0) -> tuple[int, int]:
    """:func:`_extend_in` on ``_EXTEND_WINDOW`` frames either side of ``[a, b)`` when that decides
    both ends (a run beyond ``threshold`` that stops the growth on each side, whose length is
    known), else on the whole recording: the same result, without a pass over all of it."""
    lo, hi = max(0, a - _EXTEND_WINDOW), min(dmin.size, b + _EXTEND_WINDOW)
    if lo > 0 or hi < dmin.size:
        found = _extend_window(dmin, a, b, threshold, bridge, lo, hi)
        if found is not None:
            return found
    return _extend_in(dmin, a, b, threshold, bridge)


def _extend_window(dmin: np.ndarray, a: int, b: int, threshold: float, bridge: int,
                   lo: int, hi: int) -> tuple[int, int] | None:
    """:func:`_extend_in` decided on frames ``lo:hi`` alone, or ``None`` when they do not decide it."""
    size = dmin.size
    padded = np.zeros(hi - lo + 2, dtype=bool)
    np.greater(dmin[lo:hi], threshold, out=padded[1:-1])  # NaN: unknown, not beyond
    edges = (padded[1:] != padded[:-1]).nonzero()[0] + lo
    starts, ends = edges[::2], edges[1::2]  # runs [s, e) beyond, cut at the window
    if starts.size == 0:
        return None if lo > 0 or hi < size else (0, size)
    keep = ends - starts > bridge
    # a short run at a window edge (its true length unknown): bridged or not depends on the outside
    if (not keep[0] and lo > 0 and starts[0] == lo) or (not keep[-1] and hi < size and ends[-1] == hi):
        return None
    keep[0] |= starts[0] == 0
    keep[-1] |= ends[-1] == size
    kept = keep.nonzero()[0]
    i = int(starts[kept].searchsorted(a, side="left")) - 1
    j = int(ends[kept].searchsorted(b, side="right"))
    if (i < 0 and lo > 0) or (j >= kept.size and hi < size):  # an end not decided in the window
        return None
    return _ends(starts, ends, keep, kept[i] if i >= 0 else -1, kept[j] if j < kept.size else -1,
                 a, b, bridge, size)


def _extend_in(dmin: np.ndarray, a: int, b: int, threshold: float, bridge: int = 0) -> tuple[int, int]:
    """Grow ``[a, b)`` both ways while the closest distance is within ``threshold`` or unknown.

    Excursions beyond ``threshold`` of at most ``bridge`` frames between two frames within
    it do not stop the growth: a marker of the hand hidden for a few frames makes the closest
    distance jump to the next marker's, the hand has not let go.
    """
    with np.errstate(invalid="ignore"):
        beyond = dmin > threshold  # NaN: unknown, not beyond
    padded = np.concatenate([[False], beyond, [False]])
    edges = np.flatnonzero(padded[1:] != padded[:-1])
    starts, ends = edges[::2], edges[1::2]  # runs [s, e) beyond the threshold
    keep = np.ones(starts.size, dtype=bool)
    if bridge > 0:  # short excursions between two frames within the threshold do not count
        keep = ~((ends - starts <= bridge) & (starts > 0) & (ends < beyond.size))
    kept = keep.nonzero()[0]
    i = int(np.searchsorted(starts[kept], a, side="left")) - 1  # the last run that starts before a
    j = int(np.searchsorted(ends[kept], b, side="right"))  # the first run that ends after b
    return _ends(starts, ends, keep, int(kept[i]) if i >= 0 else -1, int(kept[j]) if j < kept.size else -1,
                 a, b, bridge, dmin.size)


def _ends(starts: np.ndarray, ends: np.ndarray, keep: np.ndarray, i: int, j: int, a: int, b: int,
          bridge: int, size: int) -> tuple[int, int]:
    """The grown interval's ends, given the runs beyond the threshold ``[starts, ends)``, which of
    them end the growth (``keep``), the one before ``[a, b)`` (``i``) and the one after (``j``;
    -1: none).

    **A let-go is the first leave that is followed by moving apart**: a bridged excursion followed
    by a return within the threshold of at most ``bridge`` frames, and then by the leave that ends
    the growth, is where the hand let go (the hand opens, leaves, passes back through the grip's
    distance for a frame and leaves: KIT Stir's spoon at ×0.6 speed, whose return the bridge would
    join). Not so backwards: a grasp's grip flickers as it closes (the synthetic task
    demonstrations' grasps and KIT Stir's cup would begin 0.1-0.2 s later)."""
    if j >= 0:
        while j > 0 and not keep[j - 1] and starts[j - 1] >= b and starts[j] - ends[j - 1] <= bridge:
            j -= 1
    return (min(int(ends[i]), a) if i >= 0 else 0, max(int(starts[j]), b) if j >= 0 else size)


def union_spans(spans: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """Sorted, disjoint frame intervals covering ``spans``."""
    merged: list[tuple[int, int]] = []
    for a, b in sorted(spans):
        if merged and a <= merged[-1][1]:
            merged[-1] = (merged[-1][0], max(merged[-1][1], b))
        else:
            merged.append((a, b))
    return merged
