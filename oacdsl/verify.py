"""Closed-loop verification: does the robot's execution change the world as the demonstration did?

Both the demonstration and the robot's own execution are segmented by the same
AAS into keyframes with world states. Each keyframe transition is a *change*:
the relations it added and the ones it removed. Two changes are equal when both
sets are equal. The fidelity of a reproduction is measured by the Levenshtein
distance between the two sequences of changes (insertion, deletion and
substitution each cost 1; a swap of two steps therefore costs 2), reported with
an alignment for display. The run is *verified* when the initial world states
agree and the distance is within the tolerance (0 by default).

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

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from oacdsl.world import Relation, WorldState, relation

__all__ = ["Change", "Step", "Verification", "align", "changes", "states_from_segment_json", "verify"]


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


def _restrict(state: WorldState, keep: frozenset[str] | None) -> frozenset[Relation]:
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
        before, after = _restrict(states[i - 1], keep), _restrict(states[i], keep)
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


@dataclass(frozen=True)
class Verification:
    """The comparison of the demonstration's and the robot's sequences of world-state changes."""

    demonstration: list[Change]
    robot: list[Change]
    alignment: list[Step]
    distance: int
    relation_distance: int
    initial: tuple[frozenset[Relation], frozenset[Relation]]
    final: tuple[frozenset[Relation], frozenset[Relation]]
    instances: tuple[str, ...] | None
    tolerance: int = 0

    @property
    def fidelity(self) -> float:
        """1 − distance / longer sequence's length, in [0, 1]; 1 means identical changes."""
        longest = max(len(self.demonstration), len(self.robot))
        return 1.0 if longest == 0 else 1.0 - self.distance / longest

    @property
    def verified(self) -> bool:
        return self.initial[0] == self.initial[1] and self.distance <= self.tolerance

    def counts(self) -> dict[str, int]:
        out = {"match": 0, "split": 0, "merge": 0, "substitute": 0, "missing": 0, "extra": 0}
        for s in self.alignment:
            out[s.op] += 1
        return out

    def verdict(self) -> str:
        """One sentence a researcher reads first."""
        c = self.counts()
        n = len(self.demonstration)
        if self.initial[0] != self.initial[1]:
            head = "not verified: the robot's initial world state differs from the demonstration's"
            return head if self.distance == 0 else f"{head}; edit distance {self.distance}"
        if self.distance == 0:
            split = f" ({c['split']} of them in several robot changes)" if c["split"] else ""
            if c["merge"]:
                split += f" ({c['merge']} robot change(s) making several of them at once)"
            return f"verified: the robot made the demonstration's {n} world-state changes, in order{split}"
        detail = f"{c['missing']} missing, {c['extra']} extra, {c['substitute']} different"
        word = "verified within tolerance" if self.verified else "not verified"
        return f"{word}: edit distance {self.distance} over {n} demonstrated changes ({detail})"

    def to_json(self) -> dict[str, Any]:
        def rels(x: frozenset[Relation]) -> list[list[str]]:
            return [list(r) for r in sorted(x)]

        return {
            "demonstration": [c.to_json() for c in self.demonstration],
            "robot": [c.to_json() for c in self.robot],
            "alignment": [{"op": s.op, "demonstration": s.demonstration, "robot": s.robot,
                           **({"robot_last": s.robot_last} if s.robot_last is not None else {}),
                           **({"demonstration_last": s.demonstration_last}
                              if s.demonstration_last is not None else {})}
                          for s in self.alignment],
            "distance": self.distance,
            "relation_distance": self.relation_distance,
            "fidelity": self.fidelity,
            "initial": {
                "equal": self.initial[0] == self.initial[1],
                "demonstration": rels(self.initial[0]),
                "robot": rels(self.initial[1]),
            },
            "final": {
                "equal": self.final[0] == self.final[1],
                "demonstration": rels(self.final[0]),
                "robot": rels(self.final[1]),
            },
            "instances": None if self.instances is None else list(self.instances),
            "tolerance": self.tolerance,
            "counts": self.counts(),
            "verified": self.verified,
            "verdict": self.verdict(),
        }


def verify(
    demonstration: Sequence[WorldState],
    robot: Sequence[WorldState],
    *,
    demonstration_frames: Sequence[int | None] | None = None,
    robot_frames: Sequence[int | None] | None = None,
    demonstration_times_s: Sequence[float | None] | None = None,
    robot_times_s: Sequence[float | None] | None = None,
    instances: Iterable[str] | None = None,
    tolerance: int = 0,
    merge: bool = False,
) -> Verification:
    """Compare two keyframe sequences of world states (each starts with the initial state).

    ``instances`` limits the comparison to relations among those names (default: all);
    ``merge``: also the converse of a split (:func:`align`), for two takes of a task whose
    segmentations may group near events either way.
    """
    if not demonstration or not robot:
        raise ValueError("both sequences need at least the initial world state")
    if tolerance < 0:
        raise ValueError(f"tolerance must be >= 0, got {tolerance}")
    keep = tuple(sorted(instances)) if instances is not None else None
    demo = changes(demonstration, demonstration_frames, demonstration_times_s, keep)
    bot = changes(robot, robot_frames, robot_times_s, keep)
    distance, steps = align(demo, bot, merge)
    flat_demo = [item for c in demo for item in c.items()]
    flat_bot = [item for c in bot for item in c.items()]
    kset = frozenset(keep) if keep is not None else None
    return Verification(
        demonstration=demo,
        robot=bot,
        alignment=steps,
        distance=distance,
        relation_distance=align(flat_demo, flat_bot)[0],
        initial=(_restrict(demonstration[0], kset), _restrict(robot[0], kset)),
        final=(_restrict(demonstration[-1], kset), _restrict(robot[-1], kset)),
        instances=keep,
        tolerance=tolerance,
    )


def states_from_segment_json(doc: Mapping[str, Any]) -> tuple[list[WorldState], list[int], list[float]]:
    """World states, frames and times (s) of the keyframes of an ``oacc segment --json`` document."""
    names = list(doc["instances"])
    states, frames, times = [], [], []
    for k in doc["keyframes"]:
        states.append(WorldState(frozenset(names), frozenset(relation(a, b) for a, b in k["relations"])))
        frames.append(int(k["frame"]))
        times.append(float(k["time_s"]))
    return states, frames, times
