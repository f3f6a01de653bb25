"""Closed-loop verification: does the robot's execution change the world as the demonstration did?

Both the demonstration and the robot's own execution are segmented by the same
AAS into keyframes with world states. Each keyframe transition is a *change*:
the relations it added and the ones it removed. Two changes are equal when both
sets are equal. The fidelity of a reproduction is measured by the Levenshtein
distance between the two sequences of changes (insertion, deletion and
substitution each cost 1; a swap of two steps therefore costs 2), reported with
an alignment for display. The run is *verified* when the initial world states
agree and the distance is within the tolerance (0 by default).

The changes and their alignment (a demonstration change the robot makes in parts: a split):
:mod:`oacdsl.verify_changes`.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from oacdsl.verify_changes import Change, Step, align, changes, restricted
from oacdsl.world import Relation, WorldState, relation

__all__ = ["Change", "Step", "Verification", "align", "changes", "states_from_segment_json", "verify"]


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
        initial=(restricted(demonstration[0], kset), restricted(robot[0], kset)),
        final=(restricted(demonstration[-1], kset), restricted(robot[-1], kset)),
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
