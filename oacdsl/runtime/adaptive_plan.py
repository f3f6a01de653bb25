"""What an adaptive run does next (:mod:`oacdsl.runtime.adaptive` runs it): the demonstrated
steps still to come, which of them are done or failed, and the repair from the observed state
(:class:`AdaptivePlan`).

A repair plans from the observed state to the composed OAC's effects with a real planner
(:mod:`oacdsl.planning`): first back into the demonstration, in its order (a short plan to the
preconditions of a demonstrated step still to come, then the demonstrated steps from it on);
else a plan in which each demonstrated step still to come costs :data:`DEMONSTRATED_COST` and
any other grounding of a library OAC :data:`OTHER_COST`. A step whose skill failed is not
chosen again with the same binding. When the effects hold already, the demonstrated steps
still to come run when they apply, else nothing more runs; an executed step that failed so is
left *unmade* (:attr:`AdaptivePlan.unmade`): nothing makes it good, and the run fails with it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from oacdsl.errors import OacError
from oacdsl.matching.conditions import bind_atoms, holds
from oacdsl.model import Atom, atom_text
from oacdsl.planning.engines import PlannedStep, solve
from oacdsl.planning.explain import unreachable
from oacdsl.planning.replay import replay
from oacdsl.planning.state import instance_classes
from oacdsl.planning.task import Action, make_task, primitive_actions
from oacdsl.runtime.binding import Step
from oacdsl.runtime.executor import Run, step_label
from oacdsl.runtime.reach import FarHand, with_other_hand
from oacdsl.world import WorldState

__all__ = ["DEMONSTRATED_COST", "OTHER_COST", "AdaptivePlan", "effect_atoms", "replay_steps", "step_key"]

#: Cost of a demonstrated step still to come, and of any other grounding, in a repair plan.
DEMONSTRATED_COST, OTHER_COST = 1, 10


def step_key(step: Step) -> tuple[str, tuple[tuple[str, str], ...]]:
    return step.oac.name, tuple(sorted(step.binding.items()))


def effect_atoms(step: Step) -> tuple[Atom, ...]:
    return bind_atoms(step.oac.effect, step.binding)


class AdaptivePlan:
    """The steps an adaptive run has still to run (:attr:`queue`), and how it repairs."""

    def __init__(self, run: Run, max_repairs: int, engine: str) -> None:
        self.run, self.max_repairs, self.engine = run, max_repairs, engine
        self.library = run.context.library
        composed = run.oac.composed
        self.goal = bind_atoms(run.oac.effect, run.binding) if composed else effect_atoms(run.steps[0])
        self.demo: list[Step] = list(run.steps)  # demonstrated steps not yet done or skipped
        self.queue: list[Step] = list(run.steps)
        self.banned: set[tuple[str, tuple[tuple[str, str], ...]]] = set()
        self.adaptations: list[dict[str, Any]] = []
        self.repairs = 0
        self.failed: str | None = None
        #: (failed step, why) for each executed step that failed when the composed OAC's effects
        #: held already: nothing makes it good, and the run fails with it
        self.unmade: list[tuple[str, str]] = []

    def note(self, kind: str, index: int, text: str, plan: Sequence[Step] = ()) -> None:
        entry: dict[str, Any] = {"kind": kind, "step": index, "text": text}
        if plan:
            entry["plan"] = [step_label(s.oac.name, s.binding) for s in plan]
        self.adaptations.append(entry)

    def done(self, step: Step) -> None:
        key = step_key(step)
        for k, demo in enumerate(self.demo):
            if step_key(demo) == key:
                del self.demo[k]
                return

    def _generic(self, cost: int) -> list[Action]:
        """The library's primitive OACs at ``cost``, without the bindings that failed."""
        banned: dict[str, list[tuple[tuple[str, str], ...]]] = {}
        for name, binding in sorted(self.banned):
            banned.setdefault(name, []).append(binding)
        return [
            Action(a.name, a.oac, cost=cost, banned=tuple(banned.get(a.oac.name, ())))
            for a in primitive_actions(self.library)
        ]

    def _actions(self) -> list[Action]:
        actions = self._generic(OTHER_COST)
        seen = set()
        for k, step in enumerate(self.demo):
            if step_key(step) in self.banned or step_key(step) in seen:
                continue
            seen.add(step_key(step))
            fixed = tuple((p.name, step.binding[p.name]) for p in step.oac.params)
            name = f"demo-{k + 1}-{step.oac.name.lower()}"
            actions.append(Action(name, step.oac, fixed, DEMONSTRATED_COST))
        return actions

    def _steps(self, plan: Sequence[Any]) -> list[Step]:
        """Planned steps as runtime steps: a demonstrated one keeps its skill parameters."""
        by_key = {step_key(s): s for s in self.demo}
        out = []
        for p in plan:
            oac = self.library.oacs[p.oac]
            out.append(by_key.get((oac.name, tuple(sorted(p.binding.items()))), Step(oac, dict(p.binding))))
        return out

    def _resume(self, state: WorldState, classes: Mapping[str, frozenset[str]]) -> list[Step] | None:
        """The cheapest way back into the demonstration, in its order: a short plan to the
        preconditions of a demonstrated step still to come, then the demonstrated steps from it
        on, when they reach the goal by the matcher's semantics (None: none does)."""
        best: tuple[int, list[Step]] | None = None
        for k in range(len(self.demo)):
            rest = self.demo[k:]
            if any(step_key(s) in self.banned for s in rest):
                continue
            pre = bind_atoms(rest[0].oac.pre, rest[0].binding)
            prefix: list[Step] = []
            if not all(holds(a, state) for a in pre):
                task = make_task(self.run.scene.name, self._generic(1), classes, state, pre)
                plan = solve(task, self.engine, optimal=True)
                if plan is None:
                    continue
                prefix = self._steps(plan)
            try:
                after = replay_steps(self.library, state, [*prefix, *rest])
            except OacError:
                continue
            if not all(holds(a, after) for a in self.goal):
                continue
            cost = OTHER_COST * len(prefix) + DEMONSTRATED_COST * len(rest)
            if best is None or cost < best[0]:
                best = (cost, [*prefix, *rest])
        return None if best is None else best[1]

    def _still_to_come(self, state: WorldState) -> list[Step]:
        """The demonstrated steps not yet done (but those that failed) when, from ``state``, each
        one's preconditions hold in turn and the composed OAC's effects hold after them (by the
        matcher's semantics); else none."""
        rest = [s for s in self.demo if step_key(s) not in self.banned]
        if not rest:
            return []
        try:
            after = replay_steps(self.library, state, rest)
        except OacError:
            return []
        return rest if all(holds(a, after) for a in self.goal) else []

    def hand_over(self, index: int, step: Step, far: FarHand) -> bool:
        """Queue ``step`` and the steps after it with the other hand taking the object (up to
        where it lets go), when they reach the goal by the matcher's semantics (False: not)."""
        steps = with_other_hand([step, *self.queue], far)
        if steps is None or self.repairs >= self.max_repairs:
            return False
        try:
            after = replay_steps(self.library, self.run.world.relations(), steps)
        except OacError:
            return False
        if not all(holds(g, after) for g in self.goal):
            return False
        self.repairs += 1
        self.queue, self.demo = list(steps), list(steps)
        label = step_label(step.oac.name, step.binding)
        self.note("replanned", index, f"{label}: {far.text}: {far.other} takes it", steps)
        return True

    def repair(self, index: int, reason: str, failed: tuple[str, str] | None = None) -> bool:
        """Plan from the observed state to the goal and queue the plan (False: give up).
        ``failed``: (the step, why) when an executed step failed; left unmade (:attr:`unmade`)
        when the goal holds already."""
        state = self.run.world.relations()
        if all(holds(a, state) for a in self.goal):
            if failed is not None:
                self.unmade.append(failed)
            # what the demonstration still does (put down what the hands hold) is done too, when
            # its steps apply as they are: the effects say what ends, not where things are left
            # (KIT Pour, left-handed: the pour's own check failed with 7 of 8 balls in the cup,
            # and the run stopped holding the cup and the carton in the air)
            rest = self._still_to_come(state)
            self.queue = rest
            if rest:
                self.note("replanned", index, f"{reason}; the composed OAC's effects hold already:"
                          " the demonstrated steps still to come run", rest)
            else:
                self.note("replanned", index, f"{reason}; the composed OAC's effects hold already: done")
            return True
        if self.repairs >= self.max_repairs:
            self.failed = f"{reason}; gave up after {self.repairs} repairs"
            self.note("failed", index, self.failed)
            return False
        self.repairs += 1
        classes = instance_classes(self.library, self.run.scene)
        classes = {k: v for k, v in classes.items() if k in state.instances}
        try:
            steps = self._resume(state, classes)
            if steps is None:
                task = make_task(self.run.scene.name, self._actions(), classes, state, self.goal, costs=True)
                plan = solve(task, self.engine)
                if plan is None:
                    why = "; ".join(f"{atom_text(a)}: {w}" for a, w in unreachable(task)) or "no plan exists"
                    self.failed = f"{reason}; no plan from the observed state: {why}"
                    self.note("failed", index, self.failed)
                    return False
                steps = self._steps(plan)
        except OacError as error:
            self.failed = f"{reason}; planning failed: {error}"
            self.note("failed", index, self.failed)
            return False
        self.queue = steps
        self.note("replanned", index, f"replanned after {reason}", steps)
        planned = {step_key(s) for s in steps}
        left = [s for s in self.demo if step_key(s) not in planned]
        for s in left:
            label = step_label(s.oac.name, s.binding)
            self.note("skipped", index, f"skipped {label}: not needed from the observed state")
        self.demo = [s for s in self.demo if step_key(s) in planned]
        return True


def replay_steps(library: Any, state: WorldState, steps: Sequence[Step]) -> WorldState:
    """The state after ``steps`` by the matcher's semantics (PlanningError at an unmet precondition)."""
    return replay(library, state, [PlannedStep(s.oac.name, dict(s.binding), s.oac.name) for s in steps])[-1]
