"""Command-line overrides of a scene's initial state, shared by ``oacc run`` and ``oacc reproduce``.

Light on purpose (no MuJoCo): the command line builds a :class:`SceneOverrides` from
``--place``, ``--fill``, ``--layout`` and ``--state`` before anything heavy is imported, and the
executor passes it to :func:`oacdsl.runtime.layout.plan_layout`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

__all__ = ["SceneOverrides"]


@dataclass(frozen=True)
class SceneOverrides:
    """What the command line says over the scene: places (x, y metres on the table), starting
    containers of liquids, ball counts, and the layout (``auto`` or ``demonstrated``)."""

    places: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    fill: Mapping[str, str] = field(default_factory=dict)
    balls: Mapping[str, int] = field(default_factory=dict)
    layout: str | None = None
    #: ``--state "mixer <-> right_hand"``: hand → the object it holds when the run starts.
    held: Mapping[str, str] = field(default_factory=dict)
    #: ``--strict``: run a composed OAC's demonstrated steps as they are (default: adaptive).
    strict: bool = False
    #: ``--max-repairs``: how often an adaptive run may replan.
    max_repairs: int = 3

    def kwargs(self) -> dict[str, Any]:
        """Keyword arguments for :func:`oacdsl.runtime.executor.prepare`."""
        return {
            "places": dict(self.places),
            "fill": dict(self.fill),
            "balls": dict(self.balls),
            "layout": self.layout,
            "held": dict(self.held),
        }

    def to_json(self) -> dict[str, Any]:
        """The overrides given (empty ones left out), for the report."""
        doc: dict[str, Any] = {}
        if self.places:
            doc["places"] = {k: list(v) for k, v in sorted(self.places.items())}
        if self.fill:
            doc["fill"] = dict(sorted(self.fill.items()))
        if self.balls:
            doc["balls"] = dict(sorted(self.balls.items()))
        if self.layout:
            doc["layout"] = self.layout
        if self.held:
            doc["held"] = dict(sorted(self.held.items()))
        if self.strict:
            doc["strict"] = True
        return doc
