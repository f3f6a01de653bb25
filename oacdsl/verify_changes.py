"""The changes of a sequence of world states and their alignment (:mod:`oacdsl.verify`): a
*change* is what one keyframe transition added and removed; two sequences of changes are
aligned by the Levenshtein distance (insertion, deletion, substitution 1 each).

**Split changes.** A person's two hands let go within a moment; the demonstration's
segmentation merges events closer than its merge window (0.3 s) into one change, while a
robot that puts two objects down (or ends a pour and then puts the carton down) makes the
same changes a second or more apart. So one demonstration change also *matches*, at cost
0, a run of two or more consecutive robot changes whose union is exactly it, each
relation changing once in the run (no relation added and removed, none twice); the
alignment calls that ``split`` (its robot indices ``robot`` … ``robot_last``). Anything
else is compared strictly: a run that also changes another relation, or changes one back,
is no split.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

from oacdsl.world import Relation, WorldState

__all__ = ["Change", "Step", "align", "changes", "restricted", "split_of"]


@dataclass(frozen=True)
class Change:
    """What one keyframe transition changed; ``frame``/``time_s``/``index`` locate it, not compared."""

    added: frozenset[Relation]
    removed: frozenset[Relation]
    index: int = field(default=0, compare=False)
    frame: int | None = field(default=None, compare=False)
    time_s: float | None = field(default=None, compare=False)

    def items(self) -> list[str]:
        """The change as ``+a<->b`` / ``-a<->b`` items, sorted (for the relation-level distance)."""
        plus = [f"+{a}<->{b}" for a, b in sorted(self.added)]
        return plus + [f"-{a}<->{b}" for a, b in sorted(self.removed)]

    def label(self) -> str:
        """``+ a <-> b, − c <-> d``: readable, deterministic."""
        parts = [f"+ {a} <-> {b}" for a, b in sorted(self.added)]
        parts += [f"− {a} <-> {b}" for a, b in sorted(self.removed)]
        return ", ".join(parts)

    def to_json(self) -> dict[str, Any]:
        return {
            "index": self.index,
            "frame": self.frame,
            "time_s": self.time_s,
            "added": [list(r) for r in sorted(self.added)],
            "removed": [list(r) for r in sorted(self.removed)],
        }


@dataclass(frozen=True)
class Step:
    """One column pair of the alignment: ``op`` is match, split, substitute, missing or extra.

    ``missing``: a demonstration change the robot did not make; ``extra``: a robot change the
    demonstration does not have; ``split``: one demonstration change made by the robot as the
    consecutive changes ``robot`` … ``robot_last``; ``merge`` (only when asked for): the
    consecutive demonstration changes ``demonstration`` … ``demonstration_last`` made as one.
    Indices point into the two change lists (None when absent).
    """

    op: str
    demonstration: int | None
    robot: int | None
    robot_last: int | None = None
    demonstration_last: int | None = None


def restricted(state: WorldState, keep: frozenset[str] | None) -> frozenset[Relation]:
    """The state's relations among the instances ``keep`` (None: all of them)."""
    if keep is None:
        return state.relations
    return frozenset(r for r in state.relations if r[0] in keep and r[1] in keep)


def changes(
    states: Sequence[WorldState],
    frames: Sequence[int | None] | None = None,
    times_s: Sequence[float | None] | None = None,
    instances: Iterable[str] | None = None,
) -> list[Change]:
    """The changes between consecutive states; transitions that change nothing are left out.

    ``instances`` restricts the comparison to relations among those instances. ``index`` of a
    change is the index of the keyframe it leads to; ``frames``/``times_s`` (one per state) are
    copied onto it for display.
    """
    keep = frozenset(instances) if instances is not None else None
    out = []
    for i in range(1, len(states)):
        before, after = restricted(states[i - 1], keep), restricted(states[i], keep)
        if before != after:
            out.append(
                Change(
                    after - before,
                    before - after,
                    i,
                    frames[i] if frames is not None else None,
                    times_s[i] if times_s is not None else None,
                )
            )
    return out


def split_of(whole: Change, parts: Sequence[Change]) -> bool:
    """True when ``parts`` (two or more consecutive changes) make ``whole`` between them,
    each relation changing once: disjoint, and their union is exactly ``whole``."""
    if len(parts) < 2:
        return False
    added: set[Relation] = set()
    removed: set[Relation] = set()
    for p in parts:
        if not p.added and not p.removed:
            return False
        if p.added & added or p.removed & removed or p.added & removed or p.removed & added:
            return False
        if p.added & p.removed:
            return False
        added |= p.added
        removed |= p.removed
    return added == set(whole.added) and removed == set(whole.removed)


def _splits(a: Sequence[Any], b: Sequence[Any]) -> dict[tuple[int, int], int]:
    """(i, j) → k: demonstration item ``a[i-1]`` is split into ``b[j-k:j]`` (only Changes)."""
    out: dict[tuple[int, int], int] = {}
    for i, whole in enumerate(a, 1):
        if not isinstance(whole, Change):
            continue
        size = len(whole.added) + len(whole.removed)
        for start in range(len(b)):
            for end in range(start + 2, min(len(b), start + size) + 1):
                if all(isinstance(x, Change) for x in b[start:end]) and split_of(whole, b[start:end]):
                    out.setdefault((i, end), end - start)
    return out


def align(a: Sequence[Any], b: Sequence[Any], merge: bool = False) -> tuple[int, list[Step]]:
    """Levenshtein distance between two sequences (items compared with ``==``) and an alignment.

    A :class:`Change` of ``a`` also matches, at cost 0, a run of two or more consecutive
    changes of ``b`` that split it (:func:`split_of`). Among optimal alignments the one
    returned prefers matches and substitutions on the diagonal, then splits, then missing
    items, then extra ones. ``merge``: the converse too — a change of ``b`` matches, at cost
    0, a run of consecutive changes of ``a`` that split it (op ``merge``).
    """
    n, m = len(a), len(b)
    splits = _splits(a, b)
    merges = {(i, j): k for (j, i), k in _splits(b, a).items()} if merge else {}
    d = [[0] * (m + 1) for _ in range(n + 1)]
    for i in range(n + 1):
        d[i][0] = i
    for j in range(m + 1):
        d[0][j] = j
    for i in range(1, n + 1):
        for j in range(1, m + 1):
            d[i][j] = min(d[i - 1][j - 1] + (a[i - 1] != b[j - 1]), d[i - 1][j] + 1, d[i][j - 1] + 1)
            k = splits.get((i, j))
            if k is not None:
                d[i][j] = min(d[i][j], d[i - 1][j - k])
            k = merges.get((i, j))
            if k is not None:
                d[i][j] = min(d[i][j], d[i - k][j - 1])
    steps: list[Step] = []
    i, j = n, m
    while i or j:
        k = splits.get((i, j))
        km = merges.get((i, j))
        if i and j and a[i - 1] == b[j - 1] and d[i][j] == d[i - 1][j - 1]:
            steps.append(Step("match", i - 1, j - 1))
            i, j = i - 1, j - 1
        elif k is not None and d[i][j] == d[i - 1][j - k]:
            steps.append(Step("split", i - 1, j - k, j - 1))
            i, j = i - 1, j - k
        elif km is not None and d[i][j] == d[i - km][j - 1]:
            steps.append(Step("merge", i - km, j - 1, None, i - 1))
            i, j = i - km, j - 1
        elif i and j and d[i][j] == d[i - 1][j - 1] + (a[i - 1] != b[j - 1]):
            steps.append(Step("match" if a[i - 1] == b[j - 1] else "substitute", i - 1, j - 1))
            i, j = i - 1, j - 1
        elif i and d[i][j] == d[i - 1][j] + 1:
            steps.append(Step("missing", i - 1, None))
            i -= 1
        else:
            steps.append(Step("extra", None, j - 1))
            j -= 1
    steps.reverse()
    return d[n][m], steps
