"""A liquid touching a tool that stands in the liquid's own container is no change of the task.

A liquid fills the floor of its container: whatever is put into that container (a mixer
stirring the dough) is in the liquid, whether or not a recording sees them touch. Neither
recording can show it reliably. The demonstration's liquid is a symbol, one marker where it
landed (the dough's ``LQ1``/``LQ2``, docs/demonstration.md) or nothing at all (KIT's milk,
``untracked``); a simulated run's liquid is a few balls, and whether one of them rests
against the stirring mixer for the 0.05 s a contact needs to count is chance (the dough's
stories: a ball against the mixer for 0.05-0.55 s on some seeds and not on others, the
mixer circling alike). So in both recordings a relation *liquid* <-> *x* is left out of a
world state while that liquid and ``x`` both touch one container, ``x`` being neither a
container (a liquid reaching the bowl it is poured into from a cup resting on the rim is a
change), a liquid nor a hand (a hand in the liquid is a spill onto it). Keyframes left with
no other change are dropped. What the liquid is in, poured from or into, is judged as before.
"""

from __future__ import annotations

from collections.abc import Callable, Collection
from dataclasses import replace

from oacdsl.segmentation.result import Keyframe, Segmentation
from oacdsl.world import Relation, WorldState

__all__ = ["in_shared_container", "without_shared_container"]


def in_shared_container(
    r: Relation, state: WorldState, liquids: Collection[str], containers: Collection[str],
    is_agent: Callable[[str], bool],
) -> bool:
    """Whether ``r`` is a liquid's touch of a tool that touches a container the liquid touches
    in ``state`` (module docstring)."""
    a, b = r
    for liquid, x in ((a, b), (b, a)):
        if liquid not in liquids or x in liquids or x in containers or is_agent(x):
            continue
        if any(state.touches(liquid, c) and state.touches(x, c) for c in containers):
            return True
    return False


def without_shared_container(
    seg: Segmentation, liquids: Collection[str], containers: Collection[str],
    is_agent: Callable[[str], bool],
) -> Segmentation:
    """``seg`` with those relations left out of every keyframe's state, and the keyframes that
    then change nothing dropped."""
    if not liquids:
        return seg
    kept: list[Keyframe] = []
    for k in seg.keyframes:
        s = k.state
        drop = {r for r in s.relations if in_shared_container(r, s, liquids, containers, is_agent)}
        state = WorldState(s.instances, s.relations - drop) if drop else s
        if kept and kept[-1].state == state:
            continue
        kept.append(replace(k, state=state))
    return replace(seg, keyframes=tuple(kept))
