"""Runs of ``n`` frames and set/reset flips, vectorised: Eq. 1 / Eq. 2's "n frames in a row".

Shared by the paper's detector (:mod:`~oacdsl.segmentation.paper`) and the robust one
(:mod:`~oacdsl.segmentation.robust`): both decide per frame whether a marker pair is
*close* or *far*, and a pair flips where a run of ``n`` close (far) frames completes.
"""

from __future__ import annotations

import numpy as np

__all__ = ["flips", "windows"]


def windows(cond: np.ndarray, first: int, n_out: int, n: int) -> np.ndarray:
    """(A, n_out): ``cond`` held in all ``n`` columns ending at each output column.

    Columns before 0 count as "did not hold". Windows of length 2^k are built by
    doubling, so the cost grows with log2(n), not n.
    """
    if first < n - 1:  # recording start: pad
        pad = n - 1 - first
        cond = np.concatenate([np.zeros((cond.shape[0], pad), dtype=bool), cond], axis=1)
        first += pad
    span = cond[:, first - n + 1 : first + n_out]  # n_out + n - 1 columns
    result = np.ones((cond.shape[0], n_out), dtype=bool)
    offset, size, power = 0, 1, span  # power[:, j]: all of span[:, j:j+size]
    while size <= n:
        if n & size:
            np.logical_and(result, power[:, offset : offset + n_out], out=result)
            offset += size
        if size * 2 <= n:
            power = power[:, :-size] & power[:, size:]
        size *= 2
    return result


def flips(
    sets: np.ndarray, resets: np.ndarray, state0: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where a set/reset flip-flop changes: ``(rows, cols, new_state)``, sorted by row then column.

    ``sets`` and ``resets`` are never true together. The state is the type of the
    latest event (``state0`` before the first); it can only change at the first
    column of a run of events of one type, so only those rising edges are examined.
    """
    edges = np.empty(sets.shape, dtype=bool)
    edges[:, 0] = sets[:, 0] | resets[:, 0]
    np.greater(sets[:, 1:], sets[:, :-1], out=edges[:, 1:])
    edges[:, 1:] |= resets[:, 1:] > resets[:, :-1]
    rows, cols = np.divmod(np.flatnonzero(edges), sets.shape[1])  # faster than 2-D nonzero
    kind = sets[rows, cols]
    previous = np.empty_like(kind)
    previous[1:] = kind[:-1]
    first_in_row = np.concatenate(([True], rows[1:] != rows[:-1])) if rows.size else np.zeros(0, dtype=bool)
    previous[first_in_row] = state0[rows[first_in_row]]
    flip = kind != previous
    return rows[flip], cols[flip], kind[flip]
