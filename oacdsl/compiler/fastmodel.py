"""Build model nodes from already normalised values, without pydantic's generic overhead.

The parser creates tens of thousands of nodes and spans for a large library.
:func:`make` fills a model the way ``BaseModel.model_construct`` does (all
fields, defaults included, in declaration order, so that equality and hashing
see the same values) at a fraction of its cost; the caller applies the model's
normalisation first (sorted parents, canonical atoms, …).
``tests/test_lang_internals.py`` checks that the result equals validated
construction; the round-trip property tests compare thousands more.
"""

from __future__ import annotations

from typing import Any, TypeVar

from oacdsl.model import Node, Span

__all__ = ["make", "unquote"]

M = TypeVar("M", bound=Node | Span)
_TEMPLATES: dict[type, dict[str, Any]] = {}
_setattr = object.__setattr__


def make(cls: type[M], values: dict[str, Any]) -> M:
    """A ``cls`` instance holding ``values`` (trusted, normalised) and defaults for the rest."""
    template = _TEMPLATES.get(cls)
    if template is None:
        template = {
            name: None if field.is_required() else field.get_default(call_default_factory=True)
            for name, field in cls.model_fields.items()
        }
        _TEMPLATES[cls] = template
    fields = template.copy()
    fields.update(values)
    obj = cls.__new__(cls)
    _setattr(obj, "__dict__", fields)
    _setattr(obj, "__pydantic_fields_set__", set(values))
    _setattr(obj, "__pydantic_extra__", None)
    _setattr(obj, "__pydantic_private__", None)
    return obj


def unquote(raw: str) -> str:
    """The text of a quoted STRING token: ``"a\\"b"`` → ``a"b`` (``\\n``, ``\\r``, ``\\t`` escapes)."""
    body = raw[1:-1]
    if "\\" not in body:
        return body
    out: list[str] = []
    i = 0
    while i < len(body):
        ch = body[i]
        if ch == "\\" and i + 1 < len(body):
            nxt = body[i + 1]
            out.append({"n": "\n", "r": "\r", "t": "\t"}.get(nxt, nxt))
            i += 2
        else:
            out.append(ch)
            i += 1
    return "".join(out)
