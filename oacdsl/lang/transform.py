"""Build the typed model from Lark's parse tree, keeping source spans.

One method per grammar rule; each builds a pydantic node by keyword, with the
node's :class:`~oacdsl.model.Span` and the spans of the names inside it
(``parts``). Things the model normalises away (a parent or an atom listed
twice) are reported here as warnings, since only the tree still shows them.
"""

from __future__ import annotations

from typing import Any

from lark import Token, Transformer, v_args
from lark.tree import Meta

from oacdsl.lang.diagnostics import Diagnostic, Note
from oacdsl.model import Atom, Call, Decl, Grasp, Instance, Oac, ObjectClass, Param, Scene, Span
from oacdsl.world import NOTHING

__all__ = ["ModelBuilder"]

_Parts = list[tuple[str, Span]]


def _unquote(raw: str) -> str:
    body = raw[1:-1]
    if "\\" not in body:
        return body
    out: list[str] = []
    i = 0
    while i < len(body):
        ch = body[i]
        if ch == "\\" and i + 1 < len(body):
            nxt = body[i + 1]
            out.append({"n": "\n", "t": "\t"}.get(nxt, nxt))
            i += 2
        else:
            out.append(ch)
            i += 1
    return "".join(out)


@v_args(meta=True)
class ModelBuilder(Transformer[Token, list[Decl]]):
    """Transformer from the parse tree of one file to its declarations.

    ``diagnostics`` collects the warnings found on the way (W002).
    """

    def __init__(self, path: str) -> None:
        super().__init__(visit_tokens=False)
        self.path = path
        self.diagnostics: list[Diagnostic] = []

    # -- spans -----------------------------------------------------------
    def _span(self, meta: Meta) -> Span:
        return Span.model_construct(
            file=self.path,
            line=meta.line,
            column=meta.column,
            end_line=meta.end_line,
            end_column=meta.end_column,
        )

    def _tok(self, tok: Token) -> Span:
        return Span.model_construct(
            file=self.path,
            line=tok.line,
            column=tok.column,
            end_line=tok.end_line,
            end_column=tok.end_column,
        )

    def _twice(self, what: str, tok: Token, first: Span) -> None:
        self.diagnostics.append(
            Diagnostic(
                "W002",
                f"{what} is listed twice",
                self._tok(tok),
                (Note("first listed here", first),),
            )
        )

    def _names(self, toks: list[Token], key: str, parts: _Parts, what: str) -> tuple[str, ...]:
        seen: dict[str, Span] = {}
        for tok in toks:
            span = self._tok(tok)
            if str(tok) in seen:
                self._twice(f"{what} '{tok}'", tok, seen[str(tok)])
            else:
                seen[str(tok)] = span
                parts.append((f"{key}:{tok}", span))
        return tuple(str(t) for t in toks)

    # -- rules -----------------------------------------------------------
    def start(self, meta: Meta, children: list[Decl]) -> list[Decl]:
        return children

    def class_names(self, meta: Meta, children: list[Token]) -> list[Token]:
        return children

    def instance_names(self, meta: Meta, children: list[Token]) -> list[Token]:
        return children

    def class_decl(self, meta: Meta, children: list[Any]) -> ObjectClass:
        name, parents = children
        parts: _Parts = [("name", self._tok(name))]
        names = self._names(parents or [], "parents", parts, "parent class")
        return ObjectClass(name=str(name), parents=names, span=self._span(meta), parts=tuple(parts))

    def strings(self, meta: Meta, children: list[Token | None]) -> list[Token]:
        return [c for c in children if c is not None]

    def markers(self, meta: Meta, children: list[list[Token] | None]) -> list[Token]:
        return children[0] or []

    def params(self, meta: Meta, children: list[Param | None]) -> list[Param]:
        return [c for c in children if c is not None]

    def args(self, meta: Meta, children: list[Token]) -> list[Token]:
        return children

    def oac_body(self, meta: Meta, children: list[Any]) -> list[Any]:
        return children

    def instance_group(self, meta: Meta, children: list[Any]) -> list[Instance]:
        names, classes, markers, environment = children
        out: list[Instance] = []
        end = self._span(meta)
        for name in names:
            parts: _Parts = [("name", self._tok(name))]
            cls = self._names(classes, "classes", parts, "class") if not out else out[0].classes
            if out:
                parts += [p for p in out[0].parts if p[0] != "name"]
            marks: list[str] = []
            for i, tok in enumerate(markers or []):
                marks.append(_unquote(str(tok)))
                if not out:
                    parts.append((f"markers.{i}", self._tok(tok)))
            span = Span.model_construct(
                file=self.path,
                line=name.line,
                column=name.column,
                end_line=end.end_line,
                end_column=end.end_column,
            )
            out.append(
                Instance(
                    name=str(name),
                    classes=cls,
                    markers=tuple(marks),
                    environment=environment is not None,
                    span=span,
                    parts=tuple(parts),
                )
            )
        return out

    def scene_decl(self, meta: Meta, children: list[Any]) -> Scene:
        name, *groups = children
        instances = tuple(i for group in groups for i in group)
        return Scene(
            name=str(name), instances=instances, span=self._span(meta), parts=(("name", self._tok(name)),)
        )

    def offset(self, meta: Meta, children: list[Token]) -> tuple[tuple[float, float, float], Span]:
        x, y, z = (float(t) for t in children)
        return (x, y, z), self._span(meta)

    def grasp_decl(self, meta: Meta, children: list[Any]) -> Grasp:
        cls, kind, approach, offset = children
        parts: _Parts = [
            ("cls", self._tok(cls)),
            ("type", self._tok(kind)),
            ("approach", self._tok(approach)),
        ]
        fields: dict[str, Any] = {}
        if offset is not None:
            fields["offset"] = offset[0]
            parts.append(("offset", offset[1]))
        return Grasp(
            cls=str(cls),
            type=str(kind),
            approach=str(approach),
            span=self._span(meta),
            parts=tuple(parts),
            **fields,
        )

    def param(self, meta: Meta, children: list[Any]) -> Param:
        name, cls, default = children
        parts: _Parts = [("name", self._tok(name)), ("cls", self._tok(cls))]
        if default is not None:
            parts.append(("default", self._tok(default)))
        return Param(
            name=str(name),
            cls=str(cls),
            default=None if default is None else str(default),
            span=self._span(meta),
            parts=tuple(parts),
        )

    def atom(self, meta: Meta, children: list[Any]) -> Atom:
        negated, a, b = children
        if (a == NOTHING and b != NOTHING) or (b != NOTHING and a != NOTHING and b < a):
            a, b = b, a
        return Atom(
            left=str(a),
            right=str(b),
            negated=negated is not None,
            span=self._span(meta),
            parts=(("left", self._tok(a)), ("right", self._tok(b))),
        )

    def _section(self, meta: Meta, atoms: list[Atom | None], what: str) -> tuple[str, tuple[Atom, ...], Span]:
        seen: dict[Atom, Span | None] = {}
        for atom in atoms:
            if atom is None:
                continue
            if atom in seen:
                first = seen[atom]
                self.diagnostics.append(
                    Diagnostic(
                        "W002",
                        f"{what} '{_show(atom)}' is listed twice",
                        atom.span,
                        (Note("first listed here", first),),
                    )
                )
            else:
                seen[atom] = atom.span
        return what, tuple(a for a in atoms if a is not None), self._span(meta)

    def pre(self, meta: Meta, children: list[Atom | None]) -> tuple[str, tuple[Atom, ...], Span]:
        return self._section(meta, children, "precondition")

    def effect(self, meta: Meta, children: list[Atom | None]) -> tuple[str, tuple[Atom, ...], Span]:
        return self._section(meta, children, "effect")

    def execute(self, meta: Meta, children: list[Token]) -> tuple[str, Token]:
        return "execute", children[0]

    def steps(self, meta: Meta, children: list[Call]) -> tuple[str, tuple[Call, ...], Span]:
        return "steps", tuple(children), self._span(meta)

    def call(self, meta: Meta, children: list[Any]) -> Call:
        name, args = children
        toks: list[Token] = args or []
        parts: _Parts = [("oac", self._tok(name))]
        parts += [(f"args.{i}", self._tok(t)) for i, t in enumerate(toks)]
        return Call(
            oac=str(name), args=tuple(str(t) for t in toks), span=self._span(meta), parts=tuple(parts)
        )

    def oac_decl(self, meta: Meta, children: list[Any]) -> Oac:
        name, param_list, (pre, effect, body) = children
        params = tuple(param_list or ())
        parts: _Parts = [("name", self._tok(name))]
        fields: dict[str, Any] = {}
        if pre is not None:
            fields["pre"] = pre[1]
            parts.append(("pre", pre[2]))
        if effect is not None:
            fields["effect"] = effect[1]
            parts.append(("effect", effect[2]))
        if body[0] == "execute":
            fields["skill"] = str(body[1])
            parts.append(("skill", self._tok(body[1])))
        else:
            fields["steps"] = body[1]
            parts.append(("steps", body[2]))
        return Oac(name=str(name), params=params, span=self._span(meta), parts=tuple(parts), **fields)


def _show(atom: Atom) -> str:
    text = f"{atom.left} <-> {atom.right}"
    return f"not {text}" if atom.negated else text
