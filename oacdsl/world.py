"""World states: sets of *touching* relations among named instances.

A relation is an unordered pair of two different instance names, stored as a
sorted 2-tuple ``(a, b)`` with ``a < b``. A world state is immutable and
hashable. This module is the vocabulary shared by segmentation, matching and
the runtime; it imports nothing from the parser.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field

#: The reserved word for "touches no other instance" (``x <-> nothing``).
NOTHING = "nothing"

Relation = tuple[str, str]


def relation(a: str, b: str) -> Relation:
    """The canonical (sorted) relation between two different instances."""
    if a == b:
        raise ValueError(f"an instance cannot touch itself: {a!r}")
    return (a, b) if a < b else (b, a)


@dataclass(frozen=True, slots=True)
class WorldState:
    """The touching relations at one moment among a known set of instances.

    ``instances`` matters for ``x <-> nothing``: an instance that the state does
    not know about is not "touching nothing", it is unknown.
    """

    instances: frozenset[str]
    relations: frozenset[Relation] = field(default_factory=frozenset)

    @classmethod
    def of(cls, instances: Iterable[str], pairs: Iterable[tuple[str, str]] = ()) -> WorldState:
        """Build a state from instance names and unordered pairs (any order)."""
        rels = frozenset(relation(a, b) for a, b in pairs)
        inst = frozenset(instances)
        for a, b in rels:
            if a not in inst or b not in inst:
                missing = a if a not in inst else b
                raise ValueError(f"relation ({a}, {b}) names unknown instance {missing!r}")
        return cls(inst, rels)

    def touches(self, a: str, b: str) -> bool:
        """True when ``a`` and ``b`` touch (order does not matter)."""
        return (a, b) in self.relations or (b, a) in self.relations

    def partners(self, a: str) -> frozenset[str]:
        """The instances that ``a`` touches."""
        return frozenset(y if x == a else x for x, y in self.relations if a in (x, y))

    def touches_nothing(self, a: str) -> bool:
        """True when ``a`` is a known instance that touches no other instance."""
        return a in self.instances and not any(a in r for r in self.relations)

    def sorted_relations(self) -> list[Relation]:
        """Relations in a deterministic order (for printing and JSON)."""
        return sorted(self.relations)

    def with_changes(self, added: Iterable[Relation] = (), removed: Iterable[Relation] = ()) -> WorldState:
        """A new state with ``removed`` taken away and then ``added`` put in."""
        rels = set(self.relations)
        rels.difference_update(relation(a, b) for a, b in removed)
        rels.update(relation(a, b) for a, b in added)
        return WorldState(self.instances, frozenset(rels))

    def __iter__(self) -> Iterator[Relation]:
        return iter(self.sorted_relations())

    def __len__(self) -> int:
        return len(self.relations)
