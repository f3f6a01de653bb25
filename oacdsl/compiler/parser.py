"""Parse ``.oac`` text into a :class:`~oacdsl.model.Module`.

The grammar is ``grammar/oac.lark`` (installed as package data); the Lark LALR
parser is built once per process and builds the model while it parses
(:mod:`oacdsl.compiler.transform`). Comments reach us through a lexer callback
and are attached to nodes afterwards (:mod:`oacdsl.compiler.comments`). Syntax
errors become :class:`~oacdsl.errors.LanguageError` with one diagnostic
(:mod:`oacdsl.compiler.syntax`).
"""

from __future__ import annotations

import functools
import importlib.resources
import threading
from pathlib import Path
from typing import cast

from lark import Lark, Token, UnexpectedInput

from oacdsl.compiler.comments import Comment, attach_comments, comment_text
from oacdsl.compiler.diagnostics import Diagnostic, language_error
from oacdsl.compiler.fastmodel import make
from oacdsl.compiler.lexer import OacLexer
from oacdsl.compiler.transform import ModelBuilder
from oacdsl.errors import InputError
from oacdsl.model import Decl, Module

__all__ = [
    "grammar_text",
    "lark_parser",
    "normalize_newlines",
    "parse_file",
    "parse_source",
    "parse_text",
    "read_source",
]

_lock = threading.Lock()
_comment_sink: list[Token] = []


def grammar_text() -> str:
    """The text of ``grammar/oac.lark`` as installed with the package."""
    return importlib.resources.files("oacdsl").joinpath("grammar/oac.lark").read_text(encoding="utf-8")


def _on_comment(token: Token) -> Token:
    _comment_sink.append(token)
    return token


@functools.lru_cache(maxsize=1)
def _builder() -> ModelBuilder:
    return ModelBuilder()


@functools.lru_cache(maxsize=1)
def lark_parser() -> Lark:
    """The process-wide LALR parser, building the model as it parses (built on first use).

    The lexer is :class:`~oacdsl.compiler.lexer.OacLexer` (Lark's contextual
    lexer, faster).
    Its ``parse`` returns the list of declarations; use :func:`parse_source`,
    which also sets the file name and collects comments and warnings.
    """
    return Lark(
        grammar_text(),
        parser="lalr",
        lexer=OacLexer,
        maybe_placeholders=True,
        transformer=_builder(),
        lexer_callbacks={"COMMENT": _on_comment},
    )


def _comments(text: str, tokens: list[Token]) -> list[Comment]:
    out = []
    for tok in tokens:
        start = tok.start_pos or 0
        line_start = text.rfind("\n", 0, start) + 1
        own_line = not text[line_start:start].strip()
        out.append(Comment(tok.line or 0, tok.column or 0, own_line, comment_text(str(tok))))
    return out


def normalize_newlines(text: str) -> str:
    """``text`` with CR LF and lone CR line ends turned into LF.

    The grammar ends a line (and a ``#`` comment) at LF only: a file saved with
    classic-Mac CR line ends would otherwise be one long line, everything after
    its first ``#`` one comment. Line numbers of diagnostics count the lines a
    text editor shows.
    """
    if "\r" not in text:
        return text
    return text.replace("\r\n", "\n").replace("\r", "\n")


def parse_source(text: str, path: str = "<string>") -> tuple[Module, list[Diagnostic]]:
    """Parse ``text``; return the module and the warnings found while building it.

    Line ends may be LF, CR LF or CR (:func:`normalize_newlines`). Raises
    :class:`~oacdsl.errors.LanguageError` (one E001/E002 diagnostic) on a syntax error.
    """
    from oacdsl.compiler.syntax import syntax_diagnostic

    text = normalize_newlines(text)

    parser = lark_parser()
    builder = _builder()
    with _lock:
        builder.reset(path)
        _comment_sink.clear()
        try:
            decls = cast(list[Decl], parser.parse(text))
        except UnexpectedInput as error:
            raise language_error([syntax_diagnostic(error, text, path)], {path: text}) from None
        tokens = list(_comment_sink)
        warnings = builder.diagnostics
        _comment_sink.clear()
    decls, header, trailing = attach_comments(decls, _comments(text, tokens))
    module = make(Module, {"path": path, "decls": tuple(decls), "comments": header, "trailing": trailing})
    return module, warnings


def parse_text(text: str, path: str = "<string>") -> Module:
    """Parse one file's text (``path`` names it in diagnostics and spans)."""
    return parse_source(text, path)[0]


def read_source(path: str | Path) -> str:
    """Read a ``.oac`` file as UTF-8; :class:`~oacdsl.errors.InputError` when that fails."""
    p = Path(path)
    try:
        data = p.read_bytes()
    except FileNotFoundError:
        raise InputError("no such file", location=str(path)) from None
    except IsADirectoryError:
        raise InputError("is a directory, expected a .oac file", location=str(path)) from None
    except OSError as error:
        raise InputError(f"cannot read: {error.strerror or error}", location=str(path)) from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as error:
        line = data.count(b"\n", 0, error.start) + 1
        raise InputError(
            f"not UTF-8 text (byte 0x{data[error.start]:02x} on line {line})", location=str(path)
        ) from None
    return text[1:] if text.startswith("\ufeff") else text


def parse_file(path: str | Path) -> Module:
    """Read and parse one ``.oac`` file."""
    return parse_text(read_source(path), str(path))
