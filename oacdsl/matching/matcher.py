"""Match a sub-action (world state before, after) against a library of OACs.

The paper's rule (``mode="paper"``): a binding of the OAC's typed variables to
instances matches when every bound precondition holds before and every bound
effect holds after. A variable binds to an instance whose classes (inherited
included) contain the variable's class; different variables bind to different
instances.

The strict rule (``mode="strict"``, the default) adds: every relation that
changed is accounted for by the bound effects (a relation that started is a
positive effect; one that ended is a ``not a <-> b`` effect or ``x <-> nothing``
for one of its ends), every instance the bound effects name takes part in a
change, and the OAC changes something (:mod:`oacdsl.matching.strict`). Under the paper's rule an
OAC whose effects merely *remain* true (grasp, while the hand keeps holding the
cup and something else happens) matches every later sub-action; strict
matching links each sub-action to what caused its change, which is what the
composition needs (its effects then reproduce the demonstration step by step).

Strict matching is driven by the change: one changed relation is looked up in
an index of effect atoms by the classes of their variables, which binds two
variables (or one) at once; the rest of the binding follows the relations of
the world states (:mod:`oacdsl.matching.search`).
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable, Iterable, Mapping

from oacdsl.errors import UsageError
from oacdsl.library import Library
from oacdsl.matching.explain import explain_no_match
from oacdsl.matching.results import Match, MatchResult, Mode, callers_first, choice_reason
from oacdsl.matching.search import (
    AFTER,
    CompiledOac,
    StateView,
    compile_oac,
    domains,
    search,
    seed_ok,
)
from oacdsl.matching.strict import accounts_all, changed_instances, effect_variables, explained
from oacdsl.matching.untracked import Untracked, initial_relations, variants
from oacdsl.model import Oac, Scene
from oacdsl.world import Relation, WorldState

__all__ = ["MODES", "Matcher", "match_sub_action"]

MODES: tuple[Mode, ...] = ("strict", "paper")

Raw = tuple[CompiledOac, tuple[str, ...]]
#: The OACs that can account for one changed relation, and their seeds (partial bindings).
_Accounting = tuple[frozenset[int], dict[int, tuple[dict[int, str], ...]]]


def _check_mode(mode: str) -> Mode:
    if mode not in MODES:
        raise UsageError(f"unknown matching mode {mode!r} (valid: strict, paper)")
    return mode  # type: ignore[return-value]


class Matcher:
    """An index over a library's OACs for one set of instances and their classes.

    Args:
        oacs: the OACs to match against.
        instance_classes: instance → every class it belongs to (inherited included),
            e.g. ``Library.instance_classes(scene)``.
        ancestors: class → its classes (itself included); used for the specificity
            ranking (``Library.ancestors``). Without it every class counts as depth 1.
        mode: the default rule, ``"strict"`` or ``"paper"``.
    """

    def __init__(
        self,
        oacs: Iterable[Oac],
        instance_classes: Mapping[str, Iterable[str]],
        *,
        ancestors: Callable[[str], frozenset[str]] | None = None,
        mode: Mode = "strict",
    ) -> None:
        self.mode: Mode = _check_mode(mode)
        #: Set by :meth:`from_library` for a scene with untracked instances
        #: (:mod:`oacdsl.matching.untracked`): their relations are predicted, not observed.
        self.untracked: Untracked | None = None
        self.ancestors = ancestors
        self.oacs: tuple[Oac, ...] = tuple(oacs)
        self.instance_classes = {i: frozenset(c) for i, c in instance_classes.items()}
        self.compiled = tuple(compile_oac(o, k, self.depth) for k, o in enumerate(self.oacs))
        self._effect_vars = tuple(effect_variables(co) for co in self.compiled)
        keys: dict[str, tuple[str, ...]] = {}
        members: dict[str, set[str]] = defaultdict(set)
        for inst, classes in self.instance_classes.items():
            keys[inst] = (*sorted(classes), "=" + inst)
            for c in keys[inst]:
                members[c].add(inst)
        self._keys = keys
        self._members = {c: frozenset(v) for c, v in members.items()}
        self._restricted: dict[frozenset[str], dict[str, frozenset[str]]] = {}
        pos: dict[tuple[str, str], list[tuple[int, int, int]]] = defaultdict(list)
        neg: dict[tuple[str, str], list[tuple[int, int, int]]] = defaultdict(list)
        clear: dict[str, list[tuple[int, int]]] = defaultdict(list)
        for co in self.compiled:
            if co.impossible:
                continue
            for index, pairs in ((pos, co.eff_pos), (neg, co.eff_neg)):
                for i, j in pairs:
                    index[(co.classes[i], co.classes[j])].append((co.index, i, j))
                    index[(co.classes[j], co.classes[i])].append((co.index, j, i))
            for i in co.eff_none:
                clear[co.classes[i]].append((co.index, i))
        self._pos, self._neg, self._clear = dict(pos), dict(neg), dict(clear)
        self._views: dict[WorldState, StateView] = {}
        self._by_relation: dict[tuple[Relation, bool], _Accounting] = {}

    @classmethod
    def from_library(
        cls,
        library: Library,
        scene: Scene | None = None,
        *,
        instance_classes: Mapping[str, Iterable[str]] | None = None,
        mode: Mode = "strict",
        exclude: Iterable[str] = (),
    ) -> Matcher:
        """A matcher over all OACs of ``library`` for the instances of ``scene``
        (or for ``instance_classes`` given directly), leaving out the OACs named in
        ``exclude``. A scene's untracked instances are bound only through variants of
        the OACs (:mod:`oacdsl.matching.untracked`)."""
        if instance_classes is None:
            if scene is None:
                raise UsageError("give a scene or the instances' classes to match against")
            instance_classes = library.instance_classes(scene)
        left_out = set(exclude)
        oacs = [library.oacs[name] for name in sorted(library.oacs) if name not in left_out]
        hidden = {i.name for i in scene.untracked()} if scene is not None else set()
        if scene is None or not hidden:
            return cls(oacs, instance_classes, ancestors=library.ancestors, mode=mode)
        every = {i: frozenset(c) for i, c in instance_classes.items()}
        found = variants(oacs, {u: every.get(u, frozenset()) for u in hidden}, library.ancestors)
        classes = {i: (frozenset() if i in hidden else c) for i, c in every.items()}
        matcher = cls([v.oac for v in found], classes, ancestors=library.ancestors, mode=mode)
        matcher.untracked = Untracked(frozenset(hidden), initial_relations(scene),
                                      {id(v.oac): v for v in found})
        return matcher

    def depth(self, cls: str) -> int:
        """How many classes ``cls`` belongs to (itself included): its specificity."""
        return len(self.ancestors(cls)) if self.ancestors is not None else 1

    def _class_members(self, known: frozenset[str]) -> Mapping[str, frozenset[str]]:
        if known.issuperset(self._keys):
            return self._members
        cached = self._restricted.get(known)
        if cached is None:
            cached = {c: m & known for c, m in self._members.items()}
            self._restricted[known] = cached
        return cached

    # ------------------------------------------------------------------ search

    def raw_matches(self, before: WorldState, after: WorldState, mode: Mode | None = None) -> list[Raw]:
        """Every (compiled OAC, binding) that matches, unranked; a binding lists one
        instance per variable of ``CompiledOac.names``. The fast path for bulk use."""
        mode = _check_mode(mode or self.mode)
        first_view = self.view(before)
        views = (first_view, self.view(after, first_view))
        members = self._class_members(before.instances & after.instances)
        added = after.relations - before.relations
        removed = before.relations - after.relations
        found: list[Raw] = []
        if mode == "paper":
            for co in self.compiled:
                if co.impossible:
                    continue
                doms = domains(co, members, views)
                if doms is None:
                    continue
                out: list[tuple[str, ...]] = []
                search(co, doms, views, {}, out)
                found.extend((co, b) for b in set(out))
            return found
        if not added and not removed:
            return found
        # Every strict match accounts for every change: the OACs able to account for the first
        # one give the seeds, those able to account for each other one prune them.
        first = min(added) if added else min(removed)
        viable, seeds = self._accounting(first, bool(added))
        for r in added:
            if r != first and viable:
                viable = viable & self._accounting(r, True)[0]
        for r in removed:
            if r != first and viable:
                viable = viable & self._accounting(r, False)[0]
        cache: dict[tuple[str, tuple[tuple[int, bool], ...]], frozenset[str]] = {}
        changed = changed_instances(added, removed)
        n_added = len(added)
        for k in sorted(viable):
            co = self.compiled[k]
            if n_added > len(co.eff_pos):
                continue
            doms = domains(co, members, views, cache)
            if doms is None:
                continue
            candidates = seeds[k]
            out = []
            n_vars = len(co.names)
            for seed in candidates:
                if seed_ok(co, seed, doms, views):
                    if len(seed) == n_vars:  # the seed binds every variable: nothing to search
                        out.append(tuple(seed[v] for v in range(n_vars)))
                    else:
                        search(co, doms, views, seed, out)
            acted = self._effect_vars[k]
            for b in set(out) if len(candidates) > 1 else out:
                if accounts_all(co, b, added, removed) and all(b[v] in changed for v in acted):
                    found.append((co, b))
        return found

    def view(self, state: WorldState, near: StateView | None = None) -> StateView:
        """The adjacency view of ``state`` (the last few are kept: a keyframe's state is the
        state after one sub-action and before the next); built from ``near``, the view of a
        state that differs a little, when given and the instances agree."""
        v = self._views.get(state)
        if v is None:
            if len(self._views) >= 4:
                del self._views[next(iter(self._views))]
            if near is not None and near.state.instances == state.instances:
                v = StateView.changed(near, state)
            else:
                v = StateView(state)
            self._views[state] = v
        return v

    def _accounting(self, r: Relation, started: bool) -> _Accounting:
        """The OACs with an effect atom whose classes fit the changed relation ``r`` (that
        started, or ended), and the partial bindings that make it account for ``r``. It
        depends on the instances' classes only: computed once per relation and kept."""
        key = (r, started)
        cached = self._by_relation.get(key)
        if cached is not None:
            return cached
        keys = self._keys
        p, q = r
        seeds: dict[int, list[dict[int, str]]] = defaultdict(list)
        index = self._pos if started else self._neg
        for ca in keys.get(p, ()):
            for cb in keys.get(q, ()):
                for k, i, j in index.get((ca, cb), ()):
                    seeds[k].append({i: p, j: q})
        if not started:
            for x in r:
                for c in keys.get(x, ()):
                    for k, i in self._clear.get(c, ()):
                        seeds[k].append({i: x})
        result = (frozenset(seeds), {k: tuple(v) for k, v in seeds.items()})
        self._by_relation[key] = result
        return result

    # ------------------------------------------------------------------ results

    def match(
        self, before: WorldState, after: WorldState, *, mode: Mode | None = None, explain: bool = True
    ) -> MatchResult:
        """All matches of the sub-action ``before → after``, ranked, with the reason for
        the first; when there is none (and ``explain``), the closest OACs and what failed."""
        mode = _check_mode(mode or self.mode)
        added = after.relations - before.relations
        removed = before.relations - after.relations
        view = self.view(before)
        raw = self.raw_matches(before, after, mode)
        matches = callers_first(sorted((self._record(co, b, added, removed, view) for co, b in raw),
                                       key=Match.rank_key))
        if matches:
            return MatchResult(before, after, mode, tuple(matches), reason=choice_reason(matches))
        if not explain:
            return MatchResult(before, after, mode, ())
        members = self._class_members(before.instances & after.instances)
        near, text = explain_no_match(self.compiled, members, before, after, mode)
        return MatchResult(before, after, mode, (), near_misses=near, explanation=text)

    def _record(
        self,
        co: CompiledOac,
        b: tuple[str, ...],
        added: frozenset[Relation],
        removed: frozenset[Relation],
        before: StateView,
    ) -> Match:
        idle = 0
        for i, j in co.eff_pos:
            idle += b[j] in before.partners(b[i])
        for i, j in co.eff_neg:
            idle += b[j] not in before.partners(b[i])
        for i in co.eff_none:
            idle += b[i] in before.isolated
        for i, when in co.some:
            idle += when == AFTER and b[i] in before.touching
        return Match(
            oac=co.oac,
            binding=tuple((co.names[v], b[v]) for v in range(co.n_params)),
            explained=explained(co, b, added, removed),
            changes=len(added) + len(removed),
            specificity=co.specificity,
            idle=idle,
            conditions=len(co.oac.pre) + len(co.oac.effect),
        )


def match_sub_action(
    before: WorldState,
    after: WorldState,
    library: Library | Iterable[Oac],
    classes: Scene | Mapping[str, Iterable[str]],
    *,
    mode: Mode = "strict",
    explain: bool = True,
) -> MatchResult:
    """Match one sub-action; ``library`` is a Library or OACs, ``classes`` a scene of
    the library or the instances' classes (inherited included) given directly."""
    if isinstance(library, Library):
        if isinstance(classes, Scene):
            matcher = Matcher.from_library(library, classes, mode=mode)
        else:
            matcher = Matcher.from_library(library, instance_classes=classes, mode=mode)
    else:
        if isinstance(classes, Scene):
            raise UsageError("a scene needs a Library to resolve its classes; pass the classes directly")
        matcher = Matcher(library, classes, mode=mode)
    return matcher.match(before, after, explain=explain)
