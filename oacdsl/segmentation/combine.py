"""The adaptive detector's per-pair state: the paper's rule OR the interval rules, AND NOT a veto.

The adaptive touch detector (:mod:`oacdsl.segmentation.adaptive`) decides an instance pair's
contact from two kinds of input: the paper's rule, marker pair by marker pair, chunk by chunk
(:class:`~oacdsl.segmentation.robust.RobustDetector`), and intervals found on the whole recording
before the chunks (co-motion and rests, tool contacts and holding still, cross-hand vetoes),
given as on/off *events* at causal frames. :class:`StateCombiner` follows each managed pair's
state over the chunks: touching while some marker pair touches by the paper's rule, or an episode
or a tool contact holds, and no veto does; a pair's state counts after all changes of a frame.
"""

from __future__ import annotations

import numpy as np

from oacdsl.segmentation.pairs import PairTable

__all__ = ["StateCombiner"]


class StateCombiner:
    """The combined state of every instance pair of ``table``, carried from chunk to chunk.

    Attributes (arrays over instance pairs ``Q`` or marker pairs ``P``): ``heads`` (Q,) the marker
    pair an instance pair's changes are reported on (its first); ``paper_count`` (Q,) its marker
    pairs touching by the paper's rule; ``pair_state`` (P,) each marker pair's paper state;
    ``flags`` (Q, 4) [unused, episode, tool, veto]; ``combined`` (Q,) the pair's state.
    """

    def __init__(self, table: PairTable) -> None:
        self.table = table
        n_q = table.n_instance_pairs
        self.heads = table.block_offsets[:-1].copy()
        self.paper_count = np.zeros(n_q, dtype=np.int64)
        self.pair_state = np.zeros(table.n_pairs, dtype=bool)
        self.flags = np.zeros((n_q, 4), dtype=bool)
        self.combined = np.zeros(n_q, dtype=bool)

    def combine(
        self, pairs: np.ndarray, frames: np.ndarray, touching: np.ndarray, events: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The managed blocks' combined state changes, ``(head pairs, frames, states)``.

        ``pairs``, ``frames``, ``touching``: the paper rule's changes of managed marker pairs
        (sorted by pair, then frame); ``events``: (E, 4) [causal frame, kind, on?, block] of the
        chunk. A block's state is (some marker pair touching by the paper's rule, or an episode
        or a tool contact) and not a veto; it is evaluated after all changes of a frame, in the
        order (frame, kind, value, pair) per block.
        """
        table = self.table
        # the paper's changes that change their marker pair's state (a flip repeats none, but be exact)
        previous = np.empty_like(touching)
        previous[1:] = touching[:-1]
        new_pair = np.ones(pairs.size, dtype=bool)
        new_pair[1:] = pairs[1:] != pairs[:-1]
        previous[new_pair] = self.pair_state[pairs[new_pair]]
        delta = np.where(touching != previous, np.where(touching, 1, -1), 0)
        last_of_pair = np.ones(pairs.size, dtype=bool)
        last_of_pair[:-1] = pairs[1:] != pairs[:-1]
        self.pair_state[pairs[last_of_pair]] = touching[last_of_pair]
        # all changes, block by block in the order the state is followed
        q = np.concatenate([table.block[pairs], events[:, 3]])
        f = np.concatenate([frames, events[:, 0]])
        kind = np.concatenate([np.zeros(pairs.size, dtype=np.intp), events[:, 1]])
        value = np.concatenate([touching.astype(np.intp), events[:, 2]])
        p = np.concatenate([pairs, np.full(events.shape[0], -1, dtype=np.intp)])
        step = np.concatenate([delta, np.zeros(events.shape[0], dtype=delta.dtype)])
        order = np.lexsort((p, value, kind, f, q))
        q, f, kind, value, step = q[order], f[order], kind[order], value[order], step[order]
        empty = np.zeros(0, dtype=np.intp)
        if q.size == 0:
            return empty, empty.copy(), np.zeros(0, dtype=bool)
        index = np.arange(q.size)
        group_start = np.ones(q.size, dtype=bool)
        group_start[1:] = q[1:] != q[:-1]
        first = np.maximum.accumulate(np.where(group_start, index, 0))  # first change of each one's block
        # touching marker pairs after each change
        total = np.cumsum(step)
        count = self.paper_count[q] + total - (total[first] - step[first])
        # each flag after each change: its last value so far in the block, else the block's own
        flag = []
        for k in (1, 2, 3):
            seen = np.maximum.accumulate(np.where(kind == k, index, -1))
            flag.append(np.where(seen >= first, value[np.maximum(seen, 0)] > 0, self.flags[q, k]))
        state = ((count > 0) | flag[0] | flag[1]) & ~flag[2]
        frame_end = np.ones(q.size, dtype=bool)  # the state after all changes of a frame counts
        frame_end[:-1] = (q[1:] != q[:-1]) | (f[1:] != f[:-1])
        eq, ef, es = q[frame_end], f[frame_end], state[frame_end]
        before = np.empty_like(es)
        before[1:] = es[:-1]
        block_start = np.ones(eq.size, dtype=bool)
        block_start[1:] = eq[1:] != eq[:-1]
        before[block_start] = self.combined[eq[block_start]]
        emit = es != before
        block_end = np.ones(q.size, dtype=bool)
        block_end[:-1] = q[1:] != q[:-1]
        done = q[block_end]
        self.paper_count[done] = count[block_end]
        for j, k in enumerate((1, 2, 3)):
            self.flags[done, k] = flag[j][block_end]
        self.combined[done] = state[block_end]
        return self.heads[eq[emit]], ef[emit], es[emit]
