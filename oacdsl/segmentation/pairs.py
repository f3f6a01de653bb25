"""The table of marker pairs the AAS watches: every pair of markers of different instances.

Instances are taken in sorted name order, so an instance pair ``(A, B)`` with
``A < B`` is already the canonical relation. Marker pairs are numbered block by
block: all pairs of instance pair 0, then of instance pair 1, …; inside a block
``(A, B)`` the pair of A's i-th and B's j-th marker is ``offset + i * |B| + j``.
Reducing "instances touch while any pair of their markers touches" is then an
``any`` over one contiguous block.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from oacdsl.errors import SegmentationError
from oacdsl.segmentation.recording import Recording

__all__ = ["PairTable"]


@dataclass(frozen=True)
class PairTable:
    """Instances, their markers, and the cross-instance marker pairs of a recording.

    Attributes:
        instances: (I,) instance names, sorted.
        marker_order: (M',) recording marker indices, instance by instance (group order kept).
        marker_offsets: (I + 1,) where each instance's markers start in ``marker_order``.
        instance_pairs: (Q, 2) indices into ``instances``, ``i < j``, lexicographic.
        block_offsets: (Q + 1,) where each instance pair's marker pairs start.
        first: (P,) recording marker index of the pair's marker of the first instance.
        second: (P,) recording marker index of the pair's marker of the second instance.
        block: (P,) instance pair of each marker pair.
    """

    instances: tuple[str, ...]
    marker_order: np.ndarray
    marker_offsets: np.ndarray
    instance_pairs: np.ndarray
    block_offsets: np.ndarray
    first: np.ndarray
    second: np.ndarray
    block: np.ndarray

    @classmethod
    def of(cls, recording: Recording) -> PairTable:
        """Build the table; a marker in two instances' groups is an error."""
        names = tuple(sorted(recording.groups))
        owner: dict[int, str] = {}
        order: list[int] = []
        offsets = [0]
        for name in names:
            for m in recording.groups[name]:
                if m in owner and owner[m] != name:
                    raise SegmentationError(
                        f"marker {recording.marker_names[m]!r} belongs to both {owner[m]!r} and {name!r}",
                        location=recording.source,
                    )
                owner[m] = name
            unique = list(dict.fromkeys(recording.groups[name]))
            order.extend(unique)
            offsets.append(len(order))
        i_idx, j_idx = np.triu_indices(len(names), k=1)
        qpairs = np.stack([i_idx, j_idx], axis=1).astype(np.intp).reshape(-1, 2)
        order_arr = np.asarray(order, dtype=np.intp)
        sizes = np.diff(np.asarray(offsets))
        block_sizes = sizes[qpairs[:, 0]] * sizes[qpairs[:, 1]]
        block_offsets = np.concatenate([[0], np.cumsum(block_sizes)]).astype(np.intp)
        first: list[np.ndarray] = []
        second: list[np.ndarray] = []
        for a, b in qpairs:
            ma = order_arr[offsets[a] : offsets[a + 1]]
            mb = order_arr[offsets[b] : offsets[b + 1]]
            first.append(np.repeat(ma, len(mb)))
            second.append(np.tile(mb, len(ma)))
        empty = np.zeros(0, dtype=np.intp)
        return cls(
            instances=names,
            marker_order=order_arr,
            marker_offsets=np.asarray(offsets, dtype=np.intp),
            instance_pairs=qpairs,
            block_offsets=block_offsets,
            first=np.concatenate(first) if first else empty,
            second=np.concatenate(second) if second else empty,
            block=np.repeat(np.arange(len(qpairs), dtype=np.intp), block_sizes),
        )

    @property
    def n_pairs(self) -> int:
        """P, the number of cross-instance marker pairs."""
        return int(self.block_offsets[-1])

    @property
    def n_instance_pairs(self) -> int:
        """Q, the number of instance pairs."""
        return int(self.instance_pairs.shape[0])

    def relation(self, q: int) -> tuple[str, str]:
        """The (sorted) instance names of instance pair ``q``."""
        a, b = self.instance_pairs[q]
        return self.instances[int(a)], self.instances[int(b)]

    def block_pairs(self, blocks: np.ndarray) -> np.ndarray:
        """The marker-pair indices of the given instance pairs, in table order."""
        blocks = np.asarray(blocks, dtype=np.intp)
        if blocks.size == 0:
            return np.zeros(0, dtype=np.intp)
        starts = self.block_offsets[blocks]
        lengths = self.block_offsets[blocks + 1] - starts
        ends = np.cumsum(lengths)
        shift = np.repeat(starts - (ends - lengths), lengths)
        return np.arange(int(ends[-1]), dtype=np.intp) + shift
