"""What every validation pass shares: the library being checked and the diagnostics found.

:mod:`oacdsl.compiler.checks` (classes, scenes, grasps) and
:mod:`oacdsl.compiler.check_oacs` (OACs) both append to one :class:`Context`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from oacdsl.compiler.diagnostics import Diagnostic, Note
from oacdsl.errors import did_you_mean
from oacdsl.library import Library
from oacdsl.model import Instance, Module, Node, Scene, Span

__all__ = ["Context"]


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
