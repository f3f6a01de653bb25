"""The model's base: :class:`Span` (where a node stands in its source), :class:`Node` (frozen,
hashable, trivia outside equality) and the leaf values :class:`Quantity`, :class:`Dim`,
:class:`Point` (see :mod:`oacdsl.model`)."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, Field

__all__ = ["Dim", "Node", "Point", "Quantity", "Span"]

_TRIVIA = frozenset({"span", "comments", "note", "parts"})


class Span(BaseModel):
    """Where a node stands in its source: 1-based line and column, end exclusive."""

    model_config = ConfigDict(frozen=True)

    file: str
    line: int
    column: int
    end_line: int
    end_column: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}"


class Node(BaseModel):
    """Base of every model node: frozen, hashable, trivia outside equality.

    Trivia: ``span`` (the whole node), ``comments`` (the comment lines written
    before it, without ``#``), ``note`` (a comment at the end of its last line)
    and ``parts`` (the spans of the names inside it, keyed like ``"name"``,
    ``"cls"``, ``"parents:Cup"`` (sorted collections: by name) or ``"args.1"``
    (ordered ones: by index), for diagnostics that point at one name).
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    span: Span | None = Field(default=None, repr=False)
    comments: tuple[str, ...] = Field(default=(), repr=False)
    note: str | None = Field(default=None, repr=False)
    #: (key, line, column, end_line, end_column) of names inside the node, in ``span.file``.
    parts: tuple[tuple[str, int, int, int, int], ...] = Field(default=(), repr=False)

    def part(self, key: str) -> Span | None:
        """The span of the part ``key`` (e.g. ``"parents:Cup"``), else the node's span."""
        if self.span is not None:
            for k, line, column, end_line, end_column in self.parts:
                if k == key:
                    return Span(
                        file=self.span.file,
                        line=line,
                        column=column,
                        end_line=end_line,
                        end_column=end_column,
                    )
        return self.span

    def _key(self) -> tuple[Any, ...]:
        return tuple(v for k, v in self.__dict__.items() if k not in _TRIVIA)

    def __eq__(self, other: object) -> bool:
        return type(self) is type(other) and self._key() == other._key()  # type: ignore[attr-defined]

    def __hash__(self) -> int:
        return hash((type(self).__name__, self._key()))


class Quantity(Node):
    """A number as written with its unit as written (``4cm`` → 4.0, ``"cm"``; ``0.04`` → ``""``).

    The model keeps the text's unit so that printing gives back what was written;
    :func:`oacdsl.geometry.si` converts to SI (metres, kilograms). The compiler checks units.
    """

    value: float
    unit: str = ""


class Dim(Node):
    """A named parameter of a shape: ``radius 4cm``."""

    name: str
    value: Quantity


class Point(Node):
    """A point ``(x, y, z)`` in an object's frame (lengths, each with its unit)."""

    x: Quantity
    y: Quantity
    z: Quantity
