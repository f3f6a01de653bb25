"""Validation passes over the modules of a library: names, classes, scenes, grasps.

Every pass appends :class:`~oacdsl.compiler.diagnostics.Diagnostic` objects and
never stops at the first problem. The checks of OACs live in
:mod:`oacdsl.compiler.check_oacs`; :func:`check_modules` runs all of them.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

import networkx as nx

from oacdsl.compiler.check_geometry import check_geometry
from oacdsl.compiler.check_oacs import check_oacs
from oacdsl.compiler.check_state import check_scene_state
from oacdsl.compiler.check_together import check_together
from oacdsl.compiler.context import Context
from oacdsl.compiler.diagnostics import Diagnostic, Note
from oacdsl.compiler.grammar import keywords
from oacdsl.errors import did_you_mean
from oacdsl.model import APPROACHES, GRASP_TYPES, Grasp, Instance, Module, Oac, ObjectClass, Scene, Span

__all__ = ["check_modules"]

#: Grasp offsets longer than this (metres) are probably millimetres by mistake (W005).
MAX_OFFSET_M = 0.5


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
    """E007 once per strongly connected component of the parent graph."""
    classes = ctx.library.classes
    graph = {n: [p for p in c.parents if p in classes] for n, c in classes.items()}
    digraph = nx.DiGraph([(n, p) for n, parents in graph.items() for p in parents])
    for comp in nx.strongly_connected_components(digraph):
        if len(comp) == 1 and not digraph.has_edge(next(iter(comp)), next(iter(comp))):
            continue
        start = min(comp, key=lambda n: _pos(classes[n].span))
        path = _cycle_path(start, graph, set(comp))
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
            if inst.name in keywords():
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
        if grasp.type == "pinch" and math.hypot(grasp.offset[0], grasp.offset[1]) < 1e-6:
            ctx.add(
                "E049",
                "a pinch grasp takes a flat object's edge: its offset must be a point of the top edge,"
                " away from the object's axis (x or y not 0); a knob or the middle of the top is taken"
                " with 'type power approach top'",
                grasp.part("offset") if grasp.part("offset") is not None else grasp.part("type"),
            )
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
    ctx = Context(modules)
    check_classes(ctx)
    check_scenes(ctx)
    for scene in (d for d in _decls(ctx) if isinstance(d, Scene)):
        check_scene_state(ctx, scene)
    check_grasps(ctx)
    check_geometry(ctx)
    check_oacs(ctx)
    check_together(ctx)
    return ctx.diagnostics
