"""The binding search: OACs compiled to index form, world states as adjacency maps.

An OAC is compiled once into integer-indexed constraints over its variables
(parameters first, then any instance names written in its atoms, which act as
variables with a one-instance domain). A binding is searched for per sub-action
by following *relations*, not by enumerating bindings: a variable that shares a
positive atom ``a <-> b`` with an already bound variable only ranges over that
instance's partners in the relevant world state; the first variable of a
component ranges over the instances of its class that touch something; only
variables in no positive atom are enumerated over their class (minus the
instances the unary atoms ``x <-> nothing`` / ``not x <-> nothing`` exclude).

Different variables bind to different instances (the binding is injective).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from collections.abc import Set as AbstractSet
from dataclasses import dataclass, field

from oacdsl.model import Oac
from oacdsl.world import NOTHING, WorldState

__all__ = [
    "AFTER",
    "BEFORE",
    "CompiledOac",
    "StateView",
    "compile_oac",
    "domains",
    "plan",
    "search",
    "seed_ok",
]

BEFORE, AFTER = 0, 1
_EMPTY: frozenset[str] = frozenset()

Edge = tuple[int, int, int]  # (variable i, variable j, BEFORE|AFTER)
Unary = tuple[int, int]  # (variable, BEFORE|AFTER)
Step = tuple[int, int, int, tuple[tuple[int, int, bool], ...]]


class StateView:
    """A world state as an adjacency map, with its touching and isolated instances."""

    __slots__ = ("adj", "isolated", "state", "touching")

    def __init__(self, state: WorldState) -> None:
        adj: dict[str, set[str]] = {}
        for a, b in state.relations:
            if a in adj:
                adj[a].add(b)
            else:
                adj[a] = {b}
            if b in adj:
                adj[b].add(a)
            else:
                adj[b] = {a}
        self.state = state
        #: instance → the instances it touches (never mutated after construction).
        self.adj: dict[str, set[str]] = adj
        self.touching: frozenset[str] = frozenset(adj)
        self.isolated: frozenset[str] = state.instances - self.touching

    @classmethod
    def changed(cls, base: StateView, state: WorldState) -> StateView:
        """The view of ``state`` built from the view of a state it differs from a little."""
        view = cls.__new__(cls)
        adj = dict(base.adj)
        touched: dict[str, set[str]] = {}
        for rels, adding in (
            (base.state.relations - state.relations, False),
            (state.relations - base.state.relations, True),
        ):
            for a, b in rels:
                for x, y in ((a, b), (b, a)):
                    if x not in touched:
                        touched[x] = set(adj.get(x, ()))
                    (touched[x].add if adding else touched[x].discard)(y)
        for x, partners in touched.items():
            if partners:
                adj[x] = partners
            else:
                adj.pop(x, None)
        view.state = state
        view.adj = adj
        view.touching = frozenset(adj)
        view.isolated = state.instances - view.touching
        return view

    def partners(self, x: str) -> AbstractSet[str]:
        return self.adj.get(x, _EMPTY)


@dataclass(frozen=True, eq=False)
class CompiledOac:
    """An OAC as integer-indexed constraints (see the module docstring)."""

    index: int
    oac: Oac
    names: tuple[str, ...]
    n_params: int
    #: Class per variable; an instance name written in an atom has class ``"=name"``.
    classes: tuple[str, ...]
    pos: tuple[Edge, ...]
    neg: tuple[Edge, ...]
    none: tuple[Unary, ...]
    some: tuple[Unary, ...]
    eff_pos: tuple[tuple[int, int], ...]
    eff_neg: tuple[tuple[int, int], ...]
    eff_none: tuple[int, ...]
    #: A positive atom ``x <-> x``: the OAC can never match.
    impossible: bool
    specificity: int
    #: Per variable: the states in which it must touch someone (True) or no one (False).
    unary: tuple[tuple[tuple[int, bool], ...], ...] = ()
    plans: dict[frozenset[int], tuple[Step, ...]] = field(default_factory=dict, repr=False)


def compile_oac(oac: Oac, index: int, depth: Callable[[str], int]) -> CompiledOac:
    """Compile ``oac``; ``depth(cls)`` is the number of classes ``cls`` belongs to (itself included)."""
    names = [p.name for p in oac.params]
    classes = [p.cls for p in oac.params]
    where = {n: i for i, n in enumerate(names)}

    def var(name: str) -> int:
        if name not in where:  # an instance written directly: a one-instance variable
            where[name] = len(names)
            names.append(name)
            classes.append("=" + name)
        return where[name]

    pos: set[Edge] = set()
    neg: set[Edge] = set()
    none: set[Unary] = set()
    some: set[Unary] = set()
    eff_pos: set[tuple[int, int]] = set()
    eff_neg: set[tuple[int, int]] = set()
    eff_none: set[int] = set()
    impossible = False
    for when, atoms in ((BEFORE, oac.pre), (AFTER, oac.effect)):
        for atom in atoms:
            i = var(atom.left)
            if atom.right == NOTHING:
                (some if atom.negated else none).add((i, when))
                if when == AFTER and not atom.negated:
                    eff_none.add(i)
                continue
            j = var(atom.right)
            if i == j:
                impossible |= not atom.negated
                continue
            edge = (min(i, j), max(i, j), when)
            (neg if atom.negated else pos).add(edge)
            if when == AFTER:
                (eff_neg if atom.negated else eff_pos).add(edge[:2])
    return CompiledOac(
        index=index,
        oac=oac,
        names=tuple(names),
        n_params=len(oac.params),
        classes=tuple(classes),
        pos=tuple(sorted(pos)),
        neg=tuple(sorted(neg)),
        none=tuple(sorted(none)),
        some=tuple(sorted(some)),
        eff_pos=tuple(sorted(eff_pos)),
        eff_neg=tuple(sorted(eff_neg)),
        eff_none=tuple(sorted(eff_none)),
        impossible=impossible,
        specificity=sum(depth(p.cls) for p in oac.params),
        unary=tuple(
            tuple(
                sorted(
                    {(w, False) for i, w in none if i == v}
                    | {(w, True) for i, w in some if i == v}
                    | {(w, True) for a, b, w in pos if v in (a, b)}
                )
            )
            for v in range(len(names))
        ),
    )


def domains(
    co: CompiledOac,
    class_instances: Mapping[str, frozenset[str]],
    views: tuple[StateView, StateView],
    cache: dict[tuple[str, tuple[tuple[int, bool], ...]], frozenset[str]] | None = None,
) -> list[frozenset[str]] | None:
    """Per variable: the instances it may bind to (its class, minus what the unary atoms
    exclude: touching no one / someone, being in a positive atom); None if one is empty.
    ``cache`` shares domains between OACs for the same ``views``."""
    out: list[frozenset[str]] = []
    for key in zip(co.classes, co.unary, strict=True):
        d = cache.get(key) if cache is not None else None
        if d is None:
            d = class_instances.get(key[0], _EMPTY)
            for when, touching in key[1]:
                view = views[when]
                d = d & (view.touching if touching else view.isolated)
            if cache is not None:
                cache[key] = d
        if not d:
            return None
        out.append(d)
    return out


def plan(co: CompiledOac, seeded: frozenset[int]) -> tuple[Step, ...]:
    """The order to bind the variables not in ``seeded`` (cached per OAC and seed set).

    Each step is ``(variable, source, state, checks)``: with ``source >= 0`` the
    variable ranges over the partners of the instance bound to ``source`` in
    ``state``; with ``source == -1`` over its domain. ``checks`` are the other
    atoms between the variable and the variables bound before it,
    ``(other, state, must_touch)``.
    """
    cached = co.plans.get(seeded)
    if cached is not None:
        return cached
    bound = set(seeded)
    remaining = [v for v in range(len(co.names)) if v not in bound]
    steps: list[Step] = []
    while remaining:
        choice: tuple[int, int, int] | None = None
        best = -1
        for v in remaining:
            links = [
                (b if a == v else a, w) for a, b, w in co.pos if v in (a, b) and (b if a == v else a) in bound
            ]
            if links and len(links) > best:
                best, choice = len(links), (v, links[0][0], links[0][1])
        if choice is None:  # start a new component: the variable in most positive atoms
            v = max(remaining, key=lambda u: (sum(u in (a, b) for a, b, _ in co.pos), -u))
            choice = (v, -1, BEFORE)
        v, source, when = choice
        checks: list[tuple[int, int, bool]] = []
        for edges, must in ((co.pos, True), (co.neg, False)):
            for a, b, w in edges:
                if v in (a, b):
                    other = b if a == v else a
                    if other in bound and not (must and other == source and w == when):
                        checks.append((other, w, must))
        steps.append((v, source, when, tuple(checks)))
        bound.add(v)
        remaining.remove(v)
    result = tuple(steps)
    co.plans[seeded] = result
    return result


def seed_ok(
    co: CompiledOac, seed: Mapping[int, str], doms: list[frozenset[str]], views: tuple[StateView, StateView]
) -> bool:
    """True when a partial binding respects domains, injectivity and the atoms among its variables."""
    if len(set(seed.values())) != len(seed):
        return False
    for v, x in seed.items():
        if x not in doms[v]:
            return False
    for edges, must in ((co.pos, True), (co.neg, False)):
        for a, b, w in edges:
            if a in seed and b in seed and (seed[b] in views[w].partners(seed[a])) != must:
                return False
    return True


def search(
    co: CompiledOac,
    doms: list[frozenset[str]],
    views: tuple[StateView, StateView],
    seed: Mapping[int, str],
    out: list[tuple[str, ...]],
) -> None:
    """Append to ``out`` every complete binding that extends ``seed`` and satisfies all atoms.

    A binding is a tuple of instances, one per variable (``co.names``).
    """
    steps = plan(co, frozenset(seed))
    assign: list[str] = [""] * len(co.names)
    for v, x in seed.items():
        assign[v] = x
    used = set(seed.values())
    n = len(steps)

    def extend(k: int) -> None:
        if k == n:
            out.append(tuple(assign))
            return
        v, source, when, checks = steps[k]
        dom = doms[v]
        cands = dom if source < 0 else views[when].partners(assign[source])
        for x in cands:
            if x in used or (source >= 0 and x not in dom):
                continue
            for other, w, must in checks:
                if (x in views[w].partners(assign[other])) != must:
                    break
            else:
                assign[v] = x
                used.add(x)
                extend(k + 1)
                used.discard(x)

    extend(0)
