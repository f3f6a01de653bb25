"""Validation passes over the modules of a library: names, classes, scenes, grasps.

Every pass appends :class:`~oacdsl.compiler.diagnostics.Diagnostic` objects and
never stops at the first problem. The checks of OACs live in
:mod:`oacdsl.compiler.check_oacs`; :func:`check_modules` runs all of them.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

from oacdsl.compiler.diagnostics import Diagnostic, Note
from oacdsl.errors import did_you_mean
from oacdsl.library import Library
from oacdsl.model import APPROACHES, GRASP_TYPES, Grasp, Instance, Module, Node, Oac, ObjectClass, Scene, Span

__all__ = ["KEYWORDS", "Context", "check_modules"]

#: Words of the language; parameters and instances may not be called so (E018).
KEYWORDS = frozenset(
    {
        "approach",
        "class",
        "effect",
        "environment",
        "execute",
        "grasp",
        "markers",
        "not",
        "nothing",
        "oac",
        "offset",
        "pre",
        "scene",
        "steps",
        "type",
    }
)

#: Grasp offsets longer than this (metres) are probably millimetres by mistake (W005).
MAX_OFFSET_M = 0.5


@dataclass
class Context:
    """The definitions of all modules, first definition of each name winning."""

    modules: Sequence[Module]
    library: Library = field(init=False)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    #: instance name → every (scene, instance) that declares it.
    instances: dict[str, list[tuple[Scene, Instance]]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.library = Library(self.modules)
        for scene in self.library.scenes.values():
            for inst in scene.instances:
                self.instances.setdefault(inst.name, []).append((scene, inst))

    def add(self, code: str, message: str, span: Span | None, *notes: Note) -> None:
        self.diagnostics.append(Diagnostic(code, message, span, tuple(notes)))

    def unknown_class(self, name: str, span: Span | None, what: str = "class") -> None:
        """E003 with "did you mean" and where the suggestion is defined."""
        classes = self.library.classes
        hint = did_you_mean(name, classes)
        notes = []
        close = _suggested(hint)
        if close in classes:
            notes.append(Note(f"class '{close}' is defined here", classes[close].part("name")))
        self.add("E003", f"unknown {what} '{name}'{hint}", span, *notes)

    def class_ok(self, name: str, node: Node, key: str, what: str = "class") -> bool:
        """True when class ``name`` exists; else E003 at ``node.part(key)``."""
        if name in self.library.classes:
            return True
        self.unknown_class(name, node.part(key), what)
        return False

    def instance_classes(self, name: str) -> list[frozenset[str]]:
        """For each scene that declares ``name``: all its classes, inherited included."""
        out = []
        for _, inst in self.instances.get(name, []):
            found: set[str] = set()
            for cls in inst.classes:
                found |= self.library.ancestors(cls)
            out.append(frozenset(found))
        return out


def _suggested(hint: str) -> str | None:
    marker = "did you mean '"
    if marker in hint:
        return hint.split(marker, 1)[1].split("'", 1)[0]
    return None


def _duplicates(
    ctx: Context, kind: str, items: Iterable[tuple[str, ObjectClass | Scene | Grasp | Oac]], key: str = "name"
) -> None:
    seen: dict[str, Span | None] = {}
    for name, node in items:
        if name in seen:
            ctx.add(
                "E006",
                f"{kind} '{name}' is defined twice",
                node.part(key),
                Note("first defined here", seen[name]),
            )
        else:
            seen[name] = node.part(key)


def _decls(ctx: Context) -> list[ObjectClass | Scene | Grasp | Oac]:
    return [d for m in ctx.modules for d in m.decls]


def check_classes(ctx: Context) -> None:
    decls = [d for d in _decls(ctx) if isinstance(d, ObjectClass)]
    _duplicates(ctx, "class", ((d.name, d) for d in decls))
    for decl in decls:
        for parent in decl.parents:
            ctx.class_ok(parent, decl, f"parents:{parent}", "parent class")
    _check_cycles(ctx)


def _check_cycles(ctx: Context) -> None:
    """E007 once per strongly connected component of the parent graph (Tarjan, iterative)."""
    classes = ctx.library.classes
    graph = {n: [p for p in c.parents if p in classes] for n, c in classes.items()}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    components: list[list[str]] = []
    for root in graph:
        if root in index:
            continue
        work = [(root, 0)]
        while work:
            node, i = work.pop()
            if i == 0:
                index[node] = low[node] = len(index)
                stack.append(node)
                on_stack.add(node)
            if i < len(graph[node]):
                work.append((node, i + 1))
                nxt = graph[node][i]
                if nxt not in index:
                    work.append((nxt, 0))
                elif nxt in on_stack:
                    low[node] = min(low[node], index[nxt])
                continue
            if low[node] == index[node]:
                comp = []
                while True:
                    top = stack.pop()
                    on_stack.discard(top)
                    comp.append(top)
                    if top == node:
                        break
                components.append(comp)
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[node])
    for comp in components:
        if len(comp) == 1 and comp[0] not in graph[comp[0]]:
            continue
        members = set(comp)
        start = min(comp, key=lambda n: _pos(classes[n].span))
        path = _cycle_path(start, graph, members)
        ctx.add(
            "E007",
            "cycle in the class hierarchy: " + " → ".join(path),
            classes[start].part("name"),
            *(Note(f"class '{n}' is defined here", classes[n].part("name")) for n in path[1:-1]),
        )


def _cycle_path(start: str, graph: dict[str, list[str]], members: set[str]) -> list[str]:
    """The shortest cycle through ``start`` inside one strongly connected component."""
    came: dict[str, str] = {}
    frontier = [start]
    while frontier:
        nxt_frontier = []
        for node in frontier:
            for nxt in sorted(graph[node]):
                if nxt not in members:
                    continue
                if nxt == start:
                    path = [node]
                    while path[-1] != start:
                        path.append(came[path[-1]])
                    return [start, *reversed(path[:-1]), start] if node != start else [start, start]
                if nxt not in came:
                    came[nxt] = node
                    nxt_frontier.append(nxt)
        frontier = nxt_frontier
    return [start, start]


def _pos(span: Span | None) -> tuple[str, int, int]:
    return (span.file, span.line, span.column) if span is not None else ("", 0, 0)


def check_scenes(ctx: Context) -> None:
    scenes = [d for d in _decls(ctx) if isinstance(d, Scene)]
    _duplicates(ctx, "scene", ((d.name, d) for d in scenes))
    graspable = "Graspable" in ctx.library.classes
    for scene in scenes:
        seen: dict[str, Instance] = {}
        marker_owner: dict[str, tuple[Instance, int]] = {}
        for inst in sorted(scene.instances, key=lambda i: _pos(i.span)):
            if inst.name in seen:
                ctx.add(
                    "E006",
                    f"instance '{inst.name}' is defined twice in scene '{scene.name}'",
                    inst.part("name"),
                    Note("first defined here", seen[inst.name].part("name")),
                )
            else:
                seen[inst.name] = inst
            if inst.name in KEYWORDS:
                ctx.add(
                    "E018", f"'{inst.name}' is a reserved word and cannot name an instance", inst.part("name")
                )
            known = True
            for cls in inst.classes:
                known = ctx.class_ok(cls, inst, f"classes:{cls}") and known
            for i, marker in enumerate(inst.markers):
                owner = marker_owner.get(marker)
                if owner is not None and owner[0] is not inst:
                    ctx.add(
                        "E022",
                        f"marker \"{marker}\" is assigned to '{owner[0].name}' and to '{inst.name}'",
                        inst.part(f"markers.{i}"),
                        Note(f"assigned to '{owner[0].name}' here", owner[0].part(f"markers.{owner[1]}")),
                    )
                elif owner is None:
                    marker_owner[marker] = (inst, i)
            if graspable and known and not inst.environment:
                classes = set().union(*(ctx.library.ancestors(c) for c in inst.classes))
                if "Graspable" in classes and ctx.library.grasp_for(classes) is None:
                    ctx.add(
                        "W004",
                        f"instance '{inst.name}' is Graspable but no grasp declaration covers "
                        f"its classes ({', '.join(inst.classes)}): the robot will not know how to grasp it",
                        inst.part("name"),
                    )


def check_grasps(ctx: Context) -> None:
    grasps = [d for d in _decls(ctx) if isinstance(d, Grasp)]
    _duplicates(ctx, "grasp for class", ((d.cls, d) for d in grasps), key="cls")
    for grasp in grasps:
        ctx.class_ok(grasp.cls, grasp, "cls")
        if grasp.type not in GRASP_TYPES:
            ctx.add(
                "E020",
                f"unknown grasp type '{grasp.type}'{did_you_mean(grasp.type, GRASP_TYPES)}",
                grasp.part("type"),
            )
        if grasp.approach not in APPROACHES:
            ctx.add(
                "E020",
                f"unknown approach direction '{grasp.approach}'{did_you_mean(grasp.approach, APPROACHES)}",
                grasp.part("approach"),
            )
        if not all(math.isfinite(x) for x in grasp.offset):  # e.g. 1e400 reads as infinity
            ctx.add(
                "E025",
                "grasp offset has a number too large to be finite; offsets are metres",
                grasp.part("offset"),
            )
            continue
        length = math.hypot(*grasp.offset)
        if length > MAX_OFFSET_M:
            ctx.add(
                "W005",
                f"grasp offset is {length:.3g} m from the object's origin; offsets are metres "
                "(millimetres by mistake?)",
                grasp.part("offset"),
            )


def check_modules(modules: Sequence[Module]) -> list[Diagnostic]:
    """Run every validation pass over ``modules`` (one library); return all diagnostics."""
    from oacdsl.compiler.check_oacs import check_oacs

    ctx = Context(modules)
    check_classes(ctx)
    check_scenes(ctx)
    check_grasps(ctx)
    check_oacs(ctx)
    return ctx.diagnostics
