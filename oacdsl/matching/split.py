"""A keyframe whose change is several sub-actions at once: split it into matched parts.

A person's two hands act independently; when one hand grasps a carton while the other takes a
cup, or the carton touches the cup 0.3 s after it was grasped, the segmentation's merge window
joins the events into one keyframe, and its change (``+right_hand <-> milk_small,
+milk_small <-> cup_small``) matches no OAC. Such a change is the union of the changes of
several sub-actions, each of which does match. When a sub-action matches no OAC (strict
rule), :func:`split_change` looks for the *finest* such split: the changed relations divided
into the most blocks that, applied one after the other, are each matched by an OAC of the
library (a block's world states: the state before plus the blocks so far). The order follows
from the OACs' conditions (``bring_to`` needs the hand on the carton, which the ``grasp``
makes); parts that are independent of each other (:mod:`oacdsl.together`: neither changes
what the other needs or changes) and bind different instances form a group that may run
together, and the composed OAC writes such a group as ``together { … }``. Within a group the
parts are in the order they happened (when the recording says so), else by OAC name and
binding; the runtime runs them in that order.

A change of more than :data:`MAX_CHANGES` relations is not split (the search visits up to
3^n blocks). Only a sub-action that matches nothing is split: a library OAC for the
combination (``grasp_both``) is matched as before.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from oacdsl.matching.conditions import apply_effects
from oacdsl.matching.results import Match, MatchResult
from oacdsl.together import bound, conflict
from oacdsl.world import Relation, WorldState

__all__ = ["MAX_CHANGES", "Part", "Split", "split_change"]

#: A sub-action whose change has more relations than this is not split.
MAX_CHANGES = 8

#: (state before, state after) → the match result (strict rule).
MatchFn = Callable[[WorldState, WorldState], MatchResult]


@dataclass(frozen=True)
class Part:
    """One sub-action of a split keyframe: the match and its world states (before: the keyframe's
    state plus the parts before it)."""

    match: Match
    before: WorldState
    after: WorldState
    #: True: may run together with the part before it (one group; independent of each other).
    together: bool = False

    @property
    def added(self) -> frozenset[Relation]:
        return self.after.relations - self.before.relations

    @property
    def removed(self) -> frozenset[Relation]:
        return self.before.relations - self.after.relations


@dataclass(frozen=True)
class Split:
    """The parts of a split keyframe, in the order they run."""

    parts: tuple[Part, ...]

    def groups(self) -> list[list[Part]]:
        """The parts grouped: every group's parts may run together."""
        out: list[list[Part]] = []
        for p in self.parts:
            if p.together and out:
                out[-1].append(p)
            else:
                out.append([p])
        return out

    def text(self) -> str:
        """``together { grasp(…), grasp(…) }, then bring_to(…)``."""
        shown = []
        for g in self.groups():
            calls = ", ".join(p.match.text() for p in g)
            shown.append(f"together {{ {calls} }}" if len(g) > 1 else calls)
        return ", then ".join(shown)

    def to_json(self) -> list[dict[str, Any]]:
        """One entry per part: OAC, binding, group (parts of one group may run together), change."""
        out = []
        for k, g in enumerate(self.groups()):
            for p in g:
                out.append({
                    "oac": p.match.oac.name,
                    "binding": p.match.mapping,
                    "group": k,
                    "added": [list(r) for r in sorted(p.added)],
                    "removed": [list(r) for r in sorted(p.removed)],
                })
        return out


Change = tuple[Relation, bool]  # the relation, True: it started
Score = tuple[int, int, int, int, tuple[int, ...]]


def _apply(state: WorldState, changes: list[Change], mask: int) -> WorldState:
    added = [r for k, (r, started) in enumerate(changes) if mask >> k & 1 and started]
    removed = [r for k, (r, started) in enumerate(changes) if mask >> k & 1 and not started]
    return state.with_changes(added, removed)


def split_change(
    match: MatchFn, before: WorldState, after: WorldState, untracked: frozenset[str] = frozenset(),
    times_s: Mapping[Relation, float] | None = None,
) -> Split | None:
    """The split of the sub-action ``before → after`` into matched parts (see the module
    docstring), or None when there is none. ``untracked``: instances whose relations are
    predicted (:mod:`oacdsl.matching.untracked`); each part's state after carries what its
    effects predict for them. ``times_s``: when each changed relation changed (seconds; from
    the recording without merging), to order parts that the conditions leave unordered."""
    times = times_s or {}
    changes: list[Change] = sorted([(r, True) for r in after.relations - before.relations]
                                   + [(r, False) for r in before.relations - after.relations])
    n = len(changes)
    if n < 2 or n > MAX_CHANGES:
        return None
    full = (1 << n) - 1
    # plan[remaining] = (score, the first group's blocks with their matches); the score: fewest
    # groups, then most parts, then the most specific classes (sum over the parts), then the fewest
    # relations made before ones that changed earlier (times_s), then the most parts in the
    # earliest groups (each as early as it can)
    plan: dict[int, tuple[Score, list[tuple[int, Match]]] | None] = {0: ((0, 0, 0, 0, ()), [])}

    def solve(remaining: int) -> tuple[Score, list[tuple[int, Match]]] | None:
        if remaining in plan:
            return plan[remaining]
        state = _apply(before, changes, full & ~remaining)
        subs = _submasks(remaining)
        matched: dict[int, Match] = {}
        for block in subs:
            if block != full:  # the whole change matched nothing
                chosen = match(state, _apply(state, changes, block)).chosen
                if chosen is not None:
                    matched[block] = chosen
        found: tuple[Score, list[tuple[int, Match]]] | None = None
        for group, blocks in _partitions(subs, matched).items():
            rest = solve(remaining & ~group)
            if rest is None:
                continue
            groups, parts, specific, late, sizes = rest[0]
            done = [changes[k][0] for k in range(n) if group >> k & 1]
            later = [changes[k][0] for k in range(n) if (remaining & ~group) >> k & 1]
            late += sum(1 for a in done for b in later if a in times and b in times and times[a] > times[b])
            score = (groups + 1, parts - len(blocks), specific - sum(m.specificity for _, m in blocks),
                     late, (-len(blocks), *sizes))
            if found is None or score < found[0]:
                found = (score, blocks)
        plan[remaining] = found
        return found

    if solve(full) is None:
        return None
    order: list[tuple[int, Match, bool]] = []
    remaining = full
    while remaining:
        step = plan.get(remaining)
        if step is None:
            return None
        # within a group: in the order the parts happened (when their relations changed), else by
        # OAC and binding; the runtime runs them in this order
        blocks = sorted(step[1], key=lambda b: (_when(b[0], changes, times),
                                                b[1].oac.name, tuple(i for _, i in b[1].binding)))
        order += [(block, m, k > 0) for k, (block, m) in enumerate(blocks)]
        for block, _ in blocks:
            remaining &= ~block
    return _walk(match, before, changes, order, untracked)


def _when(block: int, changes: list[Change], times: Mapping[Relation, float]) -> float:
    """When the block's relations changed (the latest of them; infinity when unknown)."""
    known = [times[r] for k, (r, _) in enumerate(changes) if block >> k & 1 and r in times]
    return max(known) if known else float("inf")


def _submasks(mask: int) -> list[int]:
    """The non-empty submasks of ``mask``, fewest bits first (then by value)."""
    out = []
    sub = mask
    while sub:
        out.append(sub)
        sub = (sub - 1) & mask
    return sorted(out, key=lambda m: (bin(m).count("1"), m))


def _partitions(subs: list[int], matched: dict[int, Match]) -> dict[int, list[tuple[int, Match]]]:
    """For every union of blocks: its partition into the most matched, pairwise independent
    blocks (blocks matched from one state that may run together)."""
    best: dict[int, list[tuple[int, Match]]] = {0: []}
    for group in subs:  # fewest bits first: every part of a group is done before the group
        low = group & -group
        found: list[tuple[int, Match]] | None = None
        for block, m in matched.items():
            if block & low and block & group == block:
                rest = best.get(group & ~block)
                if rest is None or (found is not None and len(rest) + 1 <= len(found)):
                    continue
                if all(_apart(m, other) for _, other in rest):
                    found = [(block, m), *rest]
        if found is not None:
            best[group] = found
    del best[0]
    return best


def _apart(a: Match, b: Match) -> bool:
    """True when ``a`` and ``b`` may run together: they bind different instances (two hands, each
    with its own objects) and neither changes what the other needs (:mod:`oacdsl.together`)."""
    if {i for _, i in a.binding} & {i for _, i in b.binding}:
        return False
    return conflict(_conds(a), _conds(b)) is None


def _conds(m: Match) -> tuple[tuple[tuple[str, str, bool], ...], tuple[tuple[str, str, bool], ...]]:
    return bound(m.oac.pre, m.mapping), bound(m.oac.effect, m.mapping)


def _walk(
    match: MatchFn, before: WorldState, changes: list[Change], order: list[tuple[int, Match, bool]],
    untracked: frozenset[str],
) -> Split | None:
    """The parts for ``order`` with their states, each block matched again from its state (None
    when one does not match there)."""
    parts = []
    state = before
    for block, wanted, together in order:
        target = _apply(state, changes, block)
        result = match(state, target)
        same = [m for m in result.matches if (m.oac.name, m.binding) == (wanted.oac.name, wanted.binding)]
        if not same:
            return None
        after = target
        if untracked:  # what the part's effects predict for the untracked instances
            predicted = apply_effects(state, same[0].effect).relations
            keep = frozenset(r for r in target.relations if r[0] not in untracked and r[1] not in untracked)
            moved = frozenset(r for r in predicted if r[0] in untracked or r[1] in untracked)
            after = WorldState(target.instances, keep | moved)
        parts.append(Part(same[0], state, after, together))
        state = after
    return Split(tuple(parts))
