"""Build the typed model while Lark parses, keeping source spans.

:class:`ModelBuilder` is a Lark ``Transformer`` with one method per grammar
rule, each building a model node by keyword with its
:class:`~oacdsl.model.Span` and the spans of the names inside it (``parts``).
The parser applies it inline (no parse tree is built), so spans come from the
tokens: the grammar keeps the tokens that start and end declarations
(``CLASS``, ``RBRACE``, …).

Nodes are built with :func:`oacdsl.compiler.fastmodel.make` after applying the
model's own normalisation (sorted parents, sorted instances, atoms in
:func:`~oacdsl.model.pair_order`). Things
the model normalises away (a parent or an atom listed twice) are reported here
as warnings (W002), since only the parse still shows them.
"""

from __future__ import annotations

from typing import Any

from lark import Token, Transformer

from oacdsl.compiler.diagnostics import Diagnostic, Note
from oacdsl.compiler.fastmodel import make, unquote
from oacdsl.compiler.transform_geometry import GeometryBuilder
from oacdsl.compiler.transform_geometry import token_part as _part
from oacdsl.compiler.transform_oac import OacBuilder
from oacdsl.errors import did_you_mean
from oacdsl.model import (
    MAX_BALLS,
    Decl,
    Grasp,
    Instance,
    ObjectClass,
    Quantity,
    Scene,
    SceneFill,
    ScenePlace,
    Span,
    fill_key,
    place_key,
)
from oacdsl.units import language_si, unit_kind

__all__ = ["ModelBuilder"]

_Pos = tuple[int, int, int, int]
_PartT = tuple[str, int, int, int, int]
_Parts = list[_PartT]


class ModelBuilder(GeometryBuilder, OacBuilder, Transformer[Token, list[Decl]]):
    """Inline transformer from one file's tokens to its declarations.

    The geometry rules are in :class:`~oacdsl.compiler.transform_geometry.GeometryBuilder`,
    the OAC rules in :class:`~oacdsl.compiler.transform_oac.OacBuilder`. Call :meth:`reset`
    before each parse; ``diagnostics`` then collects the
    warnings found on the way (W002).
    """

    def __init__(self) -> None:
        super().__init__(visit_tokens=False)
        self.reset("<string>")

    def reset(self, path: str) -> None:
        self.path = path
        self.diagnostics: list[Diagnostic] = []

    # -- spans -----------------------------------------------------------
    def _span(self, line: int, column: int, end_line: int, end_column: int) -> Span:
        return make(
            Span,
            {
                "file": self.path,
                "line": line,
                "column": column,
                "end_line": end_line,
                "end_column": end_column,
            },
        )

    def _between(self, first: Token | Span, last: Token | Span) -> Span:
        return self._span(first.line, first.column, last.end_line, last.end_column)  # type: ignore[arg-type]

    def _warn_twice(self, what: str, pos: _Pos, first: _Pos) -> None:
        self.diagnostics.append(
            Diagnostic(
                "W002",
                f"{what} is listed twice",
                self._span(*pos),
                (Note("first listed here", self._span(*first)),),
            )
        )

    def _names(self, toks: list[Token], key: str, parts: _Parts, what: str) -> tuple[str, ...]:
        seen: dict[str, _Pos] = {}
        for tok in toks:
            text = str(tok)
            pos: _Pos = (tok.line, tok.column, tok.end_line, tok.end_column)  # type: ignore[assignment]
            if text in seen:
                self._warn_twice(f"{what} '{text}'", pos, seen[text])
            else:
                seen[text] = pos
                parts.append((f"{key}:{text}", *pos))  # type: ignore[arg-type]
        return tuple(sorted(seen))

    # -- rules -----------------------------------------------------------
    def start(self, children: list[Decl]) -> list[Decl]:
        return children

    def class_names(self, children: list[Token]) -> list[Token]:
        return children

    instance_names = args = class_names

    def class_decl(self, children: list[Any]) -> ObjectClass:
        kw, name, parents, geometry = children
        parts: _Parts = [_part("name", name)]
        names = self._names(parents or [], "parents", parts, "parent class")
        last = geometry.span if geometry is not None else parents[-1] if parents else name
        values: dict[str, Any] = {"name": str(name), "parents": names}
        if geometry is not None:
            values["geometry"] = geometry
        values.update(span=self._between(kw, last), parts=tuple(parts))
        return make(ObjectClass, values)

    def strings(self, children: list[Token | None]) -> list[Token]:
        return [c for c in children if c is not None]

    def markers(self, children: list[Any]) -> tuple[list[Token], Token]:
        _, strings, rpar = children
        return strings or [], rpar

    def instance_group(self, children: list[Any]) -> list[Instance]:
        names, classes, markers, flag, geometry = children
        last = flag or (markers[1] if markers else classes[-1])
        if geometry is not None:
            last = geometry.span
        shared: _Parts = []
        cls = self._names(classes, "classes", shared, "class")
        marks: list[str] = []
        for i, tok in enumerate(markers[0] if markers else ()):
            marks.append(unquote(tok))
            shared.append(_part(f"markers.{i}", tok))
        return [
            make(
                Instance,
                {
                    "name": str(name),
                    "classes": cls,
                    "markers": tuple(marks),
                    "environment": flag is not None and flag.type == "ENVIRONMENT",
                    "ignored": flag is not None and flag.type == "IGNORED",
                    "untracked": flag is not None and flag.type == "UNTRACKED",
                    "geometry": geometry,
                    "span": self._between(name, last),
                    "parts": (_part("name", name), *shared),
                },
            )
            for name in names
        ]

    def scene_decl(self, children: list[Any]) -> Scene:
        kw, name, *items, rbrace = children
        instances: list[Instance] = []
        places: list[ScenePlace] = []
        fills: list[SceneFill] = []
        values: dict[str, Any] = {}
        parts: _Parts = [_part("name", name)]
        for item in items:
            if isinstance(item, list):
                instances += item
            elif isinstance(item, ScenePlace):
                places.append(item)
            elif isinstance(item, SceneFill):
                fills.append(item)
            elif str(item[0]) != "layout":  # (NAME, NAME): only 'layout auto|demonstrated' exists
                self.diagnostics.append(
                    Diagnostic(
                        "E045",
                        f"unknown scene statement '{item[0]} {item[1]}'"
                        f"{did_you_mean(str(item[0]), ['layout'])}:"
                        " a scene holds instances ('a : Class'), 'layout auto|demonstrated',"
                        " 'x at (x, y)' and 'l in c'",
                        self._between(item[0], item[1]),
                    )
                )
            elif "layout" not in values:  # a second one is reported by the checks
                values["layout"] = str(item[1])
                parts.append(_part("layout", item[1]))
            else:
                parts.append(_part(f"layout.{len(parts)}", item[1]))
        values.update(
            name=str(name),
            instances=tuple(sorted(instances, key=lambda i: i.name)),
            places=tuple(sorted(places, key=place_key)),
            fills=tuple(sorted(fills, key=fill_key)),
            span=self._between(kw, rbrace),
            parts=tuple(parts),
        )
        return make(Scene, values)

    def layout_stmt(self, children: list[Token]) -> tuple[Token, Token]:
        return children[0], children[1]

    def measure(self, children: list[Token]) -> Quantity:
        """``56cm`` (one QUANTITY token) or ``0.56`` (NUMBER): a placement or a skill parameter."""
        return self.quantity([children[0]])

    def place_stmt(self, children: list[Any]) -> ScenePlace:
        name, _at, x, y, rpar, _turned, yaw = children
        parts: _Parts = [
            _part("instance", name),
            ("at", x.span.line, x.span.column, rpar.end_line, rpar.end_column),
        ]
        last = rpar if yaw is None else yaw.span
        if yaw is not None and yaw.value == 0:  # not turned: the model holds no zero yaw
            if language_si(0.0, yaw.unit)[1] not in ("", "rad"):  # the checks see no zero: say it here
                self.diagnostics.append(
                    Diagnostic("E043", f"the yaw of '{name}' is {unit_kind('rad')}, but '{yaw.unit}'"
                               " is no unit of angle", yaw.span)
                )
            yaw = None
        if yaw is not None:  # 'turned ANGLE'
            parts.append(("yaw", yaw.span.line, yaw.span.column, yaw.span.end_line, yaw.span.end_column))
        return make(
            ScenePlace,
            {
                "instance": str(name),
                "x": x,
                "y": y,
                "yaw": yaw,
                "span": self._between(name, last),
                "parts": tuple(parts),
            },
        )

    def fill_stmt(self, children: list[Any]) -> SceneFill:
        liquid, _in, container, _balls, count = children
        parts: _Parts = [_part("liquid", liquid), _part("container", container)]
        values: dict[str, Any] = {"liquid": str(liquid), "container": str(container)}
        last = container
        if count is not None:
            parts.append(_part("balls", count))
            number = float(str(count))
            if number.is_integer():
                values["balls"] = int(number)
            else:
                self.diagnostics.append(
                    Diagnostic(
                        "E044",
                        f"'{count}' balls: the number of balls is a whole number (1 to {MAX_BALLS})",
                        self._between(count, count),
                    )
                )
            last = count
        values.update(span=self._between(liquid, last), parts=tuple(parts))
        return make(SceneFill, values)

    def offset(self, children: list[Token]) -> tuple[tuple[float, float, float], _PartT]:
        kw, x, y, z, rpar = children
        return (float(x), float(y), float(z)), ("offset", kw.line, kw.column, rpar.end_line, rpar.end_column)  # type: ignore[return-value]

    def grasp_decl(self, children: list[Any]) -> Grasp:
        kw, cls, kind, approach, offset, rbrace = children
        parts: _Parts = [
            _part("cls", cls),
            _part("type", kind),
            _part("approach", approach),
        ]
        values: dict[str, Any] = {"cls": str(cls), "type": str(kind), "approach": str(approach)}
        if offset is not None:
            values["offset"] = offset[0]
            parts.append(offset[1])
        values.update(span=self._between(kw, rbrace), parts=tuple(parts))
        return make(Grasp, values)
