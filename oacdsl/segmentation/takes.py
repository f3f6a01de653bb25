"""Other takes of a recording: the same demonstration as another person or lab would record it.

Every function returns a new :class:`Recording` (the input is never changed); marker names
and groups are kept, so a take is segmented, matched and composed with the same library
and scene as its original.

* :func:`rotated` about the vertical (z) axis, :func:`translated`, :func:`scaled` (a larger
  person at a larger table: by default about the recording's mean xy on the floor, z = 0);
* :func:`stretched` in time (factor 2 = twice as long, i.e. half the speed; same frame rate)
  and :func:`resampled` to another frame rate, optionally with Gaussian jitter;
* :func:`with_gap`: one marker missing for a while;
* :func:`mirrored` (:mod:`oacdsl.segmentation.mirror`): a left-handed take of a
  right-handed demonstration.

Time is resampled by linear interpolation that respects gaps: a new sample between two
frames is a gap (NaN) when either of them is; a gap stays a gap (it may grow by up to
one original frame interval at each end), nothing is interpolated across it.

:data:`STANDARD_TAKES` holds the seven takes every invariance measurement uses (issue 20):
name → function ``(recording) -> (take, hand_map)``; ``hand_map`` maps an instance of the
original to the instance that plays its part in the take (the hands exchanged for the
mirror, the identity otherwise).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from oacdsl.errors import RecordingError
from oacdsl.segmentation.mirror import HANDS, hand_indices, mirrored, subject_indices
from oacdsl.segmentation.recording import Recording

__all__ = [
    "IDENTITY",
    "STANDARD_DESCRIPTIONS",
    "STANDARD_TAKES",
    "Take",
    "gap_marker",
    "mirrored",
    "resampled",
    "rotated",
    "scaled",
    "stretched",
    "translated",
    "with_gap",
]

#: The hand map of a take that keeps the hands where they are.
IDENTITY: Mapping[str, str] = {h: h for h in HANDS}

#: A standard take: the recording → (the take, original instance → the take's instance).
Take = Callable[[Recording], tuple[Recording, dict[str, str]]]


def _copy(
    rec: Recording,
    positions_m: np.ndarray,
    what: str,
    times_s: np.ndarray | None = None,
    rate_hz: float | None = None,
) -> Recording:
    return Recording(
        f"{rec.source} ({what})",
        rec.rate_hz if rate_hz is None else float(rate_hz),
        rec.times_s.copy() if times_s is None else times_s,
        rec.marker_names,
        positions_m,
        dict(rec.groups),
        rec.first_frame,
    )


def _finite(value: float, what: str, rec: Recording, positive: bool = False) -> float:
    v = float(value)
    if not np.isfinite(v) or (positive and v <= 0):
        kind = "a positive number" if positive else "a finite number"
        raise RecordingError(f"{what} must be {kind}, got {value!r}", location=rec.source)
    return v


def _mean_xy(rec: Recording) -> np.ndarray:
    xy = rec.positions_m[..., :2].reshape(-1, 2)
    xy = xy[np.all(np.isfinite(xy), axis=1)]
    if xy.size == 0:
        raise RecordingError("every marker is a gap in every frame", location=rec.source)
    return np.asarray(xy.mean(axis=0), dtype=np.float64)


def rotated(rec: Recording, angle_rad: float, about_xy_m: Sequence[float] | None = None) -> Recording:
    """The recording rotated by ``angle_rad`` (counter-clockwise seen from above) about the
    vertical line through ``about_xy_m`` (default: the mean xy of every marker and frame)."""
    angle = _finite(angle_rad, "the angle", rec)
    centre = _mean_xy(rec) if about_xy_m is None else np.asarray(about_xy_m, dtype=np.float64)[:2]
    c, s = np.cos(angle), np.sin(angle)
    out = rec.positions_m.copy()
    x, y = out[..., 0] - centre[0], out[..., 1] - centre[1]
    out[..., 0] = centre[0] + c * x - s * y
    out[..., 1] = centre[1] + s * x + c * y
    return _copy(rec, out, f"rotated {np.degrees(angle):g} deg")


def translated(rec: Recording, offset_m: Sequence[float]) -> Recording:
    """The recording moved by ``offset_m`` (x, y[, z]) metres."""
    offset = np.zeros(3)
    given = np.asarray(offset_m, dtype=np.float64).ravel()
    if given.size not in (2, 3) or not np.all(np.isfinite(given)):
        raise RecordingError(f"an offset is 2 or 3 finite lengths, got {list(offset_m)}", location=rec.source)
    offset[: given.size] = given
    return _copy(rec, rec.positions_m + offset, f"translated {offset.tolist()} m")


def scaled(rec: Recording, factor: float, about_m: Sequence[float] | None = None) -> Recording:
    """Every position scaled by ``factor`` about ``about_m`` (default: the recording's mean xy
    at z = 0, the floor: a larger person at a larger table)."""
    k = _finite(factor, "the scale factor", rec, positive=True)
    centre = np.zeros(3)
    if about_m is None:
        centre[:2] = _mean_xy(rec)
    else:
        centre[:] = np.asarray(about_m, dtype=np.float64).ravel()[:3]
    return _copy(rec, centre + k * (rec.positions_m - centre), f"scaled x{k:g}")


def _sample(rec: Recording, at_s: np.ndarray) -> np.ndarray:
    """(len(at_s), M, 3) positions at the times ``at_s`` (within the recording), interpolated
    linearly between the two frames around each time; a gap in either of them is a gap."""
    t = rec.times_s
    p = rec.positions_m
    if t.size == 1:
        return np.repeat(p[:1], at_s.size, axis=0)
    i = np.clip(np.searchsorted(t, at_s, side="right") - 1, 0, t.size - 2)
    step = t[i + 1] - t[i]
    w = np.clip((at_s - t[i]) / np.where(step > 0, step, 1.0), 0.0, 1.0)
    tol = 1e-9
    w = np.where(w < tol, 0.0, np.where(w > 1 - tol, 1.0, w))[:, None, None]
    lo, hi = p[i], p[i + 1]
    out = lo + w * (hi - lo)  # NaN where either frame is a gap
    out = np.where(w == 0.0, lo, out)  # on a frame: that frame, whatever its neighbour holds
    return np.where(w == 1.0, hi, out)


def _frame_times(start_s: float, duration_s: float, rate_hz: float) -> np.ndarray:
    n = int(np.floor(duration_s * rate_hz + 1e-6)) + 1
    return start_s + np.arange(n, dtype=np.float64) / rate_hz


def stretched(rec: Recording, factor: float) -> Recording:
    """The demonstration done ``factor`` times as slowly (2: twice as long, half the speed;
    0.5: twice as fast), recorded at the same frame rate (frames interpolated, gaps kept)."""
    k = _finite(factor, "the time factor", rec, positive=True)
    t0 = float(rec.times_s[0])
    duration = float(rec.times_s[-1] - t0)
    new_t = _frame_times(t0, duration * k, rec.rate_hz)
    return _copy(rec, _sample(rec, t0 + (new_t - t0) / k), f"time x{k:g}", times_s=new_t - t0)


def resampled(rec: Recording, rate_hz: float, jitter_m: float = 0.0, seed: int = 0) -> Recording:
    """The recording at ``rate_hz`` (frames interpolated, gaps kept), each coordinate with
    independent Gaussian noise of standard deviation ``jitter_m`` (drawn from ``seed``)."""
    rate = _finite(rate_hz, "the frame rate", rec, positive=True)
    jitter = _finite(jitter_m, "the jitter", rec)
    if jitter < 0:
        raise RecordingError(f"the jitter must be ≥ 0, got {jitter_m!r}", location=rec.source)
    t0 = float(rec.times_s[0])
    new_t = _frame_times(t0, float(rec.times_s[-1] - t0), rate)
    out = _sample(rec, new_t)
    if jitter > 0:
        out = out + np.random.default_rng(seed).normal(0.0, jitter, out.shape)
    what = f"{rate:g} Hz" + (f", jitter {jitter * 1000:g} mm" if jitter else "")
    return _copy(rec, out, what, times_s=new_t - t0, rate_hz=rate)


def _marker_index(rec: Recording, marker: str) -> int:
    from oacdsl.segmentation.grouping import resolve_markers

    found = resolve_markers(rec, [marker], "gap")
    if len(found) != 1:
        raise RecordingError(f"{marker!r} names {len(found)} markers; give one", location=rec.source)
    return found[0]


def with_gap(rec: Recording, marker: str, start_s: float, duration_s: float) -> Recording:
    """The recording with ``marker`` (a label, or its name without the group prefix) missing
    in every frame from ``start_s`` (inclusive) for ``duration_s`` seconds."""
    i = _marker_index(rec, marker)
    start = _finite(start_s, "the gap's start", rec)
    duration = _finite(duration_s, "the gap's duration", rec, positive=True)
    t = rec.times_s
    inside = (t >= start - 1e-9) & (t < start + duration - 1e-9)
    if not inside.any():
        raise RecordingError(
            f"a gap from {start:g} s for {duration:g} s holds no frame of the recording"
            f" ({t[0]:g} s to {t[-1]:g} s)",
            location=rec.source,
        )
    out = rec.positions_m.copy()
    out[inside, i] = np.nan
    return _copy(rec, out, f"gap in {rec.marker_names[i]} at {start:g} s for {duration:g} s")


def gap_marker(rec: Recording, duration_s: float) -> tuple[str, float]:
    """Where the standard gap goes: (marker label, start s).

    The object (a group that holds no marker of a hand or of the subject's torso, and is not
    named for a hand or a subject) whose markers' centroid travels farthest; its first marker
    with the fewest gaps; the ``duration_s`` window in which that object moves most."""
    skip = set(subject_indices(rec)) | {i for side in HANDS for i in hand_indices(rec, side)}
    objects = [
        (g, list(idx))
        for g, idx in sorted(rec.groups.items())
        if not skip.intersection(idx) and "hand" not in g.lower() and not g.startswith("subject")
    ]
    if not objects:
        raise RecordingError(
            "no object marker for a gap (every group is a hand or the subject)", location=rec.source
        )

    def steps(idx: list[int]) -> np.ndarray:
        with warnings.catch_warnings():  # a frame where every marker is a gap: NaN, no warning
            warnings.simplefilter("ignore", RuntimeWarning)
            centre = np.nanmean(rec.positions_m[:, idx], axis=1)
        d = np.linalg.norm(np.diff(centre, axis=0), axis=1)
        return np.nan_to_num(d, nan=0.0)

    travel = [float(steps(idx).sum()) for _, idx in objects]
    _, idx = objects[int(np.argmax(travel))]  # the first of equals: deterministic
    gaps = [int(np.isnan(rec.positions_m[:, i, 0]).sum()) for i in idx]
    marker = idx[int(np.argmin(gaps))]
    d = steps(idx)
    n = max(1, int(round(duration_s * rec.rate_hz)))
    if d.size <= n:
        return rec.marker_names[marker], float(rec.times_s[0])
    window = np.convolve(d, np.ones(n), mode="valid")  # motion in frames [k, k + n]
    k = int(np.argmax(window))
    return rec.marker_names[marker], float(rec.times_s[k])


def _standard_gap(rec: Recording) -> Recording:
    marker, start = gap_marker(rec, 0.5)
    return with_gap(rec, marker, start, 0.5)


def _same_hands(fn: Callable[[Recording], Recording]) -> Take:
    def take(rec: Recording) -> tuple[Recording, dict[str, str]]:
        return fn(rec), dict(IDENTITY)

    take.__doc__ = fn.__doc__
    return take


def _mirror_take(rec: Recording) -> tuple[Recording, dict[str, str]]:
    return mirrored(rec)


#: The seven takes of issue 20: name → ``(recording) -> (take, hand_map)``.
STANDARD_TAKES: dict[str, Take] = {
    "mirrored": _mirror_take,
    "rotated_translated": _same_hands(lambda r: translated(rotated(r, np.pi / 2), (2.0, 0.0, 0.0))),
    "half_speed": _same_hands(lambda r: stretched(r, 2.0)),
    "double_speed": _same_hands(lambda r: stretched(r, 0.5)),
    "resampled_100hz": _same_hands(lambda r: resampled(r, 100.0, jitter_m=0.0002, seed=0)),
    "marker_gap": _same_hands(_standard_gap),
    "scaled": _same_hands(lambda r: scaled(r, 1.15)),
}

#: One line per standard take, for help texts and docs.
STANDARD_DESCRIPTIONS: dict[str, str] = {
    "mirrored": "reflected across the demonstrator's sagittal plane, left and right exchanged",
    "rotated_translated": "rotated 90 deg about the vertical, then moved 2 m along x",
    "half_speed": "done at half the speed (twice as long), same frame rate",
    "double_speed": "done at twice the speed (half as long), same frame rate",
    "resampled_100hz": "resampled to 100 Hz with 0.2 mm Gaussian jitter (seed 0)",
    "marker_gap": "a 0.5 s gap in one object marker, while that object moves most",
    "scaled": "15 % larger (x1.15 about the mean xy on the floor)",
}
