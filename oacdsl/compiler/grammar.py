"""The grammar and the Lark parser built from it, once per process.

``grammar/oac.lark`` (installed as package data) is the one description of
the language's text; what other modules need to know about it is derived
here: the reserved words (:func:`keywords`) and the pattern of a name
(:func:`name_pattern`). The parser builds the model while it parses
(:class:`~oacdsl.compiler.transform.ModelBuilder`) and hands comments to
:data:`comment_sink` through a lexer callback; :mod:`oacdsl.compiler.parser`
drives it, :mod:`oacdsl.compiler.syntax` reads its states for error messages.
"""

from __future__ import annotations

import functools
import importlib.resources
import re

from lark import Lark, Token
from lark.lexer import PatternStr

from oacdsl.compiler.lexer import OacLexer
from oacdsl.compiler.transform import ModelBuilder

__all__ = ["comment_sink", "grammar_text", "keywords", "lark_parser", "model_builder", "name_pattern"]

#: Comment tokens of the current parse, in order (the parser clears it under its lock).
comment_sink: list[Token] = []


def grammar_text() -> str:
    """The text of ``grammar/oac.lark`` as installed with the package."""
    return importlib.resources.files("oacdsl").joinpath("grammar/oac.lark").read_text(encoding="utf-8")


def _on_comment(token: Token) -> Token:
    comment_sink.append(token)
    return token


@functools.lru_cache(maxsize=1)
def model_builder() -> ModelBuilder:
    """The transformer the parser applies inline (one per process; reset it before each parse)."""
    return ModelBuilder()


@functools.lru_cache(maxsize=1)
def lark_parser() -> Lark:
    """The process-wide LALR parser, building the model as it parses (built on first use, ~0.07 s).

    The lexer is :class:`~oacdsl.compiler.lexer.OacLexer` (Lark's contextual
    lexer, faster). Its ``parse`` returns the list of declarations; use
    :func:`oacdsl.compiler.parser.parse_source`, which also sets the file name
    and collects comments and warnings.
    """
    return Lark(
        grammar_text(),
        parser="lalr",
        lexer=OacLexer,
        maybe_placeholders=True,
        transformer=model_builder(),
        lexer_callbacks={"COMMENT": _on_comment},
    )


@functools.lru_cache(maxsize=1)
def keywords() -> frozenset[str]:
    """The words of the language (every literal of the grammar that looks like a name).

    Parameters and instances may not be called so (E018), although the
    contextual lexer would let the parser read them.
    """
    return frozenset(
        t.pattern.value
        for t in lark_parser().terminals
        if isinstance(t.pattern, PatternStr) and name_pattern().fullmatch(t.pattern.value)
    )


@functools.lru_cache(maxsize=1)
def name_pattern() -> re.Pattern[str]:
    """The regular expression of a name, the grammar's ``NAME`` terminal (use ``fullmatch``)."""
    terminals = {t.name: t for t in lark_parser().terminals}
    return re.compile(terminals["NAME"].pattern.to_regexp())
