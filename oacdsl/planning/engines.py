"""Plan a :class:`~oacdsl.planning.task.Task` with a real planner.

The task is written as PDDL (:mod:`oacdsl.planning.pddl`), so what is planned is exactly
what ``oacc pddl`` writes. Engines:

* ``fast-downward`` — Fast Downward, the planner inside the ``up-fast-downward`` wheel, run
  on the PDDL files directly (:mod:`oacdsl.planning.downward`): an optimal search (A*) for
  tasks with action costs and when asked (``optimal``), the LAMA configuration otherwise;
* ``pyperplan`` — pyperplan (``up-pyperplan``) through unified-planning, which reads the
  PDDL and whose compilers remove what pyperplan does not read (quantifiers, negative
  conditions, equality: the task is grounded).

A satisficing plan is looked for in a sub-task over the goal's instances and a few spares
first (:mod:`oacdsl.planning.subtask`), then in the whole task. Nothing here searches: a
missing package or an engine failure is a :class:`~oacdsl.errors.PlanningError` naming the
``plan`` extra.
"""

from __future__ import annotations

import io
import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager, redirect_stdout
from dataclasses import dataclass
from typing import Any

from oacdsl.errors import PlanningError
from oacdsl.planning import downward
from oacdsl.planning.pddl import domain_text, problem_text
from oacdsl.planning.subtask import sub_task
from oacdsl.planning.task import Task

__all__ = ["ENGINES", "PlannedStep", "solve"]

#: The engines ``oacc plan --engine`` accepts.
ENGINES = ("fast-downward", "pyperplan")


@dataclass(frozen=True)
class PlannedStep:
    """One step of a plan: an OAC with its parameters bound to instances."""

    oac: str
    binding: dict[str, str]
    action: str  # the PDDL action's name (differs from ``oac`` for a preferred step)

    def label(self) -> str:
        return f"{self.oac}({', '.join(self.binding.values())})"

    def to_json(self) -> dict[str, Any]:
        return {"oac": self.oac, "binding": dict(self.binding)}


def _up() -> Any:
    try:
        import unified_planning.shortcuts as shortcuts
        from unified_planning.io import PDDLReader
    except ImportError as error:
        raise PlanningError(
            f"planning needs the 'plan' extra (pip install oacdsl[plan]): {error}"
        ) from None
    env = shortcuts.get_environment()
    env.credits_stream = None  # the engines' banners stay off stdout
    env.error_used_name = False
    return shortcuts, PDDLReader


@contextmanager
def _scratch_folder() -> Iterator[None]:
    """Run in a fresh temporary folder: Fast Downward's driver writes its intermediate
    ``output.sas`` into the working directory, where two planners at once (parallel tests,
    two commands in one folder) would read each other's, and a user's folder would get it."""
    old = os.getcwd()
    with tempfile.TemporaryDirectory(prefix="oacdsl-plan-") as folder:
        os.chdir(folder)
        try:
            yield
        finally:
            os.chdir(old)


def _problem(task: Task) -> Any:
    _, reader = _up()
    try:
        return reader().parse_problem_string(domain_text(task), problem_text(task))
    except Exception as error:  # the reader's own exceptions have no common root
        raise PlanningError(f"unified-planning could not read the task: {error}") from None


#: Fast Downward's optimal search: A* without a heuristic. ``x <-> nothing`` as a condition
#: is a universal condition, which Fast Downward's translator turns into axioms, and its
#: admissible heuristics (LM-cut, …) refuse axioms; the tasks that need optimality are small.
OPTIMAL_SEARCH = "astar(blind())"


def _engine(engine: str, task: Task, optimal: bool) -> tuple[str, dict[str, str]]:
    """The unified-planning engine's name and parameters."""
    if engine == "fast-downward":
        if optimal or task.costs:
            return "fast-downward", {"fast_downward_search_config": OPTIMAL_SEARCH}
        return "fast-downward", {}
    if engine == "pyperplan":
        return ("pyperplan-opt" if optimal else "pyperplan"), {}
    raise PlanningError(f"unknown engine {engine!r} (choose {', '.join(ENGINES)})")


def _compiled(problem: Any, engine: str) -> tuple[Any, Any]:
    """The problem grounded for pyperplan, and the function mapping its actions back."""
    shortcuts, _ = _up()
    if engine != "pyperplan":
        return problem, None
    from unified_planning.engines import CompilationKind

    kinds = [
        CompilationKind.GROUNDING,
        CompilationKind.QUANTIFIERS_REMOVING,
        CompilationKind.NEGATIVE_CONDITIONS_REMOVING,
    ]
    backs = []
    for kind in kinds:
        with shortcuts.Compiler(problem_kind=problem.kind, compilation_kind=kind) as compiler:
            result = compiler.compile(problem, kind)
        problem = result.problem
        backs.append(result.map_back_action_instance)

    def back(instance: Any) -> Any:
        for step in reversed(backs):
            instance = step(instance)
        return instance

    return problem, back


def _via_up(task: Task, engine: str, optimal: bool) -> list[tuple[str, list[str]]] | None:
    """Plan ``task`` through unified-planning (pyperplan): (PDDL action, PDDL arguments) per step."""
    shortcuts, _ = _up()
    from unified_planning.engines import PlanGenerationResultStatus as Status

    name, params = _engine(engine, task, optimal)
    problem = _problem(task)
    try:
        compiled, back = _compiled(problem, engine)
        with _scratch_folder(), redirect_stdout(io.StringIO()):
            with shortcuts.OneshotPlanner(name=name, params=params) as planner:
                result = planner.solve(compiled)
    except PlanningError:
        raise
    except Exception as error:
        first = (str(error).strip().splitlines() or [type(error).__name__])[0]
        raise PlanningError(f"{engine} failed: {first}") from None
    if result.status in (Status.UNSOLVABLE_PROVEN, Status.UNSOLVABLE_INCOMPLETELY):
        return None
    if result.plan is None:
        raise PlanningError(f"{engine} gave no plan and no proof that none exists ({result.status.name})")
    steps = []
    for instance in result.plan.actions:
        if back is not None:
            instance = back(instance)
        steps.append((instance.action.name, [str(p.object().name) for p in instance.actual_parameters]))
    return steps


def _solve(task: Task, engine: str, optimal: bool) -> list[PlannedStep] | None:
    if engine == "fast-downward":
        raw = downward.run(task, OPTIMAL_SEARCH if optimal or task.costs else None)
    else:
        raw = _via_up(task, engine, optimal)
    if raw is None:
        return None
    actions = {a.name: a for a in task.actions}
    names = task.original()
    steps: list[PlannedStep] = []
    for action_name, args in raw:
        action = actions[action_name]
        values = iter(names[arg] for arg in args)
        fixed = dict(action.fixed)
        binding = {p.name: fixed[p.name] if p.name in fixed else next(values) for p in action.oac.params}
        steps.append(PlannedStep(action.oac.name, binding, action.name))
    return steps


def solve(task: Task, engine: str = "fast-downward", *, optimal: bool = False) -> list[PlannedStep] | None:
    """A plan for ``task`` (its steps, in order), or None when the engine proves there is none.
    A satisficing plan is looked for in the sub-task first (:mod:`oacdsl.planning.subtask`: the
    goal's instances and a few spares), then, when that has none, in the whole task."""
    if engine not in ENGINES:
        raise PlanningError(f"unknown engine {engine!r} (choose {', '.join(ENGINES)})")
    if not optimal and not task.costs:
        part = sub_task(task)
        if part is not None:
            steps = _solve(part, engine, optimal)
            if steps is not None:
                return steps
    return _solve(task, engine, optimal)
