"""The distance change in physical time: a least-squares slope over a centred window.

Eq. 1 / Eq. 2 compare the one-frame difference ``|dist[i] - dist[i-1]|`` with
``v Δt``. Its noise grows with the frame rate: white marker jitter of σ per
coordinate gives a distance noise of about ``√2 σ`` and a one-frame rate noise of
about ``2 σ · rate`` (0.5 mm at 240 Hz: 240 mm/s, above any sensible ``v``).

The robust estimate is the slope (m/s) of the straight line fitted by least squares
to the distances of the frames whose centre lies within ``±half`` frames of frame
``i`` (a first-order Savitzky–Golay derivative, with the recording's real frame
times). For ``N = 2 half + 1`` evenly spaced samples its noise is
``√2 σ · √12 / (Δt · N^1.5)`` — about ``σ √24 / (w^1.5 √rate)`` for a window of
``w`` seconds: it *falls* as the rate rises. Missing samples (NaN) are left out of
the fit, so a gap shortens the window instead of ending the estimate; with fewer than
``min_count`` samples the slope is unknown (NaN). At the recording's first frames the
window is cut at frame 0 (one-sided fit).

Sums come from prefix sums (float64), so the cost per sample is constant whatever
the window; where only a few frames of a block need a slope (the detectors fit it only within
``d``), :func:`windowed_slope_at` sums their windows directly instead, times centred on each
window's own frame (the same slopes to float64 rounding).
"""

from __future__ import annotations

import numpy as np

__all__ = ["min_samples", "windowed_slope", "windowed_slope_at"]


def min_samples(half: int) -> int:
    """The fewest valid samples for a slope: more than half of the ``2 half + 1`` window."""
    return half + 1


def windowed_slope(
    dist: np.ndarray, times_s: np.ndarray, half: int, min_count: int | None = None
) -> np.ndarray:
    """(A, R) slopes, m/s: per row and column ``c``, the least-squares slope of ``dist``
    against ``times_s`` over columns ``max(0, c - half) .. min(R - 1, c + half)``.

    ``dist``: (A, R) metres (NaN = missing), ``times_s``: (R,) seconds, increasing.
    Columns whose window holds fewer than ``min_count`` valid samples (default
    :func:`min_samples`) are NaN. Windows are cut at both ends of the array: callers use
    only columns whose window lies inside the array, or starts at the recording's start.
    """
    a, r = dist.shape
    if min_count is None:
        min_count = min_samples(half)
    if r == 0 or a == 0:
        return np.full((a, r), np.nan, dtype=np.float32)
    t = np.asarray(times_s, dtype=np.float64)
    t = t - t[r // 2]  # centred: smaller numbers, less cancellation
    valid = ~np.isnan(dist)
    x = np.where(valid, dist, 0.0).astype(np.float64)
    sx, stx = _window_sum(x, half), _window_sum(x * t, half)
    ones = np.ones((1, r))
    s0, s1, s2 = (_window_sum(ones, half), _window_sum(ones * t, half), _window_sum(ones * t * t, half))
    gappy = np.flatnonzero(~valid.all(axis=1))  # rows with a gap: their own sums (the same where valid)
    if gappy.size:
        s0, s1, s2 = (np.repeat(s, a, axis=0) for s in (s0, s1, s2))
        w = valid[gappy].astype(np.float64)
        s0[gappy], s1[gappy], s2[gappy] = (
            _window_sum(w, half),
            _window_sum(w * t, half),
            _window_sum(w * t * t, half),
        )
    den = s0 * s2 - s1 * s1
    with np.errstate(invalid="ignore", divide="ignore"):
        slope = (s0 * stx - s1 * sx) / den
    slope[np.broadcast_to(s0 < min_count, slope.shape) | ~(den > 0)] = np.nan
    return slope.astype(np.float32)


def windowed_slope_at(dist: np.ndarray, times_s: np.ndarray, half: int, rows: np.ndarray,
                      cols: np.ndarray, min_count: int | None = None) -> np.ndarray:
    """``windowed_slope(dist, times_s, half, min_count)[rows, cols]``, computed only there.

    Either the prefix sums are taken over the whole rows that hold a requested column (the
    same sums as :func:`windowed_slope`, bit for bit), the rest only at the requested columns:
    the cost of a row is two prefix sums plus a constant per requested column; or, when the
    requested windows hold fewer samples than those rows (by :data:`DIRECT_COST`), each window
    is summed directly (:func:`_slope_direct`, equal to float64 rounding). ``rows``, ``cols``:
    (K,) indices; returns (K,) float32 m/s.
    """
    a, r = dist.shape
    if min_count is None:
        min_count = min_samples(half)
    if rows.size == 0 or r == 0:
        return np.full(rows.size, np.nan, dtype=np.float32)
    t = np.asarray(times_s, dtype=np.float64)
    if (2 * half + 1) * rows.size * DIRECT_COST < _rows_held(rows) * r:  # few places: sum their windows
        return _slope_direct(dist, t, half, rows, cols, min_count)
    t = t - t[r // 2]  # centred as in windowed_slope
    if rows.size < 2 or bool((rows[1:] >= rows[:-1]).all()):  # sorted (np.nonzero's order): no sort
        new_row = np.empty(rows.size, dtype=bool)
        new_row[0] = True
        np.not_equal(rows[1:], rows[:-1], out=new_row[1:])
        used, local = rows[new_row], new_row.cumsum() - 1  # rows that hold a requested column
    else:
        used, local = np.unique(rows, return_inverse=True)
    x = (dist if used.size == a else dist[used]).astype(np.float64)  # every row requested: no gather
    gap = np.isnan(x)
    np.copyto(x, 0.0, where=gap)  # as np.where(valid, sub, 0.0)
    lo = np.maximum(cols - half, 0)
    hi = np.minimum(cols + half + 1, r)
    px = _prefix(x)
    np.multiply(x, t, out=x)
    ptx = _prefix(x)
    sx, stx = px[local, hi] - px[local, lo], ptx[local, hi] - ptx[local, lo]
    p1, p2 = _prefix(t[None, :])[0], _prefix((t * t)[None, :])[0]
    # the sample count of a full row's window: hi - lo, exactly (the prefix sums of ones, as floats)
    s0, s1, s2 = (hi - lo).astype(np.float64), p1[hi] - p1[lo], p2[hi] - p2[lo]
    gappy_rows = np.asarray(gap.any(axis=1))
    if gappy_rows.any():  # rows with a gap: their own sums (the same where valid)
        g = gappy_rows.nonzero()[0]
        w = (~gap[g]).astype(np.float64)
        where = np.full(used.size, -1, dtype=np.intp)
        where[g] = np.arange(g.size)
        k = gappy_rows[local].nonzero()[0]
        gl = where[local[k]]
        q0 = _prefix(w)
        np.multiply(w, t, out=w)
        q1 = _prefix(w)
        np.multiply(w, t, out=w)
        q2 = _prefix(w)
        s0[k], s1[k], s2[k] = (q0[gl, hi[k]] - q0[gl, lo[k]], q1[gl, hi[k]] - q1[gl, lo[k]],
                               q2[gl, hi[k]] - q2[gl, lo[k]])
    den = s0 * s2 - s1 * s1
    with np.errstate(invalid="ignore", divide="ignore"):
        slope = (s0 * stx - s1 * sx) / den
    slope[(s0 < min_count) | ~(den > 0)] = np.nan
    return slope.astype(np.float32)


#: Cost of one sample of a window summed directly against one element of the prefix sums (both
#: in numpy passes; measured on the benchmark's recordings): :func:`windowed_slope_at` sums the
#: windows directly when that is the cheaper.
DIRECT_COST = 1.5


def _rows_held(rows: np.ndarray) -> int:
    """How many distinct rows ``rows`` names (an upper bound when unsorted: its length)."""
    if rows.size < 2 or not bool((rows[1:] >= rows[:-1]).all()):
        return int(rows.size)
    return int(np.count_nonzero(rows[1:] != rows[:-1])) + 1


def _slope_direct(dist: np.ndarray, t: np.ndarray, half: int, rows: np.ndarray, cols: np.ndarray,
                  min_count: int) -> np.ndarray:
    """:func:`windowed_slope_at` by summing each requested window sample by sample, times centred
    on the window's own frame (the same least-squares slope as the prefix sums', to float64
    rounding; it depends on no other frame of the chunk)."""
    r = dist.shape[1]
    flat = np.ascontiguousarray(dist).reshape(-1)
    base = rows * r + cols
    centre = t.take(cols)
    cut = bool(cols.min() < half or cols.max() >= r - half)  # windows cut at the array's ends
    s0: np.ndarray | float = 0.0
    s1 = np.zeros(cols.size)
    s2, sx, stx = s1.copy(), s1.copy(), s1.copy()
    for k in range(-half, half + 1):
        if cut:
            j = cols + k
            inside = (j >= 0) & (j < r)
            np.clip(j, 0, r - 1, out=j)
            x = flat.take(base + (j - cols))
            x[~inside] = np.nan  # beyond the array: as a gap
            dt = t.take(j)
        else:
            x = flat.take(base + k)
            dt = t.take(cols + k)
        dt -= centre  # seconds from the window's own frame
        gap = np.isnan(x)
        if gap.any():  # gaps are left out of the sums
            x[gap] = 0.0
            dt[gap] = 0.0
            s0 = s0 + ~gap
        else:
            s0 = s0 + 1.0
        sx += x
        if k == 0:  # the window's own frame: no time from it, nothing to add to the other sums
            continue
        s1 += dt
        x64 = x * dt
        stx += x64
        dt *= dt
        s2 += dt
    den = s0 * s2 - s1 * s1
    with np.errstate(invalid="ignore", divide="ignore"):
        slope = (s0 * stx - s1 * sx) / den
    slope[np.broadcast_to(np.asarray(s0) < min_count, slope.shape) | ~(den > 0)] = np.nan
    return slope.astype(np.float32)


def _prefix(x: np.ndarray) -> np.ndarray:
    """(K, R + 1) float64 prefix sums of the rows of ``x`` (K, R), a 0 first."""
    prefix = np.empty((x.shape[0], x.shape[1] + 1))
    prefix[:, 0] = 0.0
    np.cumsum(x, axis=1, out=prefix[:, 1:])
    return prefix


def _window_sum(x: np.ndarray, half: int) -> np.ndarray:
    """Row sums of ``x`` (K, R) over columns ``max(0, c - half) .. min(R, c + half + 1) - 1``, by
    prefix sums: the full windows by two slices, the cut ones at both ends by index."""
    r = x.shape[1]
    prefix = np.zeros((x.shape[0], r + 1))
    np.cumsum(x, axis=1, out=prefix[:, 1:])
    out = np.empty((x.shape[0], r))
    width = 2 * half + 1
    if r >= width:
        np.subtract(prefix[:, width:], prefix[:, : r - width + 1], out=out[:, half : r - half])
        edge = np.concatenate([np.arange(half), np.arange(r - half, r)])
    else:
        edge = np.arange(r)
    out[:, edge] = prefix[:, np.minimum(edge + half + 1, r)] - prefix[:, np.maximum(edge - half, 0)]
    return out
