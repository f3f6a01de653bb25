"""The OAC rules of the grammar (``oac_decl``, ``param``, ``atom``, ``pre``/``effect``,
``execute``, skill parameters and paths, ``steps``, ``together``, ``call``) as a mixin of
:class:`~oacdsl.compiler.transform.ModelBuilder`: one method per rule, each building a model
node (:class:`~oacdsl.model.Oac`, :class:`~oacdsl.model.Atom`, …) with its span. An atom listed
twice in a section is reported here (W002), since only the parse still shows it.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from lark import Token

from oacdsl.compiler.diagnostics import Diagnostic, Note
from oacdsl.compiler.fastmodel import make
from oacdsl.compiler.transform_geometry import token_part as _part
from oacdsl.model import (
    Atom,
    Call,
    KeyPose,
    Oac,
    Param,
    PathValue,
    SkillParam,
    Span,
    atom_text,
    canonical_steps,
    pair_order,
    sorted_skill_params,
)

__all__ = ["OacBuilder"]

_PartT = tuple[str, int, int, int, int]
_Parts = list[_PartT]


class OacBuilder:
    """Rules of OAC declarations; needs ``_between`` and ``diagnostics`` from the
    builder it is mixed into."""

    diagnostics: list[Diagnostic]
    _between: Callable[[Token | Span, Token | Span], Span]

    def params(self, children: list[Param | None]) -> list[Param]:
        return [c for c in children if c is not None]

    def param(self, children: list[Any]) -> Param:
        name, cls, default = children
        parts: _Parts = [_part("name", name), _part("cls", cls)]
        if default is not None:
            parts.append(_part("default", default))
        return make(
            Param,
            {
                "name": str(name),
                "cls": str(cls),
                "default": None if default is None else str(default),
                "span": self._between(name, default or cls),
                "parts": tuple(parts),
            },
        )

    def atom(self, children: list[Any]) -> Atom:
        negated, first, last = children
        a, b = pair_order(str(first), str(last))
        ta, tb = (first, last) if a == str(first) else (last, first)
        start = negated if negated is not None else first
        return make(
            Atom,
            {
                "left": a,
                "right": b,
                "negated": negated is not None,
                "span": self._between(start, last),
                "parts": (_part("left", ta), _part("right", tb)),
            },
        )

    def _section(self, children: list[Any], what: str, key: str) -> tuple[str, tuple[Atom, ...], _PartT]:
        kw, *atoms = children
        unique: dict[tuple[str, str, bool], Atom] = {}
        last: Atom | None = None
        for atom in atoms:
            if atom is None:
                continue
            last = atom
            ident = (atom.left, atom.right, atom.negated)
            first = unique.get(ident)
            if first is None:
                unique[ident] = atom
            elif atom.span is not None and first.span is not None:
                self.diagnostics.append(
                    Diagnostic(
                        "W002",
                        f"{what} '{atom_text(atom)}' is listed twice",
                        atom.span,
                        (Note("first listed here", first.span),),
                    )
                )
        end = last.span if last is not None and last.span is not None else kw
        section = (key, kw.line, kw.column, end.end_line, end.end_column)
        return what, tuple(unique[k] for k in sorted(unique)), section

    def pre(self, children: list[Any]) -> tuple[str, tuple[Atom, ...], _PartT]:
        return self._section(children, "precondition", "pre")

    def effect(self, children: list[Any]) -> tuple[str, tuple[Atom, ...], _PartT]:
        return self._section(children, "effect", "effect")

    def execute(self, children: list[Any]) -> tuple[str, Token, Any, Any]:
        name, args, params = children
        return "execute", name, args, params

    def skill_args(self, children: list[Any]) -> tuple[list[Token], Token]:
        args, rpar = children
        return args or [], rpar

    def skill_params(self, children: list[Any]) -> tuple[list[SkillParam], Token]:
        return [c for c in children[:-1] if c is not None], children[-1]

    def step_params(self, children: list[Any]) -> tuple[list[SkillParam], Token]:
        return self.skill_params(children)

    def skill_param(self, children: list[Any]) -> SkillParam:
        name, value = children
        return make(
            SkillParam,
            {
                "name": str(name),
                "value": value,
                "span": self._between(name, value.span),
                "parts": (_part("name", name),),
            },
        )

    def keypose(self, children: list[Any]) -> KeyPose:
        time, position, rotation = children
        return make(
            KeyPose,
            {
                "time": time,
                "position": position,
                "rotation": rotation,
                "span": self._between(time.span, rotation.span),
            },
        )

    def pose_path(self, children: list[Any]) -> PathValue:
        *poses, rbrack = children
        kept = tuple(p for p in poses if p is not None)
        start = kept[0].span if kept else rbrack
        return make(PathValue, {"poses": kept, "span": self._between(start, rbrack)})

    def steps(self, children: list[Any]) -> tuple[str, tuple[Call, ...], _PartT]:
        kw, *items, rbrace = children
        calls: list[Call] = []
        for item in items:
            calls += item if isinstance(item, list) else [item]
        steps = canonical_steps(calls) if len(calls) != len(items) else tuple(calls)
        return "steps", steps, ("steps", kw.line, kw.column, rbrace.end_line, rbrace.end_column)

    def together(self, children: list[Any]) -> list[Call]:
        """A ``together { … }`` block: its calls, all but the first marked ``together``."""
        kw, *calls, rbrace = children
        if len(calls) < 2:
            self.diagnostics.append(
                Diagnostic(
                    "W008",
                    f"a together block of {len(calls)} step{'' if len(calls) == 1 else 's'}: it says"
                    " nothing (write the step without the block, or put the steps that may run"
                    " together into it)",
                    self._between(kw, rbrace),
                )
            )
        return [c if k == 0 else c.model_copy(update={"together": True}) for k, c in enumerate(calls)]

    def call(self, children: list[Any]) -> Call:
        name, args, rpar, params = children
        toks: list[Token] = args or []
        parts: _Parts = [_part("oac", name)]
        parts += [_part(f"args.{i}", t) for i, t in enumerate(toks)]
        values: dict[str, Any] = {"oac": str(name), "args": tuple(str(t) for t in toks)}
        end: Any = rpar
        if params is not None:
            given, rbrace = params
            end = rbrace
            first = given[0].span if given and given[0].span is not None else None
            line, column = (first.line, first.column) if first else (rpar.end_line, rpar.end_column)
            parts.append(("skill_params", line, column, rbrace.end_line, rbrace.end_column))
            if given:
                values["skill_params"] = sorted_skill_params(tuple(given))
        values.update(span=self._between(name, end), parts=tuple(parts))
        return make(Call, values)

    def oac_body(self, children: list[Any]) -> list[Any]:
        return children

    def oac_decl(self, children: list[Any]) -> Oac:
        kw, name, param_list, (pre, effect, body), rbrace = children
        parts: _Parts = [_part("name", name)]
        values: dict[str, Any] = {"name": str(name), "params": tuple(param_list or ())}
        if pre is not None:
            values["pre"] = pre[1]
            parts.append(pre[2])
        if effect is not None:
            values["effect"] = effect[1]
            parts.append(effect[2])
        if body[0] == "execute":
            values["skill"] = str(body[1])
            parts.append(_part("skill", body[1]))
            _, _, skill_args, skill_params = body
            if skill_args is not None:
                toks, rpar = skill_args
                values["skill_args"] = tuple(str(t) for t in toks)
                parts += [_part(f"skill_args.{i}", t) for i, t in enumerate(toks)]
                parts.append(("skill_call", body[1].line, body[1].column, rpar.end_line, rpar.end_column))
            if skill_params is not None and skill_params[0]:
                values["skill_params"] = sorted_skill_params(tuple(skill_params[0]))
        else:
            values["steps"] = body[1]
            parts.append(body[2])
        values.update(span=self._between(kw, rbrace), parts=tuple(parts))
        return make(Oac, values)
