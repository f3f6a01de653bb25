"""Compose a new OAC from a sequence of matched sub-actions (the paper's Algorithm 1).

Algorithm 1 applied per relation. The steps' bound effects are tracked as a net
update of the unknown initial state S: pairs added (A), pairs removed (R) and
instances whose relations were all cleared (C, by an ``x <-> nothing`` effect),
each with the step that wrote it last (a later effect overwrites an earlier one).
A bound precondition of step k is then

- *established* when the earlier steps make it true: ``a <-> b`` in A; ``not a <-> b``
  in R or cleared; ``x <-> nothing`` when x was cleared and nothing re-added a pair
  of x since (``place`` then ``grasp`` with the same hand adds no precondition);
  ``not x <-> nothing`` when a pair of x was added;
- *contradicted* when the earlier steps make it false: an error naming both steps
  (an earlier step removed a relation a later step needs);
- otherwise a precondition of the new OAC, i.e. a statement about S. A statement
  that the earlier steps only make partly true (``x <-> nothing`` after some of x's
  pairs were removed) cannot be written as it is; it becomes ``x <-> nothing`` on
  S when x touched nothing in the demonstration's first keyframe (stronger, still
  true there, and sound), and is an error otherwise.

The new OAC's effects are the net update (A as ``a <-> b``, R as ``not a <-> b``, C
as ``x <-> nothing``) with what the preconditions make redundant left out. They are
*sound*: applied to any state that satisfies the preconditions they give the same
state as the steps one by one. The paper's view, the relations of the final world
state that the initial one lacks, is kept as ``Composition.added`` (and
``ended`` for those that ended); with ``paper_effects=True`` the OAC's effects are
exactly the paper's.

Every precondition and effect carries provenance in ``Atom.note``: the step and
keyframe (and frame) that produced it.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from oacdsl.errors import MatchingError
from oacdsl.library import Library
from oacdsl.matching.algorithm1 import Net, Requirements, Step, decide_precondition, key, net_effects
from oacdsl.matching.conditions import bind_atoms
from oacdsl.matching.lift import lift
from oacdsl.model import Atom, Call, Oac, Scene, atom_text
from oacdsl.world import NOTHING, Relation

__all__ = ["Composition", "Step", "compose"]


@dataclass(frozen=True)
class Composition:
    """The composed OAC and the views of it a user asks for.

    Attributes:
        oac: the new OAC, lifted to typed parameters (defaults = the demonstration's
            instances), preconditions and effects with provenance notes, ``steps`` the calls.
        pre: the preconditions over instances (the demonstration's binding).
        effect: the OAC's effects over instances.
        added: the paper's effects: relations of the final state that the initial state lacks.
        ended: relations of the initial state that the final state lacks.
        steps: the steps composed.
        names: instance → parameter name.
        warnings: things the user should know (the paper's effects are not sound, …).
    """

    oac: Oac
    pre: tuple[Atom, ...]
    effect: tuple[Atom, ...]
    added: tuple[Relation, ...]
    ended: tuple[Relation, ...]
    steps: tuple[Step, ...]
    names: dict[str, str]
    warnings: tuple[str, ...] = field(default=())
    #: Where each precondition, effect and ended relation comes from: ``{"kind": "pre" |
    #: "effect" | "ended", "relation": [a, b], "negated": bool, "step": index into steps,
    #: "keyframe": index into the keyframes, "note": str}`` (instance names).
    provenance: tuple[dict[str, Any], ...] = field(default=())
    #: Skill parameters set from the demonstrated motion, per step that has any to set
    #: (:func:`oacdsl.matching.composedparams.with_demo_params`; ``compose.demo_params`` of result.json).
    demo_params: tuple[dict[str, Any], ...] = field(default=())

    def to_json(self, file: str | None) -> dict[str, Any]:
        """The ``oacc compose --json`` document."""
        doc: dict[str, Any] = {
            "name": self.oac.name,
            "pre": [_pair(a) for a in self.pre if not a.negated],
            "effect": [list(r) for r in self.added],
            "ended": [list(r) for r in self.ended],
            "steps": [{"oac": s.oac.name, "binding": dict(s.binding),
                       **({"together": True} if s.together else {})} for s in self.steps],
            "file": file,
        }
        negated = [_pair(a) for a in self.pre if a.negated]
        if negated:
            doc["pre_not"] = negated
        for entry in self.demo_params:
            given = {r["name"]: r["value"] for r in entry["params"] if r["value"] is not None}
            if given:
                doc["steps"][entry["step"]]["params"] = given
        if self.demo_params:
            doc["demo_params"] = list(self.demo_params)
        return doc


def _pair(atom: Atom) -> list[str]:
    return [atom.left, atom.right]


def compose(
    name: str,
    steps: Sequence[Step],
    library: Library,
    scene: Scene | None = None,
    *,
    instance_classes: Mapping[str, frozenset[str]] | None = None,
    paper_effects: bool = False,
) -> Composition:
    """Compose ``steps`` into a new OAC called ``name`` (see the module docstring). Steps
    marked ``together`` (a split keyframe, :mod:`oacdsl.matching.split`) become a
    ``together { … }`` block, in their order."""
    if not steps:
        raise MatchingError("nothing to compose: the demonstration has no sub-actions")
    if instance_classes is None:
        if scene is None:
            raise MatchingError("composing needs the scene (or the instances' classes) to type parameters")
        instance_classes = library.instance_classes(scene)
    classes = instance_classes
    initial, final = steps[0].before, steps[-1].after
    net = Net()
    req = Requirements(initial)
    for step in steps:
        mapping = step.mapping
        for atom in bind_atoms(step.oac.pre, mapping):
            decide_precondition(atom, step, net, req)
        net.apply(step, bind_atoms(step.oac.effect, mapping))
    written = net_effects(net, req)
    effects = tuple(a for a, _ in written)
    added = tuple(sorted(final.relations - initial.relations))
    ended = tuple(sorted(initial.relations - final.relations))
    warnings = req.warnings
    paper = tuple(
        Atom(
            left=a,
            right=b,
            note=(net.added[(a, b)].note(True) if (a, b) in net.added else "world-state change"),
        )
        for a, b in added
    )
    if paper_effects:
        sound = {key(a) for a in effects}
        if sound != {key(a) for a in paper}:
            warnings.append(
                "the paper's effects differ from the steps' net effects ("
                + ", ".join(atom_text(a) for a in effects)
                + "): the OAC is not sound"
            )
        effects = paper
        written = [(a, net.added.get((a.left, a.right))) for a in paper]  # type: ignore[misc]
    provenance = [_source("pre", a, req.by[key(a)]) for a in req.atoms.values()]
    provenance += [_source("effect", a, s) for a, s in written]
    provenance += [_source("ended", Atom(left=a, right=b), (net.remover((a, b)) or (None,))[0])
                   for a, b in ended]
    if not effects:  # it ends as it began (take, stir, put back): its steps still change the world
        warnings.append("the demonstration ends as it began: the composed OAC has no net effect;"
                        " each of its steps is judged by its own effects")
    comp = _lifted(name, steps, tuple(req.atoms.values()), effects, added, ended, classes, library, warnings)
    return dataclasses.replace(comp, provenance=tuple(provenance))


def _source(kind: str, atom: Atom, step: Step | None) -> dict[str, Any]:
    """One provenance record (the ``compose.provenance`` entries of ``result.json``)."""
    end = kind != "pre"
    return {
        "kind": kind,
        "relation": [atom.left, atom.right],
        "negated": atom.negated,
        "step": step.index if step is not None else None,
        "keyframe": (step.start_keyframe + int(end)) if step is not None else None,
        "note": step.note(end) if step is not None else "world-state change",
    }


def _lifted(
    name: str,
    steps: Sequence[Step],
    pre: tuple[Atom, ...],
    effect: tuple[Atom, ...],
    added: tuple[Relation, ...],
    ended: tuple[Relation, ...],
    classes: Mapping[str, frozenset[str]],
    library: Library,
    warnings: list[str],
) -> Composition:
    order: list[str] = []
    required: dict[str, list[str]] = {}
    constants: set[str] = set()
    for step in steps:
        params = {p.name for p in step.oac.params}
        for p in step.oac.params:
            inst = step.mapping[p.name]
            required.setdefault(inst, []).append(p.cls)
            if inst not in order:
                order.append(inst)
        for a in (*step.oac.pre, *step.oac.effect):
            constants.update(n for n in (a.left, a.right) if n not in params and n != NOTHING)
    for a in (*pre, *effect):
        for n in (a.left, a.right):
            if n != NOTHING and n not in order:
                order.append(n)
    order = [i for i in order if i not in constants]
    lifted, names = lift(order, classes, required, library.ancestors)

    def up(a: Atom) -> Atom:  # built anew: the pair order is normalised again after renaming
        return Atom(
            left=names.get(a.left, a.left), right=names.get(a.right, a.right), negated=a.negated, note=a.note
        )

    calls = tuple(
        Call(
            oac=s.oac.name,
            args=tuple(names.get(s.mapping[p.name], s.mapping[p.name]) for p in s.oac.params),
            together=s.together,
        )
        for s in steps
    )
    oac = Oac(name=name, params=lifted, pre=tuple(map(up, pre)), effect=tuple(map(up, effect)), steps=calls)
    return Composition(
        oac=oac,
        pre=tuple(sorted(pre, key=Atom.sort_key)),
        effect=tuple(sorted(effect, key=Atom.sort_key)),
        added=added,
        ended=ended,
        steps=tuple(steps),
        names=names,
        warnings=tuple(warnings),
    )
