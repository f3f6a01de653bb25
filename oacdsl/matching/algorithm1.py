"""The bookkeeping of Algorithm 1, per relation: the steps' net update and the preconditions.

``Net`` tracks what the steps did to the unknown initial state S, each part with
its last writer; ``Requirements`` collects the statements about S (the new OAC's
preconditions) with their first writer; ``decide_precondition`` classifies a
step's bound precondition as established, contradicted (an error naming both
steps) or required; ``net_effects`` turns the net update into effect atoms.
See :mod:`oacdsl.matching.composer` for the rules.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from oacdsl.errors import MatchingError
from oacdsl.matching.conditions import holds
from oacdsl.matching.results import Binding, call_text
from oacdsl.model import Atom, Oac, atom_text
from oacdsl.world import NOTHING, Relation, WorldState, relation

__all__ = ["Net", "Requirements", "Step", "decide_precondition", "key", "net_effects"]


@dataclass(frozen=True)
class Step:
    """One matched sub-action: the OAC, its binding and the keyframes around it.

    ``index`` is the step's position, from 0; ``keyframe`` the keyframe its sub-action starts
    at (None: ``index``, one step per sub-action). A sub-action split into parts
    (:mod:`oacdsl.matching.split`) gives several steps that share a keyframe; ``together``
    marks a step that may run together with the one before it. The frames, when known, are
    recording frames. Messages and notes count steps from 1: step ``index + 1`` ends at
    keyframe ``keyframe + 1``.
    """

    oac: Oac
    binding: Binding
    before: WorldState
    after: WorldState
    index: int
    start_frame: int | None = None
    end_frame: int | None = None
    keyframe: int | None = None
    together: bool = False

    @property
    def mapping(self) -> dict[str, str]:
        return dict(self.binding)

    @property
    def start_keyframe(self) -> int:
        """The keyframe the step's sub-action starts at."""
        return self.index if self.keyframe is None else self.keyframe

    def text(self) -> str:
        return f"step {self.index + 1} {call_text(self.oac.name, self.binding)}"

    def note(self, end: bool) -> str:
        frame = self.end_frame if end else self.start_frame
        where = f"keyframe {self.start_keyframe + int(end)}"
        where += f", frame {frame}" if frame is not None else ""
        return f"step {self.index + 1} {self.oac.name}, {where}"


def key(atom: Atom) -> tuple[str, str, bool]:
    return (atom.left, atom.right, atom.negated)


class Net:
    """The steps' net update of the unknown initial state, with the last writer of each part."""

    def __init__(self) -> None:
        self.added: dict[Relation, Step] = {}
        self.removed: dict[Relation, Step] = {}
        self.cleared: dict[str, Step] = {}

    def pairs_of(self, x: str) -> list[Relation]:
        return sorted(r for r in self.added if x in r)

    def remover(self, r: Relation) -> tuple[Step, str] | None:
        """The step that removed ``r`` (by ``not r`` or by clearing an end), and how."""
        if r in self.removed:
            return self.removed[r], f"not {r[0]} <-> {r[1]}"
        for x in r:
            if x in self.cleared:
                return self.cleared[x], f"{x} <-> nothing"
        return None

    def apply(self, step: Step, effects: Iterable[Atom]) -> None:
        effects = tuple(effects)
        for a in effects:
            if a.about_nothing and not a.negated:
                for r in self.pairs_of(a.left):
                    del self.added[r]
                self.cleared[a.left] = step
            elif a.negated and not a.about_nothing:
                r = relation(a.left, a.right)
                self.added.pop(r, None)
                self.removed[r] = step
        for a in effects:
            if not a.negated and not a.about_nothing:
                r = relation(a.left, a.right)
                self.removed.pop(r, None)
                self.added[r] = step


class Requirements:
    """Preconditions of the new OAC (statements about the initial state), first writer kept."""

    def __init__(self, initial: WorldState) -> None:
        self.initial = initial
        self.atoms: dict[tuple[str, str, bool], Atom] = {}
        self.by: dict[tuple[str, str, bool], Step] = {}
        #: Assumptions the preconditions cannot state (the OAC is sound only under them).
        self.warnings: list[str] = []

    def has(self, left: str, right: str, negated: bool = False) -> bool:
        return (left, right, negated) in self.atoms

    def _conflict(self, atom: Atom) -> tuple[str, str, bool] | None:
        x, y = atom.left, atom.right
        if atom.about_nothing:
            if atom.negated:
                return (x, NOTHING, False) if self.has(x, NOTHING) else None
            for k in self.atoms:
                if not k[2] and k[1] != NOTHING and x in k[:2]:
                    return k
            return (x, NOTHING, True) if self.has(x, NOTHING, True) else None
        if atom.negated:
            return (x, y, False) if self.has(x, y) else None
        for k in ((x, y, True), (x, NOTHING, False), (y, NOTHING, False)):
            if k in self.atoms:
                return k
        return None

    def add(self, atom: Atom, step: Step, extra: str = "") -> None:
        k = key(atom)
        if k in self.atoms:
            return
        clash = self._conflict(atom)
        if clash is not None:
            raise MatchingError(
                f"{step.text()} needs {atom_text(atom)} at the start, which contradicts"
                f" {atom_text(self.atoms[clash])} needed by {self.by[clash].text()}"
                " (no step in between changes it)"
            )
        if not holds(atom, self.initial):
            raise MatchingError(
                f"{step.text()} needs {atom_text(atom)} at the start, but it does not hold in the first"
                " keyframe: the steps' effects do not account for every change (compose with strict matching)"
            )
        self.atoms[k] = atom.model_copy(update={"note": step.note(end=False) + extra})
        self.by[k] = step


def decide_precondition(atom: Atom, step: Step, net: Net, req: Requirements) -> None:
    """Decide one bound precondition of ``step``: established, contradicted or required."""
    x, y = atom.left, atom.right
    need = f"{step.text()} needs {atom_text(atom)}"
    if not atom.about_nothing:
        r = relation(x, y)
        if r in net.added:
            if atom.negated:
                raise MatchingError(f"{need}, but {net.added[r].text()} added {x} <-> {y}")
            return
        removal = net.remover(r)
        if removal is not None:
            if not atom.negated:
                raise MatchingError(f"{need}, but {removal[0].text()} removed it (effect {removal[1]})")
            return
        req.add(atom, step)
        return
    pairs = net.pairs_of(x)
    if atom.negated:  # x touches someone
        if pairs:
            return
        if x in net.cleared:
            raise MatchingError(f"{need}, but {net.cleared[x].text()} cleared it (effect {x} <-> nothing)")
        if not any(x in r for r in net.removed) and not net.cleared:
            req.add(atom, step)
            return
        kept = [p for p in sorted(req.initial.partners(x)) if net.remover(relation(x, p)) is None]
        if not kept:
            raise MatchingError(f"{need}, but every relation of {x} was removed by earlier steps")
        req.add(Atom(left=x, right=kept[0]), step, f" (as {x} <-> {kept[0]})")
        return
    if pairs:
        adder = net.added[pairs[0]]
        raise MatchingError(f"{need}, but {adder.text()} added {pairs[0][0]} <-> {pairs[0][1]}")
    if x in net.cleared:
        return  # established by the earlier clearing effect
    if not any(x in r for r in net.removed) and not net.cleared:
        req.add(atom, step)
        return
    partners = sorted(req.initial.partners(x))
    if partners:  # implied by the demonstration, not expressible: assumed, with a warning
        req.warnings.append(
            f"{need}, which holds because earlier steps removed every relation {x} had at the start"
            f" ({', '.join(partners)}); the new OAC assumes {x} touches nothing else at the start"
        )
        return
    req.add(atom, step)  # stronger than needed, true at the start: sound


def net_effects(net: Net, req: Requirements) -> list[tuple[Atom, Step]]:
    """The net update as atoms, without what the preconditions make redundant, each with
    the step that wrote it last."""
    out: list[tuple[Atom, Step]] = []
    assumed: set[str] = set()
    for x, step in sorted(net.cleared.items()):
        pairs = net.pairs_of(x)
        if not pairs or req.has(x, NOTHING):
            continue
        partners = sorted(req.initial.partners(x))
        if not partners:  # x touched nothing at the start: say so, and the clearing is a no-op
            req.add(Atom(left=x, right=NOTHING), step, f" (so that clearing {x} need not be stated)")
            continue
        # "x touches only what was added" has no atom: end the relations x had at the start.
        assumed.add(x)
        for y in partners:
            if relation(x, y) not in net.added:
                out.append((Atom(left=x, right=y, negated=True, note=step.note(True)), step))
        req.warnings.append(
            f"{step.text()} ends every relation of {x}, then {net.added[pairs[0]].text()} adds"
            f" {pairs[0][0]} <-> {pairs[0][1]}; the effects end only the relations {x} had at the start"
            f" ({', '.join(partners)}), so the new OAC assumes {x} touches nothing else at the start"
        )
    cleared = {x: s for x, s in net.cleared.items() if not req.has(x, NOTHING) and x not in assumed}
    out += [(Atom(left=x, right=NOTHING, note=s.note(True)), s) for x, s in cleared.items()]
    for (a, b), s in net.removed.items():
        if a in cleared or b in cleared or req.has(a, b, True) or req.has(a, NOTHING) or req.has(b, NOTHING):
            continue
        out.append((Atom(left=a, right=b, negated=True, note=s.note(True)), s))
    for (a, b), s in net.added.items():
        if not req.has(a, b):
            out.append((Atom(left=a, right=b, note=s.note(True)), s))
    return out
