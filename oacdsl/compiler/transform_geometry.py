"""The geometry rules of the grammar (``geometry``, ``shape``, ``quantity``, …) as a mixin
of :class:`~oacdsl.compiler.transform.ModelBuilder`: one method per rule, each building
a model node (:class:`~oacdsl.model.Geometry`, :class:`~oacdsl.model.Shape`, …) with
its span. A property given twice in one geometry block is reported here (E035), since
only the parse still shows it.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from lark import Token

from oacdsl.compiler.diagnostics import Diagnostic, Note
from oacdsl.compiler.fastmodel import make, unquote
from oacdsl.model import Dim, Geometry, Point, Quantity, Shape, Span

__all__ = ["GeometryBuilder", "token_part"]

_PartT = tuple[str, int, int, int, int]
_Parts = list[_PartT]


def token_part(key: str, tok: Token) -> _PartT:
    return (key, tok.line, tok.column, tok.end_line, tok.end_column)  # type: ignore[return-value]


class GeometryBuilder:
    """Rules of the geometry block; needs ``_span``, ``_between`` and ``diagnostics``
    from the builder it is mixed into."""

    diagnostics: list[Diagnostic]
    _span: Callable[[int, int, int, int], Span]
    _between: Callable[[Token | Span, Token | Span], Span]

    def quantity(self, children: list[Token | None]) -> Quantity:
        if len(children) == 1 and children[0] is not None and children[0].type == "QUANTITY":
            tok = children[0]  # ``56cm`` written as one word: the number, then its unit
            text = str(tok)
            cut = len(text.rstrip("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ/"))
            return make(
                Quantity,
                {
                    "value": float(text[:cut]),
                    "unit": text[cut:],
                    "span": self._between(tok, tok),
                    "parts": (("unit", tok.line, (tok.column or 0) + cut, tok.end_line, tok.end_column),),
                },
            )
        number, unit = (*children, None)[:2]
        last = unit if unit is not None else number
        return make(
            Quantity,
            {
                "value": float(number),  # type: ignore[arg-type]
                "unit": "" if unit is None else str(unit),
                "span": self._between(number, last),  # type: ignore[arg-type]
                "parts": () if unit is None else (token_part("unit", unit),),
            },
        )

    def dim(self, children: list[Any]) -> Dim:
        name, value = children
        return make(
            Dim,
            {
                "name": str(name),
                "value": value,
                "span": self._between(name, value.span),
                "parts": (token_part("name", name),),
            },
        )

    def point(self, children: list[Any]) -> Point:
        x, y, z, rpar = children
        return make(Point, {"x": x, "y": y, "z": z, "span": self._between(x.span, rpar)})

    def at(self, children: list[Any]) -> Point:
        return children[1]  # type: ignore[no-any-return]

    def shape_args(self, children: list[Any]) -> list[Any]:
        return [c for c in children if c is not None]

    def shape(self, children: list[Any]) -> Shape:
        kw, name, *rest = children
        args: list[Any] = next((c for c in rest if isinstance(c, list)), [])
        rpar = next((c for c in rest if isinstance(c, Token)), None)
        at = next((c for c in rest if isinstance(c, Point)), None)
        parts: _Parts = [token_part("primitive", name)]
        dims = []
        values: dict[str, Any] = {"primitive": str(name)}
        for arg in args:
            if isinstance(arg, Token):  # a file name
                if "file" in values:
                    parts.append(token_part("file.extra", arg))
                else:
                    values["file"] = unquote(arg)
                    parts.append(token_part("file", arg))
            else:
                dims.append(arg)
        values["dims"] = tuple(dims)
        if at is not None:
            values["at"] = at
        last: Any = at.span if at is not None else rpar if rpar is not None else name
        values.update(span=self._between(kw, last), parts=tuple(parts))
        return make(Shape, values)

    def mass(self, children: list[Any]) -> tuple[str, Any, _PartT]:
        kw, q = children
        return "mass", q, ("mass", kw.line, kw.column, q.span.end_line, q.span.end_column)

    def friction(self, children: list[Token]) -> tuple[str, Any, _PartT]:
        kw, number = children
        return "friction", float(number), ("friction", kw.line, kw.column, number.end_line, number.end_column)  # type: ignore[return-value]

    def colour(self, children: list[Token]) -> tuple[str, Any, _PartT]:
        kw, name = children
        return "colour", str(name), ("colour", kw.line, kw.column, name.end_line, name.end_column)  # type: ignore[return-value]

    def marker_points(self, children: list[Any]) -> tuple[str, Any, _PartT]:
        kw, *points = children
        end = points[-1].span
        return "markers", tuple(points), ("markers", kw.line, kw.column, end.end_line, end.end_column)

    def geometry(self, children: list[Any]) -> Geometry:
        *props, rbrace = children
        values: dict[str, Any] = {}
        shapes: list[Shape] = []
        parts: _Parts = []
        first: Any = None
        for prop in props:
            if isinstance(prop, Shape):
                shapes.append(prop)
                first = first or prop.span
                continue
            key, value, part = prop
            first = first or self._span(*part[1:])
            if key in values:
                self.diagnostics.append(
                    Diagnostic(
                        "E035",
                        f"'{key}' is given twice in one geometry",
                        self._span(*part[1:]),
                        (Note("first given here", self._span(*next(p for p in parts if p[0] == key)[1:])),),
                    )
                )
                continue
            values[key] = value
            parts.append(part)
        if shapes:
            values["shapes"] = tuple(shapes)
        values.update(span=self._between(first or rbrace, rbrace), parts=tuple(parts))
        return make(Geometry, values)
