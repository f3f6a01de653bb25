"""A straightforward per-frame Python implementation of the AAS, for tests and benchmarks.

It follows the paper literally, one frame and one marker pair at a time, with
run counters: slow (pure Python, float64) but easy to check by eye. The fast
:func:`oacdsl.segmentation.segment` must give the same keyframes; the benchmark
``benchmarks/segmentation.py`` measures how much faster that one is.
"""

from __future__ import annotations

import math

import numpy as np

from oacdsl.segmentation.keyframes import merge_keyframes
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import Keyframe, Segmentation
from oacdsl.world import WorldState, relation

__all__ = ["pair_frames", "segment_reference"]


def segment_reference(recording: Recording, params: AasParams | None = None) -> Segmentation:
    """Keyframes by Eq. 1 / Eq. 2, frame by frame.

    Same conventions as :class:`~oacdsl.segmentation.detectors.PaperDetector`.
    """
    params = (params or AasParams()).resolved(recording.rate_hz)
    d, v, n = params.distance_m, params.speed_m_s, params.n
    names = sorted(recording.groups)
    pairs: list[tuple[int, int, tuple[str, str]]] = []
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            for ma in recording.groups[a]:
                for mb in recording.groups[b]:
                    pairs.append((ma, mb, relation(a, b)))
    pos = recording.positions_m.tolist()
    times = [float(t) for t in recording.times_s]
    n_frames = len(times)

    def distance(frame: int, ma: int, mb: int) -> float:
        pa, pb = pos[frame][ma], pos[frame][mb]
        return math.sqrt((pa[0] - pb[0]) ** 2 + (pa[1] - pb[1]) ** 2 + (pa[2] - pb[2]) ** 2)

    touching = [False] * len(pairs)
    close_run = [0] * len(pairs)
    far_run = [0] * len(pairs)
    previous = [distance(1 if n_frames > 1 else 0, ma, mb) for ma, mb, _ in pairs]
    changes: list[tuple[int, int, bool]] = []  # (frame n0 or n1, pair, new state)
    for i in range(n_frames):
        # frame 0 takes the distance change of frame 1 (its "previous" is frame 1)
        limit = v * (times[i] - times[i - 1] if i > 0 else times[1] - times[0] if n_frames > 1 else 0.0)
        for p, (ma, mb, _) in enumerate(pairs):
            dist = distance(i, ma, mb)
            change = abs(dist - previous[p]) if n_frames > 1 else math.nan
            previous[p] = dist
            if math.isnan(dist):
                close = far = False
            elif math.isnan(change):  # the other frame is a gap: only the distance is known
                close = False
                far = dist > d
            else:
                close = dist < d and change < limit
                far = dist > d or change > limit
            close_run[p] = close_run[p] + 1 if close else 0
            far_run[p] = far_run[p] + 1 if far else 0
            if not touching[p] and close_run[p] >= n:
                touching[p] = True
                changes.append((i - n + 1, p, True))
            elif touching[p] and far_run[p] >= n:
                touching[p] = False
                changes.append((i - n + 1, p, False))

    # per-frame world states from the labelled pair states
    changes.sort(key=lambda c: c[0])
    pair_state = [False] * len(pairs)
    instances = frozenset(names)
    keyframes: list[Keyframe] = []
    k = 0
    for i in range(n_frames):
        while k < len(changes) and changes[k][0] <= i:
            pair_state[changes[k][1]] = changes[k][2]
            k += 1
        rels = frozenset(pairs[p][2] for p in range(len(pairs)) if pair_state[p])
        state = WorldState(instances, rels)
        if not keyframes or state != keyframes[-1].state:
            keyframes.append(Keyframe(i, times[i], state))
    merged = merge_keyframes(keyframes, params.merge_s)
    return Segmentation(recording.source, float(recording.rate_hz), n_frames, recording.instances,
                        tuple(merged), params.to_dict())


def pair_frames(recording: Recording) -> int:
    """Marker-pair-frames of a recording: cross-instance marker pairs × frames."""
    sizes = np.array([len(g) for g in recording.groups.values()])
    pairs = (sizes.sum() ** 2 - (sizes ** 2).sum()) // 2
    return int(pairs) * recording.n_frames
