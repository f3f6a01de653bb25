"""Instances touch while any pair of their markers touches: from marker-pair changes to relation changes.

Per instance pair the tracker counts its touching marker pairs; a relation
begins when the count leaves 0 and ends when it returns to 0. Everything is
computed on the (few) changes, never on a per-frame array.
"""

from __future__ import annotations

import numpy as np

from oacdsl.segmentation.detectors import PairChanges
from oacdsl.segmentation.pairs import PairTable

__all__ = ["InstanceTouch"]


class InstanceTouch:
    """The touching state of every marker pair and instance pair, updated by :class:`PairChanges`."""

    def __init__(self, table: PairTable) -> None:
        self._block = table.block
        self.pair_state = np.zeros(table.n_pairs, dtype=bool)
        self.count = np.zeros(table.n_instance_pairs, dtype=np.int64)

    @property
    def touching(self) -> np.ndarray:
        """(Q,) bool: instance pairs touching now (after the changes applied so far)."""
        result: np.ndarray = self.count > 0
        return result

    def apply(self, changes: PairChanges) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Apply one chunk's pair changes; return ``(frames, instance_pairs, touching)`` of relation changes.

        Changes that repeat a pair's current state are ignored. Within one frame the
        net effect counts: one marker pair ending while another begins is no change.
        """
        order = np.lexsort((changes.frames, changes.pairs))
        pairs, frames, value = changes.pairs[order], changes.frames[order], changes.touching[order]
        if pairs.size:
            previous = np.empty_like(value)
            previous[1:] = value[:-1]
            first = np.concatenate(([True], pairs[1:] != pairs[:-1]))
            previous[first] = self.pair_state[pairs[first]]
            keep = value != previous
            pairs, frames, value = pairs[keep], frames[keep], value[keep]
        if pairs.size == 0:
            empty = np.zeros(0, dtype=np.intp)
            return empty, empty.copy(), np.zeros(0, dtype=bool)
        last = np.concatenate((pairs[1:] != pairs[:-1], [True]))
        self.pair_state[pairs[last]] = value[last]

        q = self._block[pairs]
        delta = np.where(value, 1, -1)
        order = np.lexsort((frames, q))
        q, frames, delta = q[order], frames[order], delta[order]
        q_first = np.concatenate(([True], q[1:] != q[:-1]))
        total = np.cumsum(delta)
        starts = np.flatnonzero(q_first)
        before_group = (total[starts] - delta[starts])[np.cumsum(q_first) - 1]
        running = self.count[q] + total - before_group  # touching marker pairs after each change
        frame_last = np.concatenate(((q[1:] != q[:-1]) | (frames[1:] != frames[:-1]), [True]))
        lq, lf, after = q[frame_last], frames[frame_last], running[frame_last] > 0
        before = np.empty_like(after)
        before[1:] = after[:-1]
        new_q = np.concatenate(([True], lq[1:] != lq[:-1]))
        before[new_q] = self.count[lq[new_q]] > 0
        q_last = np.concatenate((q[1:] != q[:-1], [True]))
        self.count[q[q_last]] = running[q_last]
        emit = after != before
        return lf[emit], lq[emit], after[emit]
