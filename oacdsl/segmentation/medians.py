"""Column medians ignoring gaps, fast and exact: the co-motion scan's speeds and distance changes.

:func:`nanmedian0` is ``np.nanmedian(x, axis=0)``'s values without its wrappers (a sort, the middle
rows); :func:`median_rows` the same values, faster for the few markers of one instance: the
columns without a gap go through a network of element-wise minimum and maximum (selection
networks for 3, 4 and 5 rows, an odd–even transposition sort up to 8). Minimum and maximum
return one of their inputs exactly and a sum of two does not depend on their order, so every
value is the sorted median's, bit for bit (``tests/test_adaptive.py`` checks it).
"""

from __future__ import annotations

import numpy as np

__all__ = ["median_rows", "nanmedian0"]

_NETWORK_ROWS = 8  # up to this many markers an instance's median is sorted by a network


def nanmedian0(x: np.ndarray) -> np.ndarray:
    """Median over axis 0 ignoring NaN (NaN where a column has no value); faster than np.nanmedian."""
    if x.shape[0] == 0:
        return np.full(x.shape[1:], np.nan)
    ordered = np.sort(x, axis=0)  # NaN sort last
    k = x.shape[0]
    if not np.isnan(ordered[-1]).any():  # no NaN at all: the middle rows
        middle: np.ndarray = (ordered[(k - 1) // 2] + ordered[k // 2]) / 2
        return middle
    count = k - np.isnan(ordered).sum(axis=0)
    cols = np.arange(x.shape[1])
    lo = np.maximum(count - 1, 0) // 2
    hi = np.minimum(count // 2, k - 1)
    median = (ordered[lo, cols] + ordered[hi, cols]) / 2
    return np.where(count > 0, median, np.nan)


def median_rows(x: np.ndarray) -> np.ndarray:
    """:func:`nanmedian0` of (K, R), the same values; for K ≤ ``_NETWORK_ROWS`` the columns
    without a gap by a network of element-wise min/max (module doc)."""
    k = x.shape[0]
    if k == 0 or k > _NETWORK_ROWS:
        return nanmedian0(x)
    gap = np.isnan(x).any(axis=0)
    some = bool(gap.any())
    if not some:
        return _network_median(list(x))
    full = ~gap
    middle = _network_median([row[full] for row in x])
    out = np.empty(x.shape[1], dtype=middle.dtype)
    out[full] = middle
    out[gap] = nanmedian0(x[:, gap])
    return out


def _network_median(rows: list[np.ndarray]) -> np.ndarray:
    """The median of ``rows`` (K equal-length rows without NaN), element-wise: the middle value,
    or the mean of the two middle values, of each column."""
    k = len(rows)
    if k == 1:
        return (rows[0] + rows[0]) / 2
    if k == 2:
        return (rows[0] + rows[1]) / 2
    if k == 3:  # the middle of three
        a, b, c = rows
        return np.maximum(np.minimum(a, b), np.minimum(np.maximum(a, b), c))
    if k in (4, 5):
        # sorted pairs (l1 ≤ h1), (l2 ≤ h2): the least of the four is min(l1, l2), the greatest
        # max(h1, h2); the middle two are max(l1, l2) and min(h1, h2)
        l1, h1 = np.minimum(rows[0], rows[1]), np.maximum(rows[0], rows[1])
        l2, h2 = np.minimum(rows[2], rows[3]), np.maximum(rows[2], rows[3])
        lo, hi = np.maximum(l1, l2), np.minimum(h1, h2)
        if k == 4:
            return (lo + hi) / 2
        # five: without the least and the greatest of the first four (one at or below the median,
        # one at or above it), the median is the middle of the three left
        lo, hi = np.minimum(lo, hi), np.maximum(lo, hi)
        return np.maximum(lo, np.minimum(hi, rows[4]))
    for rnd in range(k):  # odd–even transposition sort
        for i in range(rnd % 2, k - 1, 2):
            rows[i], rows[i + 1] = np.minimum(rows[i], rows[i + 1]), np.maximum(rows[i], rows[i + 1])
    middle: np.ndarray = (rows[(k - 1) // 2] + rows[k // 2]) / 2
    return middle
