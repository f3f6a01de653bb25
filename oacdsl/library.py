"""A library: the declarations of several modules merged, with lookups.

The parser (:mod:`oacdsl.compiler`) builds modules; this view answers the questions
the matcher, composer and runtime ask: which classes an instance has (parents
included), whether a class is a subclass of another, which OACs, scenes and
grasps exist. It does not validate: ``oacc compile`` does that first.
"""

from __future__ import annotations

from collections.abc import Iterable
from functools import cached_property

from oacdsl.model import Grasp, Module, Oac, ObjectClass, Scene


class Library:
    """Merged, read-only view of one or more modules (first definition wins)."""

    def __init__(self, modules: Iterable[Module]) -> None:
        self.modules: tuple[Module, ...] = tuple(modules)
        self.classes: dict[str, ObjectClass] = {}
        self.scenes: dict[str, Scene] = {}
        self.grasps: dict[str, Grasp] = {}
        self.oacs: dict[str, Oac] = {}
        for module in self.modules:
            for decl in module.decls:
                if isinstance(decl, ObjectClass):
                    self.classes.setdefault(decl.name, decl)
                elif isinstance(decl, Scene):
                    self.scenes.setdefault(decl.name, decl)
                elif isinstance(decl, Grasp):
                    self.grasps.setdefault(decl.cls, decl)
                elif isinstance(decl, Oac):
                    self.oacs.setdefault(decl.name, decl)

    @cached_property
    def _ancestors(self) -> dict[str, frozenset[str]]:
        result: dict[str, frozenset[str]] = {}

        def visit(name: str, stack: tuple[str, ...]) -> frozenset[str]:
            if name in result:
                return result[name]
            found = {name}
            cls = self.classes.get(name)
            if cls is not None:
                for parent in cls.parents:
                    if parent not in stack:  # cycles are reported by the compiler
                        found |= visit(parent, (*stack, name))
            result[name] = frozenset(found)
            return result[name]

        for name in self.classes:
            visit(name, ())
        return result

    def ancestors(self, cls: str) -> frozenset[str]:
        """``cls`` and every class it inherits from, transitively."""
        return self._ancestors.get(cls, frozenset({cls}))

    def is_subclass(self, cls: str, ancestor: str) -> bool:
        """True when ``cls`` is ``ancestor`` or inherits from it."""
        return ancestor in self.ancestors(cls)

    def instance_classes(self, scene: Scene) -> dict[str, frozenset[str]]:
        """For each instance of ``scene``: all classes it belongs to (inherited included)."""
        out: dict[str, frozenset[str]] = {}
        for inst in scene.instances:
            found: set[str] = set()
            for cls in inst.classes:
                found |= self.ancestors(cls)
            out[inst.name] = frozenset(found)
        return out

    def grasp_for(self, classes: Iterable[str]) -> Grasp | None:
        """The grasp of the most specific class among ``classes`` that has one."""
        candidates = [c for c in classes if c in self.grasps]
        if not candidates:
            return None
        # most specific = the one with the most ancestors
        best = max(sorted(candidates), key=lambda c: len(self.ancestors(c)))
        return self.grasps[best]
