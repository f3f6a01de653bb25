"""The typed model of the OAC language (pydantic, frozen, hashable).

Every node may carry the :class:`Span` of the text it came from and the comments
written before it; both are *trivia*: kept for diagnostics and for the printer,
but left out of equality and hashing, so ``parse(print(m)) == m`` compares
meaning, not layout. Collections whose order carries no meaning (parents,
preconditions, effects) are normalised to sorted, de-duplicated tuples when a
node is built, so two models that mean the same compare equal.

Units: grasp offsets are metres in the object's frame; geometry, placements and
skill parameters keep each quantity with the unit it was written in
(:class:`Quantity`; :func:`oacdsl.units.language_si` converts to SI).

The model is split by concept: :mod:`~oacdsl.model.node` (spans, the base node, quantities),
:mod:`~oacdsl.model.objects` (classes, geometry, grasps), :mod:`~oacdsl.model.scene` (instances
and initial state), :mod:`~oacdsl.model.oac` (atoms, parameters, calls, OACs); everything is
imported from here.
"""

from __future__ import annotations

from typing import Any

from pydantic import Field

from oacdsl.model.node import (
    Dim,
    Node,
    Point,
    Quantity,
    Span,
)
from oacdsl.model.oac import (
    Atom,
    Call,
    KeyPose,
    Oac,
    Param,
    PathValue,
    SkillParam,
    atom_text,
    canonical_steps,
    pair_order,
    sorted_skill_params,
    step_groups,
)
from oacdsl.model.objects import (
    APPROACHES,
    GRASP_TYPES,
    Geometry,
    Grasp,
    ObjectClass,
    Shape,
)
from oacdsl.model.scene import (
    LAYOUTS,
    MAX_BALLS,
    Instance,
    Scene,
    SceneFill,
    ScenePlace,
    fill_key,
    place_key,
)

__all__ = [
    "APPROACHES",
    "GRASP_TYPES",
    "LAYOUTS",
    "MAX_BALLS",
    "Atom",
    "Call",
    "Decl",
    "Dim",
    "Geometry",
    "Grasp",
    "Instance",
    "KeyPose",
    "Module",
    "Node",
    "Oac",
    "ObjectClass",
    "Param",
    "PathValue",
    "Point",
    "Quantity",
    "Scene",
    "SceneFill",
    "ScenePlace",
    "Shape",
    "SkillParam",
    "Span",
    "atom_text",
    "canonical_steps",
    "fill_key",
    "pair_order",
    "place_key",
    "sorted_skill_params",
    "step_groups",
]

Decl = ObjectClass | Scene | Grasp | Oac


class Module(Node):
    """The declarations of one ``.oac`` file, in source order."""

    path: str
    decls: tuple[Decl, ...]
    #: Comments after the last declaration of the file.
    trailing: tuple[str, ...] = Field(default=(), repr=False)

    def _key(self) -> tuple[Any, ...]:
        return (self.decls,)
