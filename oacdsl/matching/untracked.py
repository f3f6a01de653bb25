"""Untracked scene instances in matching: relations predicted by OAC effects, never required.

A scene may declare an instance the recording does not track (``milk : Milk
untracked``: KIT puts no markers on a liquid). The demonstration's world states
never hold it, so a condition about it cannot be checked there. Instead its
relations are **predicted**: they start as the scene's ``in`` statements say
(``milk in milk_small`` → ``milk <-> milk_small``) and each chosen match's bound
effects update them, sub-action after sub-action.

For matching, every OAC whose parameters could bind an untracked instance gets
*variants*, one per way of binding such parameters to untracked instances: there
the parameter becomes the instance itself, its preconditions are checked against
the demonstration's state plus the predicted relations, and its effects about the
untracked instance are left out (predictions, not requirements of the
demonstration). The strict rule then asks the variant to account for the tracked
changes only. A match of a variant is reported as the original OAC with the full
binding (``pour(h=right_hand, c=milk_small, l=milk, b=cup_small)``), and the
sub-action's states carry the predicted relations, so that the composer writes
``milk_small <-> milk`` as a precondition and ``milk <-> cup_small`` as an effect.

An untracked instance matches no parameter of an OAC otherwise (it is given no
classes in the matcher's index): only the variants bind it.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass

from oacdsl.matching.conditions import apply_effects
from oacdsl.matching.results import Match, MatchResult
from oacdsl.matching.split import Split
from oacdsl.model import Atom, Oac, Scene
from oacdsl.world import Relation, WorldState, relation

__all__ = ["Untracked", "Variant", "initial_relations", "variants"]


@dataclass(frozen=True)
class Variant:
    """An OAC with some parameters fixed to untracked instances, for the matcher's index."""

    oac: Oac  # what the matcher sees
    original: Oac
    fixed: tuple[tuple[str, str], ...]  # (parameter, untracked instance)


def initial_relations(scene: Scene) -> frozenset[Relation]:
    """The untracked instances' relations at the start: the scene's ``in`` statements."""
    names = {i.name for i in scene.untracked()}
    return frozenset(relation(f.liquid, f.container) for f in scene.fills
                     if f.liquid in names or f.container in names)


def _rename(atom: Atom, names: Mapping[str, str]) -> Atom:
    left, right = names.get(atom.left, atom.left), names.get(atom.right, atom.right)
    return Atom(left=left, right=right, negated=atom.negated, span=atom.span)


def variants(
    oacs: Iterable[Oac], untracked: Mapping[str, frozenset[str]], ancestors: Callable[[str], frozenset[str]]
) -> list[Variant]:
    """Every OAC as it is, and once per injective binding of some of its parameters to
    untracked instances of their class (``untracked``: instance → its classes, inherited)."""
    out: list[Variant] = []
    for oac in oacs:
        out.append(Variant(oac, oac, ()))
        options = [(p.name, [u for u, cls in sorted(untracked.items()) if p.cls in cls]) for p in oac.params]
        options = [(p, us) for p, us in options if us]
        for k in range(1, len(options) + 1):
            for chosen in itertools.combinations(options, k):
                for picks in itertools.product(*(us for _, us in chosen)):
                    if len(set(picks)) < len(picks):
                        continue
                    fixed = tuple((p, u) for (p, _), u in zip(chosen, picks, strict=True))
                    names = dict(fixed)
                    gone = set(names.values())
                    effect = tuple(a for a in (_rename(x, names) for x in oac.effect)
                                   if a.left not in gone and a.right not in gone)
                    out.append(Variant(
                        oac.model_copy(update={
                            "params": tuple(p for p in oac.params if p.name not in names),
                            "pre": tuple(_rename(x, names) for x in oac.pre),
                            "effect": effect,
                        }),
                        oac, fixed,
                    ))
    return out


@dataclass(frozen=True)
class Untracked:
    """What a matcher needs to predict untracked relations: the names, the starting
    relations, and the variant behind each OAC of its index (same order)."""

    names: frozenset[str]
    initial: frozenset[Relation]
    by_oac: Mapping[int, Variant]  # id(variant.oac) → variant

    def with_predicted(self, state: WorldState, predicted: frozenset[Relation]) -> WorldState:
        """``state`` (tracked instances) with the untracked instances and their relations."""
        return WorldState(state.instances | self.names, state.relations | predicted)

    def original(self, match: Match) -> Match:
        """A match of a variant as the match of its OAC with the full binding."""
        v = self.by_oac.get(id(match.oac))
        if v is None or not v.fixed:
            return match if v is None else dataclasses.replace(match, oac=v.original)
        bound = dict(match.binding) | dict(v.fixed)
        return dataclasses.replace(match, oac=v.original,
                                   binding=tuple((p.name, bound[p.name]) for p in v.original.params))

    def predict(self, before: WorldState, match: Match | None) -> frozenset[Relation]:
        """The untracked relations after ``match`` (its bound effects applied to ``before``)."""
        after = apply_effects(before, match.effect) if match is not None else before
        return frozenset(r for r in after.relations if r[0] in self.names or r[1] in self.names)

    def match_sequence(
        self, states: Sequence[tuple[WorldState, WorldState]],
        match: Callable[[WorldState, WorldState], MatchResult],
        split: Callable[[int, WorldState, WorldState], Split | None] | None = None,
    ) -> list[tuple[MatchResult, Split | None]]:
        """Match consecutive sub-actions ``(before, after)`` of tracked states, carrying the
        predicted untracked relations along; each result's states include them (after: as
        its chosen match predicts). ``split(k, before, after)``: for the sub-action ``k`` that
        matches nothing, its parts (:mod:`oacdsl.matching.split`), whose effects then predict."""
        out: list[tuple[MatchResult, Split | None]] = []
        predicted = self.initial
        for k, (before, after) in enumerate(states):
            b = self.with_predicted(before, predicted)
            result = match(b, self.with_predicted(after, predicted))
            matches = tuple(self.original(m) for m in result.matches)
            chosen = matches[0] if matches else None
            parts = split(k, b, self.with_predicted(after, predicted)) if chosen is None and split else None
            if parts is not None:
                parts = Split(tuple(dataclasses.replace(p, match=self.original(p.match))
                                    for p in parts.parts))
                last = parts.parts[-1].after
                predicted = frozenset(r for r in last.relations if r[0] in self.names or r[1] in self.names)
            else:
                predicted = self.predict(b, chosen)
            out.append((dataclasses.replace(result, before=b, after=self.with_predicted(after, predicted),
                                            matches=matches), parts))
        return out
