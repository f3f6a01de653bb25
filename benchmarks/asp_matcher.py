"""A reference matcher in answer-set programming (clingo): the same rules, declaratively.

Used by the differential tests and ``benchmarks/matching.py`` to check the
indexed matcher (:mod:`oacdsl.matching.matcher`) against an independent
implementation; clingo is a test extra, imported only here. All sub-actions
are encoded at once and ground once.

Facts (names as integers): ``inst(I)``, ``cls(I, C)`` (every class of I,
inherited included), ``st(T, X, Y)`` (X touches Y in world state T, both
orders; each distinct state once) and ``sub(S, Tb, Ta)`` (sub-action S goes
from state Tb to state Ta). Each OAC k becomes a rule whose body is its atoms,
its typed variables and pairwise different variables. In strict mode a
candidate is generated from a changed relation one of its effects accounts for
and dropped when another changed relation is not accounted for, or when an
instance its effects name takes part in no change. The answer
holds ``m(k, S, (V1, …, Vn))``.
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

from oacdsl.matching.results import Mode
from oacdsl.model import Oac
from oacdsl.world import NOTHING, WorldState

__all__ = ["AspTimes", "asp_matches", "encode"]


class _Ids:
    """Instance and class names as small integers (shorter facts, faster grounding)."""

    def __init__(self) -> None:
        self.ids: dict[str, int] = {}

    def __call__(self, name: str) -> int:
        return self.ids.setdefault(name, len(self.ids))

    def names(self) -> dict[int, str]:
        return {v: k for k, v in self.ids.items()}


def _oac_rules(k: int, oac: Oac, mode: Mode, iid: _Ids, cid: _Ids) -> list[str]:
    params = [p.name for p in oac.params]
    var = {p: f"V{i}" for i, p in enumerate(params)}

    def term(name: str) -> str:
        return var.get(name, str(iid(name)))

    # Relations first (effects, then preconditions), then classes, then the rest:
    # the order in which the grounder best joins.
    joins: list[str] = []
    rest: list[str] = []
    for state, atoms in (("Ta", oac.effect), ("Tb", oac.pre)):
        for atom in atoms:
            x = term(atom.left)
            if atom.about_nothing:
                lit = f"{'' if atom.negated else 'not '}touch({state}, {x})"
                (joins if atom.negated else rest).append(lit)
            elif atom.left == atom.right:
                if not atom.negated:
                    return []  # never holds
            elif atom.negated:
                rest.append(f"not st({state}, {x}, {term(atom.right)})")
            else:
                joins.append(f"st({state}, {x}, {term(atom.right)})")
    names = {n for a in (*oac.pre, *oac.effect) for n in (a.left, a.right)}
    constants = sorted(names - set(params) - {NOTHING})
    terms = [var[p] for p in params] + [term(c) for c in constants]
    body = ["sub(S, Tb, Ta)", *joins] + [f"cls({var[p.name]}, {cid(p.cls)})" for p in oac.params]
    body += [f"inst({term(c)})" for c in constants] + rest
    body += [f"{x} != {y}" for i, x in enumerate(terms) for y in terms[i + 1 :]]
    vs = "(" + ", ".join(var[p] for p in params) + ("," if len(params) == 1 else "") + ")"
    if mode == "paper":
        return [f"m({k}, S, {vs}) :- {', '.join(body)}."]
    # Strict: a candidate must account for some changed relation, so it is generated from one
    # (an added relation by a positive effect, a removed one by 'not a <-> b' or 'x <-> nothing').
    drivers = []
    for atom in oac.effect:
        if atom.about_nothing and not atom.negated:
            drivers.append(f"rem(S, {term(atom.left)}, _)")
        elif not atom.about_nothing and atom.left != atom.right:
            drivers.append(f"{'rem' if atom.negated else 'add'}(S, {term(atom.left)}, {term(atom.right)})")
    rules = [f"c{k}(S, {vs}) :- {d}, {', '.join(body)}." for d in drivers]
    for atom in oac.effect:
        if atom.about_nothing or atom.left == atom.right:
            continue
        x, y = term(atom.left), term(atom.right)
        pred = "rem" if atom.negated else "add"
        rules.append(f"cov{k}(S, {vs}, {pred}, {x}, {y}) :- c{k}(S, {vs}).")
        rules.append(f"cov{k}(S, {vs}, {pred}, {y}, {x}) :- c{k}(S, {vs}).")
    cleared = [term(a.left) for a in oac.effect if a.about_nothing and not a.negated]
    keep = "".join(f", A != {x}, B != {x}" for x in cleared)
    head = f"u{k}(S, {vs}) :- c{k}(S, {vs})"
    rules.append(f"{head}, add(S, A, B), A < B, not cov{k}(S, {vs}, add, A, B).")
    rules.append(f"{head}, rem(S, A, B), A < B, not cov{k}(S, {vs}, rem, A, B){keep}.")
    # Every instance an effect names takes part in a change.
    for x in sorted({term(n) for a in oac.effect for n in (a.left, a.right) if n != NOTHING}):
        rules.append(f"{head}, not chg(S, {x}).")
    rules.append(f"m({k}, S, {vs}) :- c{k}(S, {vs}), not u{k}(S, {vs}).")
    return rules


_COMMON = """
touch(T, X) :- st(T, X, _).
add(S, X, Y) :- sub(S, Tb, Ta), st(Ta, X, Y), not st(Tb, X, Y).
rem(S, X, Y) :- sub(S, Tb, Ta), st(Tb, X, Y), not st(Ta, X, Y).
chg(S, X) :- add(S, X, _).
chg(S, X) :- rem(S, X, _).
#show m/3.
"""


def encode(
    oacs: Sequence[Oac],
    instance_classes: Mapping[str, Iterable[str]],
    sub_actions: Sequence[tuple[WorldState, WorldState]],
    mode: Mode,
) -> tuple[str, dict[int, str]]:
    """The program (rules and facts) and the instance names of the integer ids.

    Facts: ``inst(I)``, ``cls(I, C)``, ``st(T, X, Y)`` for every distinct world state T
    (both orders), ``sub(S, Tb, Ta)`` for sub-action S from state Tb to state Ta.
    """
    iid, cid = _Ids(), _Ids()
    for inst in instance_classes:
        iid(inst)
    rules = [r for k, oac in enumerate(oacs) for r in _oac_rules(k, oac, mode, iid, cid)]
    out = [_COMMON, *rules]
    for inst, classes in instance_classes.items():
        i = iid(inst)
        out.append(f"inst({i}).")
        out.extend(f"cls({i}, {cid(c)})." for c in classes)
    state_ids: dict[WorldState, int] = {}
    for s, pair in enumerate(sub_actions):
        ts = []
        for state in pair:
            t = state_ids.get(state)
            if t is None:
                t = state_ids[state] = len(state_ids)
                for x, y in state.relations:
                    a, b = iid(x), iid(y)
                    out.append(f"st({t}, {a}, {b}). st({t}, {b}, {a}).")
            ts.append(t)
        out.append(f"sub({s}, {ts[0]}, {ts[1]}).")
    return "\n".join(out) + "\n", iid.names()


@dataclass
class AspTimes:
    """Seconds spent: conversion (writing the program text, clingo reading it), grounding,
    solving (with reading the model)."""

    convert_s: float = 0.0
    ground_s: float = 0.0
    solve_s: float = 0.0
    extra: dict[str, float] = field(default_factory=dict)

    @property
    def total_s(self) -> float:
        return self.convert_s + self.ground_s + self.solve_s


def asp_matches(
    oacs: Sequence[Oac],
    instance_classes: Mapping[str, Iterable[str]],
    sub_actions: Sequence[tuple[WorldState, WorldState]],
    mode: Mode = "strict",
    times: AspTimes | None = None,
) -> set[tuple[int, int, tuple[str, ...]]]:
    """Every (OAC index, sub-action index, binding of the parameters in order), by clingo."""
    import clingo

    times = times if times is not None else AspTimes()
    t0 = time.perf_counter()
    program, names = encode(oacs, instance_classes, sub_actions, mode)
    ctl = clingo.Control(["--warn=none"])
    ctl.add("base", [], program)
    t1 = time.perf_counter()
    ctl.ground([("base", [])])
    t2 = time.perf_counter()
    found: set[tuple[int, int, tuple[str, ...]]] = set()

    def on_model(model: clingo.Model) -> None:
        for sym in model.symbols(shown=True):
            k, s, vs = sym.arguments
            found.add((k.number, s.number, tuple(names[v.number] for v in vs.arguments)))

    ctl.solve(on_model=on_model)
    t3 = time.perf_counter()
    times.convert_s += t1 - t0
    times.ground_s += t2 - t1
    times.solve_s += t3 - t2
    return found
