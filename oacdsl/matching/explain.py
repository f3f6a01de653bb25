"""Why a sub-action matches no OAC: the closest bindings and the conditions they fail.

For each OAC, a branch-and-bound search over the bindings of its variables
(classes respected, different variables to different instances) finds the
binding that fails the fewest conditions. The conditions are the bound
preconditions (before), the bound effects (after) and, in strict mode, one per
changed relation that the bound effects must account for, and, when it fails, that
every instance the effects name takes part in a change. Values that fail the
fewest conditions are tried first, so the first complete binding is already
good; the search stops after ``node_cap`` nodes per OAC (20 000, fewer for a large
library: 400 000 in all, at least 2 000 each) and says so.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from oacdsl.matching.conditions import bind_atom, why_not
from oacdsl.matching.results import Mode, NearMiss, change_text
from oacdsl.matching.search import AFTER, BEFORE, CompiledOac, StateView, plan
from oacdsl.matching.strict import changed_instances, untouched
from oacdsl.matching.transient import AGENT_CLASS
from oacdsl.model import Atom, atom_text
from oacdsl.world import NOTHING, WorldState

__all__ = ["closest_binding", "explain_no_match"]

#: (state, kind, i, j, atom): kind is "pos", "neg", "none" or "some"; j = -1 for unary atoms.
Cond = tuple[int, str, int, int, Atom]


def _conditions(co: CompiledOac) -> list[Cond]:
    where = {n: i for i, n in enumerate(co.names)}
    out: list[Cond] = []
    for when, atoms in ((BEFORE, co.oac.pre), (AFTER, co.oac.effect)):
        for atom in atoms:
            i = where[atom.left]
            if atom.right == NOTHING:
                out.append((when, "some" if atom.negated else "none", i, -1, atom))
            elif where[atom.right] != i:
                out.append((when, "neg" if atom.negated else "pos", i, where[atom.right], atom))
    return out


def _ok(c: Cond, b: Sequence[str], views: tuple[StateView, StateView]) -> bool:
    when, kind, i, j, _ = c
    view = views[when]
    if kind == "pos":
        return b[j] in view.partners(b[i])
    if kind == "neg":
        return b[j] not in view.partners(b[i])
    if kind == "none":
        return b[i] in view.isolated
    return b[i] in view.touching


def _unaccounted(
    co: CompiledOac, b: Sequence[str], added: frozenset[tuple[str, str]], removed: frozenset[tuple[str, str]]
) -> list[str]:
    pos = {tuple(sorted((b[i], b[j]))) for i, j in co.eff_pos}
    neg = {tuple(sorted((b[i], b[j]))) for i, j in co.eff_neg}
    cleared = {b[i] for i in co.eff_none}
    out = [
        f"change {x} <-> {y} started, but no effect states {x} <-> {y}"
        for x, y in sorted(added)
        if (x, y) not in pos
    ]
    out += [
        f"change {x} <-> {y} ended, but no effect states not {x} <-> {y}, {x} <-> nothing or {y} <-> nothing"
        for x, y in sorted(removed)
        if (x, y) not in neg and x not in cleared and y not in cleared
    ]
    return out


def _untouched_text(
    co: CompiledOac, b: Sequence[str], added: frozenset[tuple[str, str]], removed: frozenset[tuple[str, str]]
) -> list[str]:
    """The strict rule's condition that every instance the effects name takes part in a change,
    as a failure text (an empty list when it holds)."""
    idle = untouched(co, b, changed_instances(added, removed))
    if not idle:
        return []
    verb = "takes" if len(idle) == 1 else "take"
    return [f"the effects name {', '.join(idle)}, which {verb} part in no change (an OAC's effects say"
            " what it changes)"]


def _classes_of(members: Mapping[str, frozenset[str]]) -> dict[str, list[str]]:
    """Instance → its classes (inherited included), for the instances that have any."""
    out: dict[str, list[str]] = {}
    for cls, instances in sorted(members.items()):
        if not cls.startswith("="):
            for i in instances:
                out.setdefault(i, []).append(cls)
    return out


def closest_binding(
    co: CompiledOac,
    members: Mapping[str, frozenset[str]],
    before: WorldState,
    after: WorldState,
    mode: Mode,
    *,
    node_cap: int = 20_000,
) -> NearMiss:
    """The binding of ``co`` that fails the fewest conditions, and those conditions."""
    oac = co.oac
    if co.impossible:
        return NearMiss(oac, (), ("an atom says an instance touches itself",), 0)
    doms = [sorted(members.get(c, ())) for c in co.classes]
    for v, d in enumerate(doms):
        if not d:
            what = (
                f"{co.names[v]} is not an instance of the world state"
                if v >= co.n_params
                else f"no instance of class {co.classes[v]} for parameter {co.names[v]}"
            )
            return NearMiss(oac, (), (what,), 0)
    # A parameter may also stand for an instance of another class, as one failed condition
    # (``crate is not a Graspable``): what a library's OAC would need to match. Agents (class
    # Hand) and objects do not stand for each other.
    classes_of = _classes_of(members)
    agents = members.get(AGENT_CLASS, frozenset())
    outside: list[frozenset[str]] = []
    for v, d in enumerate(doms):
        agent = set(d) <= agents
        others = [i for i in sorted(set(classes_of) - set(d)) if (i in agents) == agent]
        others = others if v < co.n_params else []
        outside.append(frozenset(others))
        doms[v] = d + others
    views = (StateView(before), StateView(after))
    added = after.relations - before.relations
    removed = before.relations - after.relations
    conds = _conditions(co)
    order = [step[0] for step in plan(co, frozenset())]
    position = {v: k for k, v in enumerate(order)}
    levels: list[list[Cond]] = [[] for _ in order]
    for c in conds:
        levels[max(position[c[2]], position.get(c[3], 0))].append(c)
    n = len(order)
    assign = [""] * len(co.names)
    used: set[str] = set()
    # Costs: a failed condition or unaccounted change weighs more than all class failures and
    # the effects' instances together, so the binding found is the one the ranking of the near
    # misses (conditions satisfied) prefers, whatever the instances are called.
    weight = co.n_params + 2
    best_fails = (len(conds) + len(added) + len(removed) + 1) * weight
    best: tuple[str, ...] | None = None
    nodes = 0
    truncated = False

    def extend(k: int, fails: int) -> None:
        nonlocal best_fails, best, nodes, truncated
        if k == n:
            total = fails
            if mode == "strict":
                total += weight * len(_unaccounted(co, assign, added, removed))
                if total == 0:  # reported only as the one reason left
                    total += len(_untouched_text(co, assign, added, removed))
            if total < best_fails:
                best_fails, best = total, tuple(assign)
            return
        nodes += 1
        if nodes > node_cap:
            truncated = True
            return
        v = order[k]
        scored = []
        for x in doms[v]:
            if x in used:
                continue
            assign[v] = x
            failing = sum(not _ok(c, assign, views) for c in levels[k])
            scored.append((weight * failing + (x in outside[v]), x))
        scored.sort()
        for f, x in scored:
            if fails + f >= best_fails:
                break
            assign[v] = x
            used.add(x)
            extend(k + 1, fails + f)
            used.discard(x)

    extend(0, 0)
    if best is None:
        why = (
            "no complete binding within the search budget"
            if truncated
            else "its parameters cannot all bind to different instances"
        )
        return NearMiss(oac, (), (why,), 0, truncated)
    bound = best
    mapping = dict(zip(co.names, bound, strict=True))
    failed = [
        f"{x} is not a {co.classes[v]} (parameter {co.names[v]}; {x}: {', '.join(classes_of[x])})"
        for v, x in enumerate(bound[: co.n_params]) if x in outside[v]
    ]
    total = len(conds) + len(failed)  # a class counts as a condition where it fails
    for c in conds:
        if not _ok(c, bound, views):
            when, atom = c[0], bind_atom(c[4], mapping)
            label, moment, state = ("pre", "before", before) if when == BEFORE else ("effect", "after", after)
            failed.append(f"{label} {atom_text(atom)} does not hold {moment}: {why_not(atom, state)}")
    if mode == "strict":
        # one condition per changed relation; the one on the instances the effects name when it
        # is the one reason left
        failed += _unaccounted(co, bound, added, removed)
        idle = [] if failed else _untouched_text(co, bound, added, removed)
        failed += idle
        total += len(added) + len(removed) + len(idle)
    binding = tuple((co.names[v], bound[v]) for v in range(co.n_params))
    return NearMiss(oac, binding, tuple(failed), total, truncated)


def explain_no_match(
    compiled: Sequence[CompiledOac],
    members: Mapping[str, frozenset[str]],
    before: WorldState,
    after: WorldState,
    mode: Mode,
    *,
    limit: int = 3,
) -> tuple[tuple[NearMiss, ...], str]:
    """The ``limit`` closest OACs and a one-line explanation of why none matches."""
    added = after.relations - before.relations
    removed = before.relations - after.relations
    rule = "strict rule" if mode == "strict" else "paper's rule"
    if mode == "strict" and not added and not removed:
        return (), (
            "nothing changed between the two keyframes; under the strict rule an OAC must"
            " change something (the paper's rule, --paper, accepts OACs whose effects already hold)"
        )
    cap = max(2_000, 400_000 // max(1, len(compiled)))  # a budget for the whole library
    misses = [closest_binding(co, members, before, after, mode, node_cap=cap) for co in compiled]
    # Closest first: the binding that satisfies the most conditions, then the fewest failures.
    misses.sort(key=lambda m: (m.conditions == 0, -(m.conditions - len(m.failed)), len(m.failed), m.oac.name))
    near = tuple(misses[:limit])
    head = f"no OAC matches ({rule}) the change {change_text(added, removed)}"
    if not near:
        return near, f"{head}: the library has no OACs"
    return near, f"{head}; closest: " + " | ".join(m.text() for m in near)
