"""Adaptive execution: the world at execution time decides which steps run (issue 22).

A composed OAC's demonstrated steps run in order, but before each one the executor reads the
world state from the simulation's contacts:

* a step whose effects all hold already is **skipped** ("skipped pour(…): liquid_one <->
  orange_bowl already holds");
* when a step's preconditions do not hold, or its skill fails, or its effects are not
  observed, the executor **replans** from the observed state to the composed OAC's effects
  with a real planner (:mod:`oacdsl.planning`), preferring the demonstrated steps still to
  come with their bindings (each costs 1, any other grounding of an OAC 10), and runs the
  repair; a step whose skill failed is not chosen again with the same binding;
* a step that would send a hand for an object its arm does not reach while the other hand's
  does is not run: the repair leaves the object to the other hand (:mod:`oacdsl.runtime.reach`);
  when that holds for the task as a whole (a left-handed demonstration in a scene laid out for
  the right hand), the two hands are **exchanged** for every step before the run starts;
* at most ``max_repairs`` repairs; no plan is a clear failure naming the unreachable atoms;
* a step that failed when the composed OAC's effects held already is made good by nothing:
  the run fails with it, its outcome ``effects hold, but step 3 screw_on(…) failed``
  (``RunResult.effects_hold``), as a script running many tasks must tell it from success.

Every adaptation is recorded in ``RunResult.adaptations`` (the run's JSON). The per-step
machinery is the executor's (:func:`oacdsl.runtime.executor.run_step`); what to run next and
the repairs are :mod:`oacdsl.runtime.adaptive_plan`'s; this module runs the loop.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Mapping, Sequence
from typing import Any

from oacdsl.errors import OacError
from oacdsl.matching.conditions import bind_atoms, holds
from oacdsl.model import atom_text
from oacdsl.runtime.adaptive_plan import AdaptivePlan, effect_atoms, step_key
from oacdsl.runtime.binding import Step, bound_atoms
from oacdsl.runtime.executor import Run, run_metrics, run_step, step_label
from oacdsl.runtime.intent import predicted_states
from oacdsl.runtime.judging import check as _check
from oacdsl.runtime.judging import judge_call as _judge_call
from oacdsl.runtime.judging import observed_pairs as _pairs
from oacdsl.runtime.judging import pair as _pair
from oacdsl.runtime.reach import exchanged_hands, out_of_reach
from oacdsl.runtime.results import RunResult, StepResult
from oacdsl.world import WorldState

__all__ = ["MAX_REPAIRS", "describe", "run_adaptive"]

#: Repairs (replanning) one run may make before it gives up.
MAX_REPAIRS = 3
#: ``fault(index, step, world)`` is called after each executed step was judged (tests inject one).
Fault = Callable[[int, Step, Any], None]


def _changes_nothing_by_design(step: Step, state: WorldState) -> bool:
    """True when the step's effects follow from its own preconditions (``keep``: hold on for a
    while, its effect ``not h <-> nothing`` implied by ``h <-> o``): such a step changes no
    relation even in the demonstration, so its effects holding is no reason to skip it."""
    pre = [a for a in bind_atoms(step.oac.pre, step.binding) if not a.negated and not a.about_nothing]
    minimal = WorldState.of(state.instances, [(a.left, a.right) for a in pre if a.left != a.right])
    return all(holds(x, minimal) for x in effect_atoms(step))


def _recover(run: Run, step: Step) -> str:
    """After a failed skill: each empty hand of the step opens, goes back to its home pose and
    takes its wrist force as zero again (a safety stop leaves it pressing on something).
    Returns a note for the adaptation's text ("" when nothing was done)."""
    from oacdsl.runtime.skills import IMPLEMENTATIONS

    ctx, world = run.context, run.world
    done = []
    for name in step.binding.values():
        if name not in world.layout.hands:  # only the step's hands
            continue
        side = ctx.side(name)
        if world.held.get(side) is not None:
            continue
        try:
            ctx.ctl.tare(side)
            ctx.ctl.open_hand(side)
            IMPLEMENTATIONS["retreat"](ctx, name)
        except OacError:
            pass  # the repair plans from wherever the hand is
        for s in ("l", "r"):
            ctx.ctl.tare(s)
        done.append(name)
    return f" ({', '.join(done)} taken back)" if done else ""


def _with_hands(run: Run, swap: Mapping[str, str]) -> Run:
    """``run`` with every binding's hands exchanged by ``swap``."""
    def bound(binding: Mapping[str, str]) -> dict[str, str]:
        return {k: swap.get(v, v) for k, v in binding.items()}

    return dataclasses.replace(
        run, binding=bound(run.binding),
        steps=[dataclasses.replace(s, binding=bound(s.binding)) for s in run.steps],
        calls=[dataclasses.replace(c, binding=bound(c.binding)) for c in run.calls])


def run_adaptive(
    run: Run,
    *,
    on_step: Any = None,
    on_call: Any = None,
    wall0: float | None = None,
    max_repairs: int = MAX_REPAIRS,
    engine: str = "fast-downward",
    fault: Fault | None = None,
) -> RunResult:
    """Execute a :func:`~oacdsl.runtime.executor.prepare`-d run adaptively (module docstring);
    the same result as :func:`~oacdsl.runtime.executor.run_prepared`, with ``adaptations``."""
    wall0 = time.perf_counter() if wall0 is None else wall0
    world, ctx = run.world, run.context
    exchange = exchanged_hands(ctx, run.steps) if run.oac.composed else None
    if exchange is not None:  # a left-handed demonstration in a scene laid out for the right hand
        run = _with_hands(run, exchange[0])
    a = AdaptivePlan(run, max_repairs, engine)
    if exchange is not None:
        a.note("exchanged", 0, exchange[1], run.steps)
    results: list[StepResult] = []
    states = [world.relations()]
    goal = bound_atoms(run.oac.effect, run.binding) if run.oac.composed else []
    top = _check(states[0], bound_atoms(run.oac.pre, run.binding), f"precondition of {run.oac.name} not met")
    if top is not None and a.goal and all(holds(g, states[0]) for g in a.goal):
        # the effects say what ends, not what happens (KIT Cut: the knife leaves the cucumber):
        # holding at the start they ask for nothing, so the demonstration's steps decide
        a.note("followed", 0, f"{top}; the composed OAC's effects hold at the start: its steps run,"
               " each skipped when its effects hold")
    elif top is not None and not a.repair(0, top):
        a.queue = []
    executed = 0
    while a.queue and a.failed is None:
        step = a.queue.pop(0)
        state = world.relations()
        label = step_label(step.oac.name, step.binding)
        effects = effect_atoms(step)
        if effects and all(holds(x, state) for x in effects) and not _changes_nothing_by_design(step, state):
            a.note("skipped", executed + 1, f"skipped {label}: {', '.join(atom_text(x) for x in effects)}"
                   f" already hold{'s' * (len(effects) == 1)}")
            a.done(step)
            continue
        pre = bound_atoms(step.oac.pre, step.binding)
        error = _check(state, pre, f"precondition of {step.oac.name} not met")
        far = out_of_reach(ctx, step, state) if error is None else None
        if far is not None:  # the demonstrated hand takes an object only when its arm reaches it
            a.banned.add(step_key(step))
            if not a.hand_over(executed + 1, step, far):
                a.repair(executed + 1, f"{label}: {far.text}")
            continue
        if error is not None:
            a.repair(executed + 1, f"{label}: {error}")
            continue
        t0 = world.time_s
        expected = predicted_states(state, [step, *a.queue], goal)[0]
        error = run_step(ctx, step, expected, a.queue)
        after = world.relations()
        states.append(after)
        bound_effects = bound_atoms(step.oac.effect, step.binding)
        if error is None:
            error = _check(after, bound_effects, f"{step.oac.name}: predicted effect not observed")
        predicted = sorted(_pair(x, y) for x, y, n in bound_effects if not n)
        result = StepResult(step.oac.name, dict(step.binding), error is None, world.time_s - t0, predicted,
                            _pairs(after, set(step.binding.values())), error, step.given or None)
        results.append(result)
        executed += 1
        if on_step is not None:
            on_step(executed - 1, result, world)
        if fault is not None:
            fault(executed - 1, step, world)
        if error is None:
            a.done(step)
            continue
        a.banned.add(step_key(step))
        recovered = _recover(run, step)
        a.repair(executed, f"step {executed} {label} failed: {error}{recovered}",
                 (f"step {executed} {label}", error))
    final = world.relations()
    judged = []
    if run.oac.composed and run.calls:
        top_call = run.calls[0]
        verdict = _judge_call(top_call, final)
        judged.append(verdict)
        if on_call is not None:
            on_call(verdict)
    reached = all(holds(x, final) for x in a.goal)
    # a step that failed with the effects holding already stays failed: the run did not do all
    # it was asked (a lid that never went on the bottle, a pour that spilled a ball)
    success = a.failed is None and reached and all(j.success for j in judged) and not a.unmade
    failed_step: str | None = None
    failure: str | None = None
    if a.failed is not None:
        failed_step = a.failed
    elif a.unmade and reached:
        failed_step, failure = a.unmade[0]
    elif not success:
        failed_step = f"the composed OAC {step_label(run.oac.name, run.binding)}"
    metrics = {**run_metrics(run, wall0), "repairs": a.repairs}
    out = RunResult(run.oac.name, success, results, metrics, run.seed, states, judged, failed_step)
    out.adaptations = a.adaptations
    out.effects_hold = reached if run.oac.composed else None
    out.failure = failure
    return out


def describe(adaptations: Sequence[Mapping[str, Any]]) -> list[str]:
    """One line per adaptation, for the terminal and the report."""
    return [str(x["text"]) + (f" → {', '.join(x['plan'])}" if x.get("plan") else "") for x in adaptations]
