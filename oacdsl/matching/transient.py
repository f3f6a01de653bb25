"""Transient world states: an object in flight does not split a sub-action.

A liquid poured from a height leaves the cup and reaches the bowl a moment later; a
dropped object falls before it lands on something. In between, the object touches
nothing: the segmentation rightly reports that world state, but it is not one a person
would name, and the two halves ("liquid leaves cup", "liquid reaches bowl") match no
OAC while the whole matches ``pour``.

**The rule.** A keyframe ``k`` (not the first, not the last) is *transient* when the
world state it starts lasts less than ``max_s`` seconds (until keyframe ``k + 1``) and
some *object* ``x`` — an instance that is not an agent (class ``Hand`` or a subclass) —

- touches nothing in it, but touches something in the state before it and in the state
  after it (it left one contact and reached another), and
- is part of every relation that changes at keyframe ``k`` and at keyframe ``k + 1``
  (nothing else happened: a bowl that merely stops touching a cup set on it and then
  receives a liquid poured from that cup is not in flight).

A transient keyframe does not delimit a sub-action: it is dropped, and the
sub-actions on both sides become one. A keyframe whose state then equals the previous
kept state is dropped as well (the object went back where it was). Environment
instances (``environment`` in the scene) are never tracked, so never in a world state.

The rule lives in matching, not in the segmentation, because it needs to know which
instances are agents, which only the scene says; the segmentation keeps reporting
every change it sees (``oacc segment``). ``oacc match`` and ``oacc compose`` apply it
(``--transient``, default :data:`TRANSIENT_S`; ``0s`` switches it off), and
``oacc reproduce`` applies it to the demonstration and to the robot's run alike.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, replace

from oacdsl.segmentation.result import Keyframe, Segmentation

__all__ = ["AGENT_CLASS", "TRANSIENT_S", "Transient", "agents_of", "stable_segmentation"]

#: Seconds: a state shorter than this in which an object touches nothing between two
#: contacts is transient. A liquid poured from a height or a dropped object is in the air
#: for well under a second; a demonstrated sub-action (reach, grasp, set down) lasts a
#: second or more, and the rule needs an object that touches something on both sides.
TRANSIENT_S = 1.5
#: The class whose instances are agents (never "in flight").
AGENT_CLASS = "Hand"


@dataclass(frozen=True)
class Transient:
    """A dropped keyframe: the state from ``keyframe`` lasted ``duration_s``; ``objects`` were in flight."""

    keyframe: Keyframe
    duration_s: float
    objects: tuple[str, ...]

    def to_json(self) -> dict[str, object]:
        return {
            "frame": int(self.keyframe.frame),
            "time_s": float(self.keyframe.time_s),
            "duration_s": round(float(self.duration_s), 6),
            "in_flight": list(self.objects),
        }


def agents_of(
    instance_classes: Mapping[str, Iterable[str]], agent_class: str = AGENT_CLASS
) -> frozenset[str]:
    """The instances whose classes (inherited included) contain ``agent_class``."""
    return frozenset(i for i, classes in instance_classes.items() if agent_class in set(classes))


def stable_segmentation(
    segmentation: Segmentation, is_agent: Callable[[str], bool], max_s: float = TRANSIENT_S
) -> tuple[Segmentation, tuple[Transient, ...]]:
    """``segmentation`` without its transient keyframes (see the module docstring), and those."""
    kfs = segmentation.keyframes
    if max_s <= 0 or len(kfs) < 3:
        return segmentation, ()
    kept: list[Keyframe] = [kfs[0]]
    dropped: list[Transient] = []
    for k in range(1, len(kfs)):
        cur = kfs[k]
        if cur.state == kept[-1].state:  # the object went back: nothing changed since the last kept
            continue
        if k + 1 < len(kfs):
            duration = kfs[k + 1].time_s - cur.time_s
            prev, nxt = kept[-1].state, kfs[k + 1].state
            changed = (prev.relations ^ cur.state.relations) | (cur.state.relations ^ nxt.relations)
            flying = tuple(
                sorted(
                    x
                    for x in cur.state.instances
                    if not is_agent(x)
                    and cur.state.touches_nothing(x)
                    and not prev.touches_nothing(x)
                    and not nxt.touches_nothing(x)
                    and all(x in r for r in changed)
                )
            )
            if duration < max_s and flying:
                dropped.append(Transient(cur, duration, flying))
                continue
        kept.append(cur)
    if not dropped:
        return segmentation, ()
    return replace(segmentation, keyframes=tuple(kept)), tuple(dropped)
