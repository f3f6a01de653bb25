"""Execute an OAC on the simulated ARMAR-III and measure what happened.

:func:`execute` binds the OAC's parameters, sets the scene up (a liquid starts in the
container the OAC's preconditions name), checks the preconditions against the
touching relations the simulation reports, runs the primitive steps' skills one after
the other (the steps of a ``together { … }`` block too, in the written order: they are
independent, so any order gives the same world), and after each step compares
the observed relations with the step's predicted effects. It returns a :class:`RunResult`
(the ``oacc run --json`` document); it never raises for a failure of the robot, only for
a wrong call (unknown OAC, bad binding), as :class:`~oacdsl.errors.RuntimeFailure`.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import mujoco

from oacdsl.errors import RuntimeFailure, did_you_mean
from oacdsl.library import Library
from oacdsl.model import Oac, Scene
from oacdsl.runtime.binding import (
    Call,
    Step,
    bind,
    bound_atoms,
    choose_scene,
    expand,
    holds,
    liquid_contents,
)
from oacdsl.runtime.build import build_model
from oacdsl.runtime.control import Controller, Observer
from oacdsl.runtime.ik import WholeBodyIK
from oacdsl.runtime.intent import coming_takes, predicted_states
from oacdsl.runtime.judging import check as _check
from oacdsl.runtime.judging import judge_call as _judge_call
from oacdsl.runtime.judging import observed_pairs as _pairs
from oacdsl.runtime.judging import pair as _pair
from oacdsl.runtime.layout import plan_layout
from oacdsl.runtime.layout_cause import layout_cause
from oacdsl.runtime.results import CallResult, RunResult, StepResult
from oacdsl.runtime.simworld import SimWorld
from oacdsl.runtime.skills import IMPLEMENTATIONS, SkillContext
from oacdsl.skills import SIGNATURES
from oacdsl.world import WorldState

__all__ = [
    "execute",
    "step_label",
    "RunResult",
    "StepResult",
    "CallResult",
    "Run",
    "prepare",
    "run_prepared",
    "run_step",
    "run_metrics",
]

_UNSTABLE = ("mjWARN_BADQACC", "mjWARN_BADQPOS", "mjWARN_BADQVEL", "mjWARN_BADCTRL")


@dataclass
class Run:
    """A prepared run: the bound steps and the simulation, before anything moved."""

    oac: Oac
    scene: Scene
    binding: dict[str, str]
    steps: list[Step]
    calls: list[Call]
    world: SimWorld
    controller: Controller
    context: SkillContext
    seed: int | None = None
    #: Simulated time (s) when the run proper starts (after a stated hold was set up).
    start_s: float = 0.0


def _set_up_holds(run: Run, held: Mapping[str, str]) -> None:
    """Each hand of ``held`` grasps its object before the run (``--state "mixer <->
    right_hand"``): the robot starts holding it (RuntimeFailure when that cannot be done)."""
    hands = run.world.layout.hands
    for hand, obj in sorted(held.items()):
        if hand not in hands:
            names = ", ".join(sorted(hands))
            raise RuntimeFailure(f"--state: {hand!r} is not one of the robot's hands ({names})")
        if obj not in run.context.objects():
            raise RuntimeFailure(f"--state: {obj!r} is not on the table: no hand can start holding it")
        try:
            IMPLEMENTATIONS["reach_and_grasp"](run.context, hand, obj)
        except RuntimeFailure as error:
            raise RuntimeFailure(f"--state: could not set up {hand} holding {obj}: {error}") from None


def prepare(
    library: Library,
    oac: Oac | str,
    binding: Mapping[str, str] | None = None,
    scene: Scene | str | None = None,
    seed: int | None = None,
    *,
    fill: Mapping[str, str] | None = None,
    observers: Sequence[Observer] = (),
    self_collision: bool = True,
    places: Mapping[str, tuple[float, float]] | None = None,
    balls: Mapping[str, int] | None = None,
    layout: str | None = None,
    demonstrated: Mapping[str, Any] | None = None,
    held: Mapping[str, str] | None = None,
    set_downs: Mapping[str, Any] | None = None,
) -> Run:
    """Bind, lay out and build everything :func:`execute` needs (raises RuntimeFailure).

    The scene's initial state (``at``, ``in``, ``layout``) is the default; ``places``,
    ``fill``, ``balls`` and ``layout`` override it (the command line's ``--place``, …);
    ``demonstrated`` holds the recording's first-frame positions for ``layout demonstrated``
    (:func:`oacdsl.runtime.layout.plan_layout`), ``set_downs`` where it sets objects down
    (:func:`oacdsl.runtime.demo_places.set_down_places`). A liquid the OAC's own preconditions put
    in a container (``l <-> c``) starts there unless ``fill`` says otherwise. ``held`` (hand →
    object) has each hand grasp its object first, before the observers see anything."""
    if isinstance(oac, str):
        if oac not in library.oacs:
            raise RuntimeFailure(f"no oac {oac!r} in the library{did_you_mean(oac, library.oacs)}")
        oac = library.oacs[oac]
    sc = scene if isinstance(scene, Scene) else choose_scene(library, oac, scene, binding)
    bound = bind(library, oac, sc, binding)
    steps, calls = expand(library, oac, bound)
    for step in steps:
        if step.oac.skill not in IMPLEMENTATIONS:
            raise RuntimeFailure(
                f"oac {step.oac.name} executes skill {step.oac.skill!r}, which the runtime"
                f" lacks{did_you_mean(str(step.oac.skill), IMPLEMENTATIONS)}"
            )
        sig = SIGNATURES[str(step.oac.skill)]
        if len(step.args) != len(sig.args):
            raise RuntimeFailure(
                f"oac {step.oac.name} calls skill {sig.text()} with {len(step.args)} arguments"
                " (oacc compile reports this as E040)"
            )
    contents = liquid_contents(library, sc, oac, bound)
    contents.update(fill or {})
    plan = plan_layout(
        library, sc, contents, seed, places, balls=balls, layout=layout, demonstrated=demonstrated,
        set_downs=set_downs,
    )
    world = SimWorld(build_model(plan, seed))
    ik = WholeBodyIK(self_collision=self_collision)
    controller = Controller(world, ik, [] if held else list(observers))
    context = SkillContext(controller, library, library.instance_classes(sc))
    run = Run(oac, sc, bound, steps, calls, world, controller, context, seed)
    if held:
        _set_up_holds(run, held)
        run.start_s = world.time_s
        for observer in observers:
            controller.add_observer(observer)
    return run


def _with_cause(error: str, run: Run, state: WorldState, atoms: list[tuple[str, str, bool]]) -> str:
    """``error`` with the layout named as its cause when the failing atoms are about its objects."""
    cause = layout_cause(run.world.layout, [(a, b, n) for a, b, n in atoms if not holds(state, a, b, n)])
    return f"{error}; {cause}" if cause else error


def execute(
    library: Library,
    oac: Oac | str,
    binding: Mapping[str, str] | None = None,
    scene: Scene | str | None = None,
    seed: int | None = None,
    recorder: Observer | None = None,
    *,
    fill: Mapping[str, str] | None = None,
    observers: Sequence[Observer] = (),
    self_collision: bool = True,
    places: Mapping[str, tuple[float, float]] | None = None,
    on_step: Any = None,
    balls: Mapping[str, int] | None = None,
    layout: str | None = None,
    demonstrated: Mapping[str, Any] | None = None,
) -> RunResult:
    """Run ``oac`` in simulation and report per step (see the module docstring).

    ``recorder`` is called with the world at its ``rate_hz`` (e.g. a
    :class:`~oacdsl.runtime.recorder.MarkerRecorder`); ``observers`` likewise (video);
    ``on_step(index, step_result, world)`` is called after every step (frame snapshots);
    ``places`` puts named objects at given (x, y) on the table over the scene's ``at`` (metres).
    """
    wall0 = time.perf_counter()
    run = prepare(
        library,
        oac,
        binding,
        scene,
        seed,
        fill=fill,
        observers=[*([recorder] if recorder is not None else []), *observers],
        self_collision=self_collision,
        places=places,
        balls=balls,
        layout=layout,
        demonstrated=demonstrated,
    )
    return run_prepared(run, on_step=on_step, wall0=wall0)


def step_label(name: str, binding: Mapping[str, str]) -> str:
    """``name(instance, …)``: a step or call as the terminal and the errors name it."""
    return f"{name}({', '.join(binding.values())})"


def run_prepared(
    run: Run, *, on_step: Any = None, on_call: Any = None, wall0: float | None = None
) -> RunResult:
    """Execute a :func:`prepare`-d run (observers may be added to ``run.controller`` first).

    ``on_step(index, step_result, world)`` is called after every primitive step,
    ``on_call(call_result)`` after every composed step was judged."""
    wall0 = time.perf_counter() if wall0 is None else wall0
    world, ctx, seed = run.world, run.context, run.seed
    results: list[StepResult] = []
    judged: list[CallResult] = []
    failed: str | None = None
    states = [world.relations()]
    goal = bound_atoms(run.oac.effect, run.binding) if run.oac.composed else []
    expected = predicted_states(states[0], run.steps, goal)
    top_pre = _check(
        states[0], bound_atoms(run.oac.pre, run.binding), f"precondition of {run.oac.name} not met"
    )
    top_pre = top_pre and _with_cause(top_pre, run, states[0], bound_atoms(run.oac.pre, run.binding))
    for index, step in enumerate(run.steps):
        atoms_pre = bound_atoms(step.oac.pre, step.binding)
        effects = bound_atoms(step.oac.effect, step.binding)
        predicted = sorted(_pair(a, b) for a, b, n in effects if not n)
        mentioned = set(step.binding.values())
        t0 = world.time_s
        error = top_pre if index == 0 else None
        error = error or _check(world.relations(), atoms_pre, f"precondition of {step.oac.name} not met")
        if error is not None and index == 0 and error is not top_pre:
            error = _with_cause(error, run, states[0], atoms_pre)
        if error is None:
            ctx.expected = expected[index]
            ctx.coming = coming_takes(run.steps[index + 1 :], world.layout.hands)
            error = _run_skill(ctx, step)
            ctx.expected, ctx.coming = None, ()
        state = world.relations()
        states.append(state)
        if error is None:
            error = _check(state, effects, f"{step.oac.name}: predicted effect not observed")
        result = StepResult(
            step.oac.name,
            dict(step.binding),
            error is None,
            world.time_s - t0,
            predicted,
            _pairs(state, mentioned),
            error,
            step.given or None,
        )
        results.append(result)
        if error is not None:
            failed = f"step {index + 1} {step_label(step.oac.name, step.binding)}"
        if on_step is not None:
            on_step(index, result, world)
        if error is not None:
            break
        # composed steps that end here, inner before outer
        for call in sorted((c for c in run.calls if c.last == index), key=lambda c: -c.depth):
            verdict = _judge_call(call, state)
            judged.append(verdict)
            if on_call is not None:
                on_call(verdict)
            if verdict.error is not None:
                what = "the composed OAC" if call.depth == 0 else "composed step"
                span = f"steps {call.first + 1}-{call.last + 1}"
                failed = f"{what} {step_label(call.oac.name, call.binding)} ({span})"
                break
        if failed is not None:
            break
    success = bool(results) and failed is None and len(results) == len(run.steps)
    return RunResult(run.oac.name, success, results, run_metrics(run, wall0), seed, states, judged, failed)


def run_metrics(run: Run, wall0: float) -> dict[str, float | int]:
    """A finished run's figures: balls poured into containers that started empty, simulated and
    wall time (s, since ``wall0``), regrasps internal to a step (not changes of the task)."""
    world = run.world
    filled = set(world.layout.liquids.values())  # containers that start empty: poured to
    targets = [p.name for p in world.layout.placements if p.body.container and p.name not in filled]
    return {
        "balls_total": world.balls_total,
        "balls_in_bowl": sum(world.balls_inside(b) for b in targets),
        "sim_time_s": round(world.time_s - run.start_s, 4),
        "wall_time_s": round(time.perf_counter() - wall0, 4),
        "regrasps": len(run.controller.regrasps),
        "reseats": len(run.controller.reseats),
    }


def _run_skill(ctx: SkillContext, step: Step) -> str | None:
    skill = IMPLEMENTATIONS[str(step.oac.skill)]
    try:
        skill(ctx, *step.args, **step.params)
    except RuntimeFailure as failure:
        # a skill names itself ("stir: …"): a step of the same name does not say it twice
        text, prefix = str(failure), f"{step.oac.name}: "
        return text if text.startswith(prefix) else prefix + text
    except mujoco.FatalError as failure:
        return f"{step.oac.name}: the simulation failed: {failure}"
    unstable = {k: v for k, v in ctx.world.warnings().items() if k in _UNSTABLE}
    if unstable:
        return f"{step.oac.name}: the simulation became unstable ({', '.join(unstable)})"
    return None


def run_step(
    ctx: SkillContext, step: Step, expected: WorldState | None, coming: Sequence[Step] = ()
) -> str | None:
    """Run one primitive step's skill, told the world state it is meant to leave and the steps
    meant to follow (``coming``): the error, or None. The hook the adaptive executor
    (:mod:`oacdsl.runtime.adaptive`) drives."""
    ctx.expected = expected
    ctx.coming = coming_takes(coming, ctx.world.layout.hands)
    try:
        return _run_skill(ctx, step)
    finally:
        ctx.expected, ctx.coming = None, ()
