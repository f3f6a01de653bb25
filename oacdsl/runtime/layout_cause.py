"""Why a precondition fails at the start of a run, when the cause is the scene's layout.

The world a run starts in is the layout's (:mod:`oacdsl.runtime.layout`): where each object
stands and what stands on what comes from ``--place``, the scene's ``at``, ``layout
demonstrated`` with a recording, or the first free slot. A precondition of the first step
that names objects of that layout fails because of it, not because of the robot; the message
then says where each object was put and from where, and how to start it otherwise.
"""

from __future__ import annotations

from collections.abc import Sequence

from oacdsl.runtime.layout import Layout
from oacdsl.world import NOTHING

__all__ = ["layout_cause"]

_FROM = {
    "given": "--place",
    "scene": "the scene's 'at'",
    "demonstrated": "the demonstration's first frame",
    "auto": "the first free slot (layout auto)",
}


def _where(layout: Layout, name: str) -> str | None:
    names = {p.name for p in layout.placements}
    if name in layout.liquids:
        return f"{name} starts in {layout.liquids[name]}"
    if name not in names:
        return None
    p = layout.placement(name)
    if p.on is not None:
        return f"{name} starts on {p.on} ({_FROM.get(layout.sources.get(name, ''), 'the layout')})"
    source = _FROM.get(layout.sources.get(name, ""), "the layout")
    return f"{name} stands alone at ({p.x:.2f}, {p.y:.2f}) m, from {source}"


def layout_cause(layout: Layout, failed: Sequence[tuple[str, str, bool]]) -> str | None:
    """A sentence blaming the layout for the failed precondition atoms ``(a, b, negated)`` of
    the initial state, or None when no failed atom is about objects the layout placed."""
    parts: list[str] = []
    stack_hint = False
    for a, b, negated in failed:
        named = [n for n in (a, b) if n != NOTHING]
        texts = [_where(layout, n) for n in named]
        if not named or None in texts:  # a hand, or an instance the layout did not place
            continue
        parts.extend(t for t in texts if t is not None and t not in parts)
        placed = {p.name for p in layout.placements}
        if not negated and a in placed and b in placed:
            stack_hint = True
    if not parts:
        return None
    hint = ""
    if stack_hint:
        hint = (
            "; an object that starts on another (a lid on its bottle) is laid out so only by"
            " 'layout demonstrated' with the recording (--demonstration REC, or oacc reproduce)"
            " when it is on top of it at the first frame; else give --place or 'at'"
        )
    return "the initial state comes from the layout: " + "; ".join(parts) + hint
