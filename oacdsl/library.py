"""A library: the declarations of several modules merged, with lookups.

The parser (:mod:`oacdsl.compiler`) builds modules; this view answers the questions
the matcher, composer and runtime ask: which classes an instance has (parents
included), whether a class is a subclass of another, which OACs, scenes and
grasps exist. It does not validate: ``oacc compile`` does that first.
"""

from __future__ import annotations

from collections.abc import Iterable

from oacdsl.model import Grasp, Module, Oac, ObjectClass, Scene


class Library:
    """Merged, read-only view of one or more modules (first definition wins)."""

    def __init__(self, modules: Iterable[Module]) -> None:
        self.modules: tuple[Module, ...] = tuple(modules)
        self.classes: dict[str, ObjectClass] = {}
        self.scenes: dict[str, Scene] = {}
        self.grasps: dict[str, Grasp] = {}
        self.oacs: dict[str, Oac] = {}
        self._ancestors: dict[str, frozenset[str]] = {}
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

    def ancestors(self, cls: str) -> frozenset[str]:
        """``cls`` and every class it inherits from, transitively (cycles tolerated).

        Computed when asked, iteratively, and remembered for the classes asked about: a
        chain of 100,000 classes costs one walk per class queried, not a set per class.
        """
        found = self._ancestors.get(cls)
        if found is None:
            seen, todo = {cls}, [cls]
            while todo:
                decl = self.classes.get(todo.pop())
                if decl is not None:
                    for parent in decl.parents:
                        if parent not in seen:
                            seen.add(parent)
                            todo.append(parent)
            found = self._ancestors[cls] = frozenset(seen)
        return found

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
