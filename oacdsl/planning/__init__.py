"""The library as a planning domain: OACs as actions, a scene's world state as a problem.

:mod:`~oacdsl.planning.task` and :mod:`~oacdsl.planning.pddl` write the task as PDDL (``oacc
pddl``); :mod:`~oacdsl.planning.engines` plans it with Fast Downward or pyperplan through
unified-planning (``oacc plan``, the ``plan`` extra); :mod:`~oacdsl.planning.replay` checks a
plan by the matcher's semantics; :mod:`~oacdsl.planning.explain` says why a goal has no plan.
"""

from oacdsl.planning.engines import ENGINES, PlannedStep, solve
from oacdsl.planning.pddl import domain_text, problem_text
from oacdsl.planning.planner import PlanResult, goal_task, plan_goal
from oacdsl.planning.replay import replay
from oacdsl.planning.state import parse_atoms, scene_state, stated
from oacdsl.planning.task import Action, Task, make_task, primitive_actions

__all__ = [
    "ENGINES",
    "Action",
    "PlanResult",
    "PlannedStep",
    "Task",
    "domain_text",
    "goal_task",
    "make_task",
    "parse_atoms",
    "plan_goal",
    "primitive_actions",
    "problem_text",
    "replay",
    "scene_state",
    "solve",
    "stated",
]
