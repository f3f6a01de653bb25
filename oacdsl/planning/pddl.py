"""A :class:`~oacdsl.planning.task.Task` written as PDDL text: ``domain.pddl`` and ``problem.pddl``.

Deterministic: predicates, actions, objects and facts are sorted, so the same library and
state give the same bytes. The encoding is described in :mod:`oacdsl.planning.task`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

from oacdsl.errors import PlanningError
from oacdsl.model import Atom
from oacdsl.planning.task import Action, Task, pddl_name

__all__ = ["domain_text", "problem_text", "DOMAIN"]

#: The domain's name in both files.
DOMAIN = "oacs"
_TYPE = "instance"
_REQUIREMENTS = (
    ":typing :negative-preconditions :equality :existential-preconditions"
    " :universal-preconditions :conditional-effects :disjunctive-preconditions"
)


def _touch(a: str, b: str, negated: bool = False) -> str:
    return f"(not (touching {a} {b}))" if negated else f"(touching {a} {b})"


def _condition(atom: Atom, term: Callable[[str], str], var: str = "?other") -> list[str]:
    """The PDDL condition(s) of a bound or unbound atom (``term`` gives a name's PDDL term)."""
    x = term(atom.left)
    if atom.about_nothing:
        if atom.negated:
            return [f"(exists ({var} - {_TYPE}) (touching {x} {var}))"]
        return [f"(forall ({var} - {_TYPE}) (not (touching {x} {var})))"]
    y = term(atom.right)
    if x == y:
        return [] if atom.negated else [f"(not (= {x} {x}))"]  # nothing touches itself
    return [_touch(x, y, atom.negated)]


def _effect(atom: Atom, term: Callable[[str], str]) -> list[str]:
    x = term(atom.left)
    if atom.about_nothing:
        if atom.negated:
            return []  # a statement about the result, no update (as the matcher)
        return [f"(forall (?other - {_TYPE}) (and {_touch(x, '?other', True)} {_touch('?other', x, True)}))"]
    y = term(atom.right)
    if x == y:
        raise PlanningError(f"an effect makes {atom.left} touch itself")
    return [_touch(x, y, atom.negated), _touch(y, x, atom.negated)]


def _and(parts: Iterable[str], indent: str) -> str:
    items = list(parts)
    if not items:
        return "(and)"
    inner = f"\n{indent}    ".join(items)
    return f"(and\n{indent}    {inner})"


def _action(task: Task, action: Action) -> str:
    fixed = dict(action.fixed)
    variables = {name: "?" + pddl_name(name) for name, _ in action.free()}
    if len(set(variables.values())) != len(variables):
        raise PlanningError(f"oac {action.oac.name}: two parameters are one name in PDDL (case is ignored)")

    def term(name: str) -> str:
        if name in fixed:
            return task.pddl(fixed[name])
        if name in variables:
            return variables[name]
        if name in task.pddl_names:
            return task.pddl(name)
        raise PlanningError(f"oac {action.oac.name} names {name!r}, neither a parameter nor an instance")

    pre = [f"({task.class_names[cls]} {variables[name]})" for name, cls in action.free()]
    terms = [term(p.name) for p in action.oac.params]
    pre += [f"(not (= {a} {b}))" for i, a in enumerate(terms) for b in terms[i + 1 :]
            if a.startswith("?") or b.startswith("?")]
    for binding in action.banned:
        pre.append("(not (and " + " ".join(f"(= {term(p)} {task.pddl(i)})" for p, i in binding) + "))")
    for atom in action.oac.pre:
        pre += _condition(atom, term)
    eff: list[str] = []
    for atom in action.oac.effect:
        eff += _effect(atom, term)
    if task.costs:
        eff.append(f"(increase (total-cost) {action.cost})")
    params = " ".join(f"{v} - {_TYPE}" for v in variables.values())
    return (
        f"  (:action {action.name}\n"
        f"    :parameters ({params})\n"
        f"    :precondition {_and(pre, '    ')}\n"
        f"    :effect {_and(eff, '    ')})"
    )


def _constants(task: Task) -> list[str]:
    named = {i for a in task.actions for _, i in a.fixed}
    named |= {i for a in task.actions for binding in a.banned for _, i in binding}
    return sorted(task.pddl(i) for i in named)


def domain_text(task: Task) -> str:
    """``domain.pddl``: the predicates (touching, one per class) and one action per OAC."""
    requirements = _REQUIREMENTS + (" :action-costs" if task.costs else "")
    preds = ["(touching ?a - instance ?b - instance)"]
    preds += [f"({p} ?x - {_TYPE})" for p in sorted(task.class_names.values())]
    lines = [
        f"(define (domain {DOMAIN})",
        f"  (:requirements {requirements})",
        f"  (:types {_TYPE})",
    ]
    constants = _constants(task)
    if constants:
        lines.append(f"  (:constants {' '.join(constants)} - {_TYPE})")
    lines.append("  (:predicates\n    " + "\n    ".join(preds) + ")")
    if task.costs:
        lines.append("  (:functions (total-cost) - number)")
    lines += [_action(task, a) for a in sorted(task.actions, key=lambda a: a.name)]
    return "\n".join(lines) + ")\n"


def _goal(task: Task) -> list[str]:
    out: list[str] = []
    for index, atom in enumerate(task.goal):
        out += _condition(atom, task.pddl, f"?other{index}")
    return out


def problem_text(task: Task) -> str:
    """``problem.pddl``: the instances, their classes and relations, the goal."""
    constants = set(_constants(task))
    objects = sorted(task.pddl(i) for i in task.classes if task.pddl(i) not in constants)
    facts = sorted(
        f"({task.class_names[c]} {task.pddl(i)})"
        for i, classes in task.classes.items()
        for c in classes
        if c in task.class_names
    )
    touching = set()
    for a, b in task.init.relations:
        touching |= {_touch(task.pddl(a), task.pddl(b)), _touch(task.pddl(b), task.pddl(a))}
    facts += sorted(touching)
    if task.costs:
        facts.append("(= (total-cost) 0)")
    name = pddl_name(task.name)
    lines = [
        f"(define (problem {name})",
        f"  (:domain {DOMAIN})",
        f"  (:objects {' '.join(objects)} - {_TYPE})" if objects else "  (:objects)",
        "  (:init\n    " + "\n    ".join(facts) + ")",
        f"  (:goal {_and(_goal(task), '  ')})",
    ]
    if task.costs:
        lines.append("  (:metric minimize (total-cost))")
    return "\n".join(lines) + ")\n"
