"""A task over part of its instances: the goal's, what touches them, a few spares of each class.

A planner grounds every action over every instance its parameters' classes admit: in a
50-instance scene ``pour(h, c, l, b)`` alone has some 16 000 groundings, of which a goal
about three liquids needs a handful. :func:`sub_task` keeps

* the instances the goal names (and those an action fixes or bans);
* :data:`SPARES` instances of each class an action's parameter asks for (the goal's count;
  instances that touch nothing at the start come first, then by name);
* every instance touching a kept one at the start, and so on (the liquid in a kept cup, the
  cup in a kept hand).

A plan of the sub-task is a plan of the whole task: no relation joins a kept instance and a
left-out one at the start, no action of the plan names a left-out one, so each condition —
``h <-> nothing`` included — is as true in the whole state as in the part, and so is the
goal. The sub-task may miss a plan that needs more instances (a third spare cup): the caller
then plans the whole task (:func:`oacdsl.planning.engines.solve`), so nothing is lost but
time. It may also miss a shorter plan, so it is used for satisficing planning only.
"""

from __future__ import annotations

from oacdsl.planning.task import Task, make_task
from oacdsl.world import NOTHING, WorldState

__all__ = ["SPARES", "sub_task"]

#: Instances of each class a parameter asks for that the sub-task keeps at least.
SPARES = 2


def _closure(kept: set[str], state: WorldState) -> set[str]:
    """``kept`` with every instance connected to one of it by the state's relations."""
    out, todo = set(kept), list(kept)
    while todo:
        for other in state.partners(todo.pop()):
            if other not in out:
                out.add(other)
                todo.append(other)
    return out


def sub_task(task: Task, spares: int = SPARES) -> Task | None:
    """The task over the instances the module docstring lists; None when that is all of them."""
    named = {n for a in task.goal for n in (a.left, a.right) if n != NOTHING}
    named |= {i for a in task.actions for _, i in a.fixed}
    named |= {i for a in task.actions for binding in a.banned for _, i in binding}
    kept = _closure(named & set(task.classes), task.init)
    wanted = sorted({cls for a in task.actions for _, cls in a.free()})
    order = sorted(task.classes, key=lambda i: (not task.init.touches_nothing(i), i))
    for cls in wanted:
        have = sum(1 for i in kept if cls in task.classes[i])
        for name in order:
            if have >= spares:
                break
            if name not in kept and cls in task.classes[name]:
                kept = _closure(kept | {name}, task.init)
                have = sum(1 for i in kept if cls in task.classes[i])
    if len(kept) == len(task.classes):
        return None
    classes = {i: c for i, c in task.classes.items() if i in kept}
    init = WorldState.of(kept, [(a, b) for a, b in task.init.relations if a in kept and b in kept])
    return make_task(task.name, task.actions, classes, init, task.goal, costs=task.costs)
