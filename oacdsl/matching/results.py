"""Result records of matching: a match, a near miss, the result for one sub-action."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

from oacdsl.matching.conditions import bind_atoms
from oacdsl.model import Atom, Oac, atom_text
from oacdsl.world import Relation, WorldState

__all__ = [
    "Match",
    "MatchResult",
    "Mode",
    "NearMiss",
    "call_text",
    "callers_first",
    "change_text",
    "choice_reason",
    "Binding",
]

#: ``strict`` (default): the paper's rule plus "the effects account for every change";
#: ``paper``: the paper's rule alone (pre holds before, effects hold after).
Mode = Literal["strict", "paper"]

Binding = tuple[tuple[str, str], ...]


def call_text(name: str, binding: Binding) -> str:
    """``grasp(h=left_hand, o=red_cup)``."""
    return f"{name}({', '.join(f'{v}={i}' for v, i in binding)})"


def change_text(added: frozenset[Relation], removed: frozenset[Relation]) -> str:
    """``+left_hand <-> red_cup, -liquid_one <-> red_cup`` (``no change`` when empty)."""
    parts = [f"+{a} <-> {b}" for a, b in sorted(added)] + [f"-{a} <-> {b}" for a, b in sorted(removed)]
    return ", ".join(parts) if parts else "no change"


@dataclass(frozen=True)
class Match:
    """An OAC and a binding of its parameters under which a sub-action matches it.

    Attributes:
        oac: the matched OAC.
        binding: (parameter, instance) pairs in parameter order.
        explained: how many of the sub-action's changed relations the bound effects account for.
        changes: how many relations changed in the sub-action.
        specificity: sum over the parameters of the depth of their class (ancestors counted).
        idle: bound effects that already held before (they describe no change).
        conditions: how many preconditions and effects the OAC states (more: more specific).
    """

    oac: Oac
    binding: Binding
    explained: int
    changes: int
    specificity: int
    idle: int
    conditions: int = 0

    @property
    def mapping(self) -> dict[str, str]:
        """The binding as a dict, parameter → instance."""
        return dict(self.binding)

    @property
    def pre(self) -> tuple[Atom, ...]:
        """The bound preconditions (instances in place of variables)."""
        return bind_atoms(self.oac.pre, self.mapping)

    @property
    def effect(self) -> tuple[Atom, ...]:
        """The bound effects."""
        return bind_atoms(self.oac.effect, self.mapping)

    def text(self) -> str:
        return call_text(self.oac.name, self.binding)

    def same_meaning(self, other: Match) -> bool:
        """True when ``other`` binds the same OAC to the same bound conditions (a symmetric OAC
        such as ``grasp_both(h1, o1, h2, o2)`` with its two hands exchanged): no real choice."""
        def bound(m: Match) -> tuple[frozenset[str], frozenset[str]]:
            return frozenset(map(atom_text, m.pre)), frozenset(map(atom_text, m.effect))

        return self.oac.name == other.oac.name and bound(self) == bound(other)

    def calls(self, other: Match) -> bool:
        """True when this match's OAC runs ``other`` as one of its steps, on the same instances
        (``hold_on_board(h, c, b)``, steps ``onto_board(h, c, b)``, ``keep(h, c)``)."""
        mapping = self.mapping
        wanted = tuple(i for _, i in other.binding)
        return any(c.oac == other.oac.name and tuple(mapping.get(a, a) for a in c.args) == wanted
                   for c in self.oac.steps or ())

    def rank_key(self) -> tuple[int, int, int, int, str, tuple[str, ...]]:
        """Sort key, best first: more change explained, more specific classes,
        fewer idle effects, more conditions, then name and binding (deterministic)."""
        instances = tuple(i for _, i in self.binding)
        return (-self.explained, -self.specificity, self.idle, -self.conditions, self.oac.name, instances)


@dataclass(frozen=True)
class NearMiss:
    """An OAC that did not match, with the binding that came closest and what failed."""

    oac: Oac
    binding: Binding
    failed: tuple[str, ...]
    conditions: int
    #: True when the search for the closest binding was cut off (the library is large).
    truncated: bool = False

    def text(self) -> str:
        head = call_text(self.oac.name, self.binding) if self.binding else self.oac.name
        cut = " (closest found before the search was cut off)" if self.truncated else ""
        if not self.conditions:
            return f"{head}: {'; '.join(self.failed)}{cut}"
        failed = "; ".join(self.failed)
        return f"{head} fails {len(self.failed)} of {self.conditions} conditions{cut}: {failed}"


@dataclass(frozen=True)
class MatchResult:
    """The matches of one sub-action (ranked, best first), or why there is none."""

    before: WorldState
    after: WorldState
    mode: Mode
    matches: tuple[Match, ...]
    #: Why ``matches[0]`` was chosen; None when there are fewer than two matches.
    reason: str | None = None
    near_misses: tuple[NearMiss, ...] = field(default=())
    #: Why nothing matched; None when something did.
    explanation: str | None = None
    #: True when a tie of the best matches was broken by how far their hands moved
    #: (:mod:`oacdsl.matching.agency`): then no longer ambiguous.
    by_motion: bool = False

    @property
    def chosen(self) -> Match | None:
        return self.matches[0] if self.matches else None

    @property
    def added(self) -> frozenset[Relation]:
        return self.after.relations - self.before.relations

    @property
    def removed(self) -> frozenset[Relation]:
        return self.before.relations - self.after.relations

    @property
    def ambiguous(self) -> bool:
        """True when the best two matches tie on everything but name and binding."""
        if len(self.matches) < 2 or self.by_motion:
            return False
        a, b = self.matches[0].rank_key(), self.matches[1].rank_key()
        first, second = self.matches[0], self.matches[1]
        return a[:4] == b[:4] and not first.same_meaning(second) and not first.calls(second)


def _classes_text(m: Match) -> str:
    return ", ".join(p.cls for p in m.oac.params)


def callers_first(matches: list[Match]) -> list[Match]:
    """``matches`` (ranked) with, among those that tie with the first on the ranking's criteria
    1-4, an OAC that runs another of them as a step (on the same instances) before it."""
    if len(matches) < 2:
        return matches
    key = matches[0].rank_key()[:4]
    n = next((k for k, m in enumerate(matches) if m.rank_key()[:4] != key), len(matches))
    tied = matches[:n]
    return sorted(tied, key=lambda m: -sum(m.calls(o) for o in tied)) + matches[n:]


def choice_reason(matches: list[Match]) -> str | None:
    """Why the first of the ranked ``matches`` was chosen over the second."""
    if len(matches) < 2:
        return None
    a, b = matches[0], matches[1]
    head = f"{len(matches)} matches; chose {a.text()}"
    why = _reason(a, b)
    other = next((m for m in matches[2:] if not a.same_meaning(m)), None) if a.same_meaning(b) else None
    if other is not None:  # the twin says nothing of why it beat a different OAC: say that too
        why += f"; over {other.text()}: {_reason(a, other)}"
    return f"{head}: {why}"


def _reason(a: Match, b: Match) -> str:
    """Why ``a`` ranks before ``b``."""
    if a.explained != b.explained:
        why = f"it explains {a.explained} of {a.changes} changed relations, {b.text()} only {b.explained}"
    elif a.specificity != b.specificity:
        why = (
            f"its classes are more specific ({_classes_text(a)}) than those of {b.text()}"
            f" ({_classes_text(b)})"
        )
    elif a.idle != b.idle:
        why = f"fewer of its effects already held before ({a.idle}, {b.text()}: {b.idle})"
    elif a.conditions != b.conditions:
        why = (
            f"it states more conditions ({a.conditions} preconditions and effects, {b.text()}:"
            f" {b.conditions})"
        )
    elif a.calls(b):
        steps = ", ".join(c.oac for c in a.oac.steps or ())
        why = (f"it runs {b.text()} as one of its steps ({steps}): the more particular way of doing it"
               " (they tie on explained change, class specificity, idle effects and number of conditions)")
    elif a.same_meaning(b):
        why = f"the same conditions as {b.text()} (the OAC is symmetric in these parameters)"
    elif a.oac.name == b.oac.name:
        why = (
            f"ambiguous: it ties with {b.text()}; chosen by binding order. The conditions of"
            f" {a.oac.name} do not tell these instances apart: add one that does (a precondition"
            " about the instance you mean, or a more specific parameter class)"
        )
    else:
        why = (
            f"ambiguous: it ties with {b.text()} on explained change, class specificity, idle"
            f" effects and number of conditions ({a.conditions}); chosen by name. To choose the"
            " other, give the OAC you mean a more specific parameter class or a precondition the"
            " other lacks (or leave the other out of the library)"
        )
    return why
