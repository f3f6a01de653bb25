"""Parse ``.oac`` text into a :class:`~oacdsl.model.Module`.

The grammar is ``grammar/oac.lark``; the Lark LALR parser is built once per
process (:mod:`oacdsl.compiler.grammar`) and builds the model while it parses
(:mod:`oacdsl.compiler.transform`). Comments reach us through a lexer callback
and are attached to nodes afterwards (:mod:`oacdsl.compiler.comments`). Syntax
errors become :class:`~oacdsl.errors.LanguageError` with one diagnostic
(:mod:`oacdsl.compiler.syntax`).
"""

from __future__ import annotations

import threading
from pathlib import Path
from typing import cast

from lark import Token, UnexpectedInput

from oacdsl.compiler.comments import Comment, attach_comments, comment_text
from oacdsl.compiler.diagnostics import Diagnostic, language_error
from oacdsl.compiler.fastmodel import make
from oacdsl.compiler.grammar import comment_sink, lark_parser, model_builder
from oacdsl.compiler.syntax import syntax_diagnostic
from oacdsl.errors import InputError, SourceEncodingError
from oacdsl.model import Decl, Module, Span

__all__ = [
    "decode_source",
    "normalize_newlines",
    "parse_file",
    "parse_source",
    "parse_text",
    "read_bytes",
    "read_source",
]

_lock = threading.Lock()


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
    text = normalize_newlines(text)
    parser = lark_parser()
    builder = model_builder()
    with _lock:
        builder.reset(path)
        comment_sink.clear()
        try:
            decls = cast(list[Decl], parser.parse(text))
        except UnexpectedInput as error:
            raise language_error([syntax_diagnostic(error, text, path)], {path: text}) from None
        tokens = list(comment_sink)
        warnings = builder.diagnostics
        comment_sink.clear()
    decls, header, trailing = attach_comments(decls, _comments(text, tokens))
    module = make(Module, {"path": path, "decls": tuple(decls), "comments": header, "trailing": trailing})
    return module, warnings


def parse_text(text: str, path: str = "<string>") -> Module:
    """Parse one file's text (``path`` names it in diagnostics and spans)."""
    return parse_source(text, path)[0]


def read_bytes(path: str | Path) -> bytes:
    """The bytes of a ``.oac`` file; :class:`~oacdsl.errors.InputError` when it cannot be read."""
    p = Path(path)
    try:
        return p.read_bytes()
    except FileNotFoundError:
        raise InputError("no such file", location=str(path)) from None
    except IsADirectoryError:
        raise InputError("is a directory, expected a .oac file", location=str(path)) from None
    except OSError as error:
        raise InputError(f"cannot read: {error.strerror or error}", location=str(path)) from None


def decode_source(data: bytes, path: str) -> str:
    """The UTF-8 text of a ``.oac`` file, without a byte-order mark.

    Raises :class:`~oacdsl.errors.SourceEncodingError` with one E024 diagnostic
    at the line and column (in characters) of the first byte that is not UTF-8.
    """
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as error:
        raise _encoding_error(data, error.start, path) from None
    return text.removeprefix(_BOM)


_BOM = "\ufeff"


def _encoding_error(data: bytes, start: int, path: str) -> SourceEncodingError:
    line = data.count(b"\n", 0, start) + 1
    line_start = data.rfind(b"\n", 0, start) + 1
    before = data[line_start:start].decode("utf-8")  # valid: decoding failed first at ``start``
    column = len(before.removeprefix(_BOM) if line_start == 0 else before) + 1
    span = Span(file=path, line=line, column=column, end_line=line, end_column=column + 1)
    diagnostic = Diagnostic("E024", f"not UTF-8 text (byte 0x{data[start]:02x} on line {line})", span)
    shown = data.decode("utf-8", errors="replace").removeprefix(_BOM)
    error = language_error([diagnostic], {path: shown})
    return SourceEncodingError(str(error), diagnostics=error.diagnostics, rendered=error.rendered)


def read_source(path: str | Path) -> str:
    """Read a ``.oac`` file as UTF-8 text (:func:`read_bytes`, :func:`decode_source`)."""
    return decode_source(read_bytes(path), str(path))


def parse_file(path: str | Path) -> Module:
    """Read and parse one ``.oac`` file."""
    return parse_text(read_source(path), str(path))
