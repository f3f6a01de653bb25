"""A small, literal evaluation of the paper's touching rule, used to time the ground truth.

The synthetic demonstration's *states* are scripted; the *frame* at which each
intended change happens is defined as the frame where the paper's rule (Eq. 1
and Eq. 2 of Wächter et al. 2013) fires on the noise-free, gap-free scene. This
module is that definition, written independently of the project's AAS so that
the two check each other: the AAS on the noisy recording must reproduce it.

Per marker pair of two instances: distance ``dist`` (m) and its change
``|dist[f] - dist[f-1]| · rate`` (m/s, the first frame copies the second). A pair
starts touching at frame n0 when ``dist < d`` and change ``< v`` on every frame
n0 … n0+n−1; it stops at n1 when ``dist > d`` or change ``> v`` on every frame
n1 … n1+n−1. Instances touch while any of their pairs does. Keyframes closer than
the merge window form a group (chained), replaced by its last keyframe.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from itertools import combinations

import numpy as np

__all__ = ["PaperRule", "merge_keyframes", "pair_distances", "touching", "world_states"]


@dataclass(frozen=True)
class PaperRule:
    """The paper's parameters: distance d (m), distance change v (m/s), n frames, merge window (s).

    The defaults are the project's AAS defaults (``AasParams()`` resolved at 100 Hz:
    d = 150 mm, v = 100 mm/s, n = 0.1 s = 10 frames, merge 0.3 s).
    """

    distance_m: float = 0.15
    speed_m_s: float = 0.1
    frames: int = 10
    merge_s: float = 0.3


def pair_distances(a_m: np.ndarray, b_m: np.ndarray) -> np.ndarray:
    """(F, ka·kb) distances between every marker of ``a`` (F, ka, 3) and of ``b`` (F, kb, 3), m."""
    diff = a_m[:, :, None, :] - b_m[:, None, :, :]
    return np.linalg.norm(diff, axis=-1).reshape(a_m.shape[0], -1)


def _runs(mask: np.ndarray, n: int) -> np.ndarray:
    """True at f when mask[f … f+n−1] are all true (per column)."""
    f = mask.shape[0]
    c = np.concatenate([np.zeros((1, mask.shape[1]), int), np.cumsum(mask, axis=0)])
    out = np.zeros_like(mask)
    if f >= n:
        out[: f - n + 1] = (c[n:] - c[:-n]) == n
    return out


def touching(a_m: np.ndarray, b_m: np.ndarray, rate_hz: float, rule: PaperRule) -> np.ndarray:
    """(F,) bool: the two instances touch (any marker pair does), by the paper's rule."""
    dist = pair_distances(a_m, b_m)
    change = np.abs(np.diff(dist, axis=0, prepend=dist[:1])) * rate_hz
    if dist.shape[0] > 1:
        change[0] = change[1]
    ok = (dist < rule.distance_m) & (change < rule.speed_m_s)
    bad = (dist > rule.distance_m) | (change > rule.speed_m_s)
    start, stop = _runs(ok, rule.frames), _runs(bad, rule.frames)
    out = np.zeros(dist.shape[0], bool)
    for col in range(dist.shape[1]):
        starts, stops = np.flatnonzero(start[:, col]), np.flatnonzero(stop[:, col])
        f = 0
        while True:
            i = np.searchsorted(starts, f)
            if i == starts.size:
                break
            on = int(starts[i])
            j = np.searchsorted(stops, on)
            off = int(stops[j]) if j < stops.size else dist.shape[0]
            out[on:off] = True
            f = off
    return out


def world_states(
    markers_m: Mapping[str, np.ndarray], rate_hz: float, rule: PaperRule
) -> tuple[list[tuple[str, str]], np.ndarray]:
    """All instance pairs (sorted) and an (F, pairs) bool array of which touch when."""
    names = sorted(markers_m)
    pairs = list(combinations(names, 2))
    cols = [touching(markers_m[a], markers_m[b], rate_hz, rule) for a, b in pairs]
    return pairs, np.stack(cols, axis=1)


def merge_keyframes(frames: list[int], rate_hz: float, merge_s: float) -> list[int]:
    """Keep the last frame of every chain of keyframes closer than ``merge_s``; frame 0 stays."""
    kept: list[int] = []
    group: list[int] = []
    for f in frames:
        if f == 0:
            kept.append(f)
            continue
        if group and (f - group[-1]) / rate_hz >= merge_s:
            kept.append(group[-1])
            group = []
        group.append(f)
    if group:
        kept.append(group[-1])
    return kept
