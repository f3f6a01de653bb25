"""Plan a goal over a scene with a library's OACs: the task, the plan, or why there is none.

:func:`plan_goal` is what ``oacc plan`` prints: a plan of library OACs with their bindings,
checked by replaying it through the matcher's semantics, or — when the engine proves that
none exists — each goal atom that cannot be reached and why (relaxed reachability,
:mod:`oacdsl.planning.explain`), or, when each atom can be reached alone, that they cannot
all hold together.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from oacdsl.errors import PlanningError
from oacdsl.library import Library
from oacdsl.matching.conditions import holds
from oacdsl.model import Atom, Scene, atom_text
from oacdsl.planning.engines import PlannedStep, solve
from oacdsl.planning.explain import unreachable
from oacdsl.planning.replay import replay
from oacdsl.planning.state import instance_classes
from oacdsl.planning.task import Action, Task, make_task, primitive_actions
from oacdsl.world import WorldState

__all__ = ["PlanResult", "goal_task", "plan_goal"]


@dataclass
class PlanResult:
    """A plan (None: none exists) and, without one, the goal atoms that cannot be reached."""

    goal: tuple[Atom, ...]
    engine: str
    plan: list[PlannedStep] | None
    unreachable: list[tuple[Atom, str]] = field(default_factory=list)
    states: list[WorldState] = field(default_factory=list)
    time_s: float = 0.0

    @property
    def why(self) -> str:
        """One line saying why no plan exists."""
        if self.unreachable:
            return "; ".join(f"{atom_text(a)}: {why}" for a, why in self.unreachable)
        return "each goal atom can be reached alone, but not all of them together"

    def to_json(self) -> dict[str, Any]:
        doc: dict[str, Any] = {
            "goal": [atom_text(a) for a in self.goal],
            "engine": self.engine,
            "planned": self.plan is not None,
            "time_s": round(self.time_s, 4),
        }
        if self.plan is not None:
            doc["plan"] = [s.to_json() for s in self.plan]
            doc["final"] = [list(r) for r in self.states[-1].sorted_relations()] if self.states else []
        else:
            doc["unreachable"] = [{"atom": atom_text(a), "why": w} for a, w in self.unreachable]
            doc["why"] = self.why
        return doc


def goal_task(
    library: Library,
    scene: Scene,
    state: WorldState,
    goal: Sequence[Atom],
    actions: Sequence[Action] | None = None,
    *,
    costs: bool = False,
) -> Task:
    """The planning task: the library's primitive OACs (or ``actions``) over ``scene``'s
    related instances, from ``state`` to ``goal``."""
    classes = instance_classes(library, scene)
    chosen = primitive_actions(library) if actions is None else actions
    return make_task(scene.name, chosen, classes, state, goal, costs=costs)


def plan_goal(
    library: Library,
    scene: Scene,
    state: WorldState,
    goal: Sequence[Atom],
    engine: str = "fast-downward",
    *,
    optimal: bool = False,
) -> PlanResult:
    """Plan ``goal`` from ``state`` (see the module docstring)."""
    t0 = time.perf_counter()
    task = goal_task(library, scene, state, goal)
    if all(holds(a, state) for a in goal):
        return PlanResult(tuple(goal), engine, [], states=[state], time_s=time.perf_counter() - t0)
    steps = solve(task, engine, optimal=optimal)
    if steps is None:
        return PlanResult(tuple(goal), engine, None, unreachable(task), time_s=time.perf_counter() - t0)
    states = replay(library, state, steps)
    missed = [atom_text(a) for a in goal if not holds(a, states[-1])]
    if missed:  # the encoding and the matcher disagree: say so rather than print a wrong plan
        raise PlanningError(f"{engine}'s plan does not reach {', '.join(missed)} by the matcher's semantics")
    return PlanResult(tuple(goal), engine, steps, states=states, time_s=time.perf_counter() - t0)
