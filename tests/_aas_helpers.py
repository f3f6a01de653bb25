"""Hand-made recordings for the AAS tests (positions in metres)."""

from __future__ import annotations

import numpy as np

from oacdsl.segmentation.recording import Recording


def recording(tracks: dict[str, np.ndarray], rate_hz: float = 100.0, source: str = "test") -> Recording:
    """A recording from ``{instance: (F, k, 3) or (F, 3) positions}``; marker names ``inst.i``."""
    names: list[str] = []
    cols: list[np.ndarray] = []
    groups: dict[str, tuple[int, ...]] = {}
    for inst, arr in tracks.items():
        arr = np.asarray(arr, dtype=np.float64)
        if arr.ndim == 2:
            arr = arr[:, None, :]
        idx = []
        for k in range(arr.shape[1]):
            idx.append(len(names))
            names.append(f"{inst}.{k}")
            cols.append(arr[:, k, :])
        groups[inst] = tuple(idx)
    pos = np.stack(cols, axis=1)
    times = np.arange(pos.shape[0]) / rate_hz
    return Recording(source, rate_hz, times, tuple(names), pos, groups)


def path(frames: int, keys: list[tuple[int, tuple[float, float, float]]]) -> np.ndarray:
    """(F, 3) piecewise-linear path through ``(frame, xyz)`` keys, constant outside."""
    f = np.arange(frames)
    ks = [k for k, _ in keys]
    pts = np.array([p for _, p in keys], dtype=np.float64)
    return np.stack([np.interp(f, ks, pts[:, i]) for i in range(3)], axis=1)


def still(frames: int, xyz: tuple[float, float, float]) -> np.ndarray:
    return np.tile(np.asarray(xyz, dtype=np.float64), (frames, 1))


def summary(seg) -> list[tuple[int, list[tuple[str, str]]]]:
    """``[(frame, sorted relations)]`` of a segmentation, for compact asserts."""
    return [(k.frame, k.state.sorted_relations()) for k in seg.keyframes]


def grid_scene(rng: np.random.Generator, frames: int, n_inst: int, markers: int,
               gap_rate: float = 0.02) -> Recording:
    """Random rigid clusters stepping on a 1 cm grid, with NaN gaps.

    On this grid every marker distance is ``sqrt(integer)`` cm: none lies within
    0.08 mm of 155 mm, and a non-zero distance change is at least 0.08 mm. With
    ``d = 0.155 m`` and ``v = 0.001 m/s`` at 100 Hz (0.01 mm per frame) no decision
    sits near a threshold, so float32 rounding, marker order or a rigid motion of the
    scene cannot flip one.
    """
    cent = np.zeros((frames, n_inst, 3))
    c = rng.integers(0, 30, (n_inst, 3)).astype(float)
    for f in range(frames):
        move = rng.random(n_inst) < 0.5
        c = np.clip(c + move[:, None] * rng.integers(-1, 2, (n_inst, 3)), 0, 30)
        cent[f] = c
    off = rng.integers(-3, 4, (n_inst, markers, 3))
    pos = (cent[:, :, None, :] + off[None]) * 0.01
    pos[rng.random((frames, n_inst, markers)) < gap_rate] = np.nan
    return recording({f"o{i}": pos[:, i] for i in range(n_inst)})


def on_spans(keyframes: list, pair: tuple[str, str]) -> list[tuple[int, int | None]]:
    """Frame intervals ``[a, b)`` in which ``pair`` touches (``b`` None: to the end), from
    ``summary`` keyframes."""
    out: list[tuple[int, int | None]] = []
    start = None
    for frame, rels in keyframes:
        if pair in rels and start is None:
            start = frame
        elif pair not in rels and start is not None:
            out.append((start, frame))
            start = None
    return out + ([(start, None)] if start is not None else [])


def closest_m(tracks: dict[str, np.ndarray], a: str, b: str) -> np.ndarray:
    """(F,) distance of the nearest markers of instances ``a`` and ``b`` in each frame, metres."""
    return np.linalg.norm(tracks[a][:, :, None] - tracks[b][:, None], axis=3).min(axis=(1, 2))
