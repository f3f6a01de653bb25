"""Validation passes over OACs: parameters, relations, skills and steps.

A name in a relation or a step argument is a parameter of the OAC or, failing
that, an instance of one of the library's scenes (a composed OAC may name the
demonstration's objects directly). Environment instances take part in no
relation and may not be named.
"""

from __future__ import annotations

from oacdsl.compiler.check_skills import check_skill_call, check_step_params
from oacdsl.compiler.context import Context
from oacdsl.compiler.diagnostics import Note
from oacdsl.compiler.grammar import keywords
from oacdsl.errors import did_you_mean
from oacdsl.model import Atom, Call, Node, Oac, Param, atom_text
from oacdsl.skills import SKILLS
from oacdsl.world import NOTHING

__all__ = ["check_oacs"]


class _OacChecker:
    def __init__(self, ctx: Context, oac: Oac) -> None:
        self.ctx = ctx
        self.oac = oac
        self.params: dict[str, Param] = {}
        self.used: set[str] = set()

    # -- names -----------------------------------------------------------
    def resolve(self, name: str, node: Node, key: str) -> list[frozenset[str]] | None:
        """The class sets ``name`` (at ``node.part(key)``) may have, one per binding; None after reporting."""
        self.used.add(name)
        param = self.params.get(name)
        if param is not None:
            return [self.ctx.library.ancestors(param.cls)]
        entries = self.ctx.instances.get(name)
        if entries:
            env = [(scene.name, inst) for scene, inst in entries if inst.environment or inst.ignored]
            if env and len(env) == len(entries):
                what = "environment" if env[0][1].environment else "ignored"
                self.ctx.add(
                    "E021",
                    f"'{name}' is {what} in scene '{env[0][0]}': it takes part in no "
                    "relation and cannot be named in an OAC",
                    node.part(key),
                    Note("declared here", entries[0][1].part("name")),
                )
                return None
            return self.ctx.instance_classes(name)
        valid = [
            *self.params,
            *(n for n, e in self.ctx.instances.items() if not all(i.environment or i.ignored for _, i in e)),
        ]
        self.ctx.add(
            "E005",
            f"unbound variable '{name}': not a parameter of '{self.oac.name}' nor an "
            f"instance of a scene{did_you_mean(name, valid)}",
            node.part(key),
        )
        return None

    def check_params(self) -> None:
        for param in self.oac.params:
            if param.name in self.params:
                self.ctx.add(
                    "E006",
                    f"parameter '{param.name}' is defined twice in '{self.oac.name}'",
                    param.part("name"),
                    Note("first defined here", self.params[param.name].part("name")),
                )
                continue
            self.params[param.name] = param
            if param.name in keywords():
                self.ctx.add(
                    "E018",
                    f"'{param.name}' is a reserved word and cannot name a parameter",
                    param.part("name"),
                )
            known = self.ctx.class_ok(param.cls, param, "cls")
            if param.default is not None:
                self.check_default(param, known)

    def check_default(self, param: Param, known_class: bool) -> None:
        default = param.default or ""
        span = param.part("default")
        if default not in self.ctx.instances:
            self.ctx.add(
                "E004", f"unknown instance '{default}'{did_you_mean(default, self.ctx.instances)}", span
            )
            return
        if not known_class:
            return
        if not any(param.cls in classes for classes in self.ctx.instance_classes(default)):
            scene, inst = self.ctx.instances[default][0]
            self.ctx.add(
                "E017",
                f"'{default}' is a {', '.join(inst.classes)}, not a {param.cls}: it cannot be "
                f"the default of '{param.name}: {param.cls}'",
                span,
                Note(f"'{default}' is declared in scene '{scene.name}' here", inst.part("name")),
            )

    # -- relations -------------------------------------------------------
    def check_atom(self, atom: Atom) -> None:
        if atom.left == atom.right:
            self.ctx.add(
                "E008",
                f"'{atom_text(atom)}' relates '{atom.left}' with itself: "
                "a relation needs two different objects",
                atom.span,
            )
            return
        for side in ("left", "right"):
            name = getattr(atom, side)
            if name != NOTHING:
                self.resolve(name, atom, side)

    def contradictions(self, atoms: tuple[Atom, ...], code: str, what: str) -> None:
        positive = {(a.left, a.right): a for a in atoms if not a.negated}
        for atom in atoms:
            other: Atom | None = None
            if atom.negated:
                other = positive.get((atom.left, atom.right))
            elif atom.right == NOTHING:
                other = next(
                    (
                        a
                        for a in positive.values()
                        if atom.left in (a.left, a.right) and a.right != NOTHING and a.left != a.right
                    ),
                    None,
                )
            if other is not None:
                self.ctx.add(
                    code,
                    f"{what} contradicts itself: '{atom_text(atom)}' and '{atom_text(other)}' "
                    "cannot both hold",
                    atom.span,
                    Note(f"'{atom_text(other)}' is stated here", other.span),
                )

    def check_effect(self) -> None:
        oac = self.oac
        if not oac.effect:
            if oac.steps:  # composed: its steps change the world, even if it ends as it began
                return
            self.ctx.add(
                "E011",
                f"OAC '{oac.name}' states no effect: write what it changes ('effect a <-> b, not c <-> d')",
                oac.part("name"),
            )
            return
        pre = set(oac.pre)
        already = [a for a in oac.effect if a in pre]
        if len(already) == len(oac.effect):
            self.ctx.add(
                "E012",
                f"the effect of '{oac.name}' changes nothing: every effect is also a precondition"
                + ("; a composed OAC that ends as it began states no effect (leave 'effect' out)"
                   if oac.composed else ""),
                oac.part("effect"),
                Note("preconditions stated here", oac.part("pre")),
            )
            return
        for atom in already:
            self.ctx.add(
                "W003",
                f"effect '{atom_text(atom)}' already holds before: it is also a precondition",
                atom.span,
            )

    # -- execution -------------------------------------------------------
    def check_skill(self) -> None:
        skill = self.oac.skill
        if skill is not None and skill not in SKILLS:
            self.ctx.add(
                "E016",
                f"unknown skill '{skill}'{did_you_mean(skill, SKILLS)}",
                self.oac.part("skill"),
                Note("the runtime provides " + ", ".join(sorted(SKILLS)) + " (see 'oacc skills')"),
            )
            for i, arg in enumerate(self.oac.skill_args or ()):
                self.resolve(arg, self.oac, f"skill_args.{i}")
            return
        if skill is not None:
            check_skill_call(self.ctx, self.oac, self.resolve, self.declared)

    def declared(self, name: str) -> str:
        """The class ``name`` is declared with (a parameter's, else an instance's), for messages."""
        if name in self.params:
            return self.params[name].cls
        return "/".join(sorted(self.ctx.instances[name][0][1].classes))

    def check_call(self, call: Call) -> None:
        callee = self.ctx.library.oacs.get(call.oac)
        if callee is None:
            hint = did_you_mean(call.oac, self.ctx.library.oacs)
            self.ctx.add("E013", f"unknown OAC '{call.oac}'{hint}", call.part("oac"))
            for i, arg in enumerate(call.args):
                self.resolve(arg, call, f"args.{i}")
            return

        def defined() -> Note:
            signature = ", ".join(f"{p.name}: {p.cls}" for p in callee.params)
            return Note(f"'{callee.name}({signature})' is defined here", callee.part("name"))

        if len(call.args) != len(callee.params):
            self.ctx.add(
                "E014",
                f"'{call.oac}' takes {len(callee.params)} argument"
                f"{'s' if len(callee.params) != 1 else ''}, {len(call.args)} given",
                call.span,
                defined(),
            )
        for i, (arg, param) in enumerate(zip(call.args, callee.params, strict=False)):
            kinds = self.resolve(arg, call, f"args.{i}")
            if kinds is None or param.cls not in self.ctx.library.classes:
                continue
            if not any(param.cls in classes for classes in kinds):
                declared = self.declared(arg)
                self.ctx.add(
                    "E015",
                    f"argument '{arg}' is a {declared}, but '{call.oac}' expects a "
                    f"{param.cls} for '{param.name}'",
                    call.part(f"args.{i}"),
                    defined(),
                )
        for i in range(len(callee.params), len(call.args)):
            self.resolve(call.args[i], call, f"args.{i}")
        check_step_params(self.ctx, call, callee)

    def run(self) -> None:
        oac = self.oac
        self.check_params()
        for atom in (*oac.pre, *oac.effect):
            self.check_atom(atom)
        self.contradictions(oac.pre, "E009", "the precondition")
        self.contradictions(oac.effect, "E010", "the effect")
        self.check_effect()
        if oac.steps is not None:
            if not oac.steps:
                self.ctx.add(
                    "E023",
                    f"composed OAC '{oac.name}' has no steps: call at least one OAC",
                    oac.part("steps"),
                )
            for call in oac.steps:
                self.check_call(call)
        else:
            self.check_skill()
        for name, param in self.params.items():
            if name not in self.used:
                self.ctx.add("W001", f"parameter '{name}' of '{oac.name}' is never used", param.part("name"))


def _recursion(ctx: Context) -> None:
    """E019 for composed OACs that reach themselves through their steps."""
    oacs = ctx.library.oacs
    calls = {n: sorted({c.oac for c in o.steps or () if c.oac in oacs}) for n, o in oacs.items()}
    reported: set[frozenset[str]] = set()
    for start in sorted(calls):
        # breadth-first: the shortest chain of calls leading back to start
        came: dict[str, str] = {}
        frontier = [start]
        path: list[str] | None = None
        while frontier and path is None:
            nxt_frontier = []
            for node in frontier:
                for nxt in calls[node]:
                    if nxt == start:
                        path = [node]
                        while path[-1] != start:
                            path.append(came[path[-1]])
                        path = [start, *reversed(path[:-1]), start] if node != start else [start, start]
                        break
                    if nxt not in came:
                        came[nxt] = node
                        nxt_frontier.append(nxt)
                if path is not None:
                    break
            frontier = nxt_frontier
        if path is not None and frozenset(path) not in reported:
            reported.add(frozenset(path))
            ctx.add(
                "E019", f"composed OAC '{start}' calls itself: " + " → ".join(path), oacs[start].part("name")
            )


def check_oacs(ctx: Context) -> None:
    oacs = [d for m in ctx.modules for d in m.decls if isinstance(d, Oac)]
    seen: dict[str, Oac] = {}
    for oac in oacs:
        if oac.name in seen:
            ctx.add(
                "E006",
                f"OAC '{oac.name}' is defined twice",
                oac.part("name"),
                Note("first defined here", seen[oac.name].part("name")),
            )
            continue
        seen[oac.name] = oac
        _OacChecker(ctx, oac).run()
    _recursion(ctx)
