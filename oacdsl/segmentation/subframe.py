"""When a contact began or ended between two frames: event times below the frame period.

A keyframe stands on a frame (the world state a frame shows), but the change it stands for
happened somewhere between that frame and the one before: at 10 Hz anywhere in 0.1 s, in a take
at twice the speed anywhere in 0.2 s of the demonstration. Decisions that compare the times of
two changes (:mod:`oacdsl.matching.coincident`: are the two hands' grasps one bimanual action?)
then flip with a frame: KIT Wipe's two grasps, 0.52 s apart, are 5 frames apart at 10 Hz and 2
(0.4 s of the demonstration) in a 10 Hz take at double speed.

Where a contact's start or end is a **threshold crossing** — the extension of a co-motion
episode (:func:`oacdsl.segmentation.episodes.extend_episode`) begins at the first frame within
the episode's distance and ends at the first frame beyond it — the time of the crossing is
estimated by linear interpolation of the pair's closest marker distance between the two frames
around it (:func:`crossing`). Other boundaries (co-motion that stops, a tool's dwell, a hand at
rest, the paper's rule) have no such signal: they happened somewhere between the two frames, and
are put halfway (the frame's own time would make them half a frame later, on average, than an
interpolated one: KIT Wipe ×0.8 has its left hand leave the plate where co-motion stops, its right
hand leave the sponge by the distance). Keyframes stay on frames; only comparisons of times use
these (:attr:`oacdsl.segmentation.result.Keyframe.change_s`).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np

__all__ = ["EdgeTimes", "change_times_s", "crossing", "span_edges"]

#: Per instance pair: boundary frame → where the threshold was crossed, in frames (a fraction in
#: ``(frame - 1, frame]``).
EdgeTimes = dict[int, dict[int, float]]


def crossing(dmin: np.ndarray, frame: int, threshold_m: float) -> float | None:
    """Where ``dmin`` (closest marker distance per frame, metres) crosses ``threshold_m`` between
    frames ``frame - 1`` and ``frame``, in frames (linear interpolation), or ``None`` when it does
    not cross it there (a gap, the first frame, both on one side)."""
    if frame <= 0 or frame >= dmin.size:
        return None
    d0, d1 = float(dmin[frame - 1]), float(dmin[frame])
    if not (np.isfinite(d0) and np.isfinite(d1)) or d0 == d1:
        return None
    if (d0 - threshold_m) * (d1 - threshold_m) > 0 or d0 == threshold_m:
        return None  # not crossed between the two (at d0 exactly: crossed at or before frame - 1)
    return frame - 1 + (threshold_m - d0) / (d1 - d0)


def span_edges(dmin: np.ndarray, spans: Iterable[tuple[int, int, float]], out: dict[int, float]) -> None:
    """Add to ``out`` (frame → crossing, frames) the crossings at the ends of ``spans``: ``(a, b,
    threshold_m)``, touching on frames ``[a, b)`` while ``dmin`` is within ``threshold_m``. A
    frame that two spans give different crossings keeps the earliest."""
    for a, b, threshold in spans:
        for frame in (a, b):
            found = crossing(dmin, frame, threshold)
            if found is not None:
                out[frame] = min(found, out.get(frame, found))


def change_times_s(edges: Mapping[int, Mapping[int, float]], pairs: np.ndarray, frames: np.ndarray,
                   times_s: np.ndarray) -> np.ndarray:
    """Per change (instance pair ``pairs[i]`` changed at frame ``frames[i]``): the time of its
    crossing, seconds (interpolated in ``times_s``), else halfway between the frame and the one
    before (the first frame's own time for a change there)."""
    frames = np.asarray(frames, dtype=np.intp)
    times = np.asarray(times_s, dtype=np.float64)
    clipped = np.clip(frames, 0, times.size - 1)
    out = (times[clipped] + times[np.maximum(clipped - 1, 0)]) / 2
    for i, (q, f) in enumerate(zip(np.asarray(pairs).tolist(), clipped.tolist(), strict=True)):
        at = edges.get(q, {}).get(f)
        if at is None:
            continue
        lo = int(np.floor(at))
        frac = at - lo
        out[i] = float(times[lo] + frac * (times[min(lo + 1, times.size - 1)] - times[lo]))
    return out
