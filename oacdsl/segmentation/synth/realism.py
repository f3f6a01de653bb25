"""What makes a synthetic recording look like motion capture: marker noise and occlusion gaps.

Noise per marker and axis (metres) is the sum of

* white jitter, σ = 0.1 mm per frame — the reconstruction jitter of an optical
  system (the real 100 Hz recordings in ``../shared/mocap`` show 0.01 mm for the
  Vicon box and about 0.1 mm per frame for the Qualisys glove);
* a slow wobble, smoothed over about 0.1 s, σ = 0.8 mm on hand markers (skin and
  marker-base movement) and 0.4 mm on object markers,

so a marker is off by about 1 mm while its frame-to-frame change stays small
enough for the paper's distance-change condition (v = 50 mm/s ↔ 0.5 mm/frame at 100 Hz).

Gaps are runs of NaN frames: a fixed list tied to moments of the story (some
during a contact, one hiding the only marker of an instance) plus a few short
random ones, placed away from every intended keyframe.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["Gap", "NoiseModel", "add_noise", "random_gaps", "apply_gaps"]


@dataclass(frozen=True)
class NoiseModel:
    """Marker noise: white jitter (m), slow wobble of hands and objects (m), its time scale (s)."""

    white_m: float = 0.00005
    slow_hand_m: float = 0.0008
    slow_object_m: float = 0.0004
    slow_time_s: float = 0.1

    def to_json(self) -> dict[str, float]:
        return {
            "white_m": self.white_m,
            "slow_hand_m": self.slow_hand_m,
            "slow_object_m": self.slow_object_m,
            "slow_time_s": self.slow_time_s,
        }


@dataclass(frozen=True)
class Gap:
    """Marker ``label`` of ``instance`` is missing on frames ``first`` … ``last`` (inclusive)."""

    instance: str
    label: str
    first: int
    last: int
    reason: str


def _smooth(x: np.ndarray, sigma_frames: float) -> np.ndarray:
    """Gaussian smoothing along axis 0 (edges reflected), rescaled to unit standard deviation."""
    half = int(np.ceil(4.0 * sigma_frames))
    k = np.exp(-0.5 * (np.arange(-half, half + 1) / sigma_frames) ** 2)
    k /= k.sum()
    padded = np.concatenate([x[half:0:-1], x, x[-2 : -half - 2 : -1]], axis=0)
    flat = padded.reshape(padded.shape[0], -1)
    out = np.stack([np.convolve(flat[:, j], k, mode="valid") for j in range(flat.shape[1])], axis=1)
    out = out.reshape((x.shape[0],) + x.shape[1:])
    return out / max(float(out.std()), 1e-12)


def add_noise(
    markers_m: Mapping[str, np.ndarray],
    rate_hz: float,
    model: NoiseModel,
    rng: np.random.Generator,
    hands: Sequence[str],
) -> dict[str, np.ndarray]:
    """Noisy copies of the (F, k, 3) marker arrays, in sorted instance order of random draws."""
    out: dict[str, np.ndarray] = {}
    for name in sorted(markers_m):
        clean = markers_m[name]
        slow_sigma = model.slow_hand_m if name in hands else model.slow_object_m
        slow = _smooth(rng.standard_normal(clean.shape), model.slow_time_s * rate_hz) * slow_sigma
        white = rng.standard_normal(clean.shape) * model.white_m
        out[name] = clean + slow + white
    return out


def random_gaps(
    labels: Mapping[str, Sequence[str]],
    n_frames: int,
    forbidden: Sequence[tuple[int, int]],
    rng: np.random.Generator,
    count: int = 8,
    min_len: int = 2,
    max_len: int = 6,
) -> list[Gap]:
    """``count`` short gaps on markers of multi-marker instances, outside the ``forbidden`` frame spans."""
    candidates = [(inst, lab) for inst in sorted(labels) if len(labels[inst]) > 1 for lab in labels[inst]]
    gaps: list[Gap] = []
    tries = 0
    while len(gaps) < count and tries < 1000:
        tries += 1
        inst, lab = candidates[int(rng.integers(len(candidates)))]
        length = int(rng.integers(min_len, max_len + 1))
        first = int(rng.integers(0, n_frames - length))
        last = first + length - 1
        if any(first <= b and last >= a for a, b in forbidden):
            continue
        if any(g.label == lab and first <= g.last + 5 and last >= g.first - 5 for g in gaps):
            continue
        gaps.append(Gap(inst, lab, first, last, "random dropout"))
    return sorted(gaps, key=lambda g: (g.first, g.instance, g.label))


def apply_gaps(
    markers_m: Mapping[str, np.ndarray], labels: Mapping[str, Sequence[str]], gaps: Sequence[Gap]
) -> dict[str, np.ndarray]:
    """Copies of the marker arrays with NaN on every gap's frames."""
    out = {k: v.copy() for k, v in markers_m.items()}
    for g in gaps:
        k = list(labels[g.instance]).index(g.label)
        out[g.instance][g.first : g.last + 1, k, :] = np.nan
    return out
