"""The OAC language: parser, canonical printer, validation passes, diagnostics.

>>> from oacdsl.compiler import parse_text, print_module
>>> m = parse_text("class Cup : Graspable, Container")
>>> print_module(m)
'class Cup : Container, Graspable\\n'

The grammar is ``grammar/oac.lark``; docs/language.md describes the language
and every diagnostic code.
"""

from oacdsl.compiler.checks import check_modules
from oacdsl.compiler.diagnostics import CODES, Diagnostic, Note, render, render_one
from oacdsl.compiler.loader import CompileResult, collect_files, compile_paths, compile_sources, load_library
from oacdsl.compiler.parser import parse_file, parse_source, parse_text, read_source
from oacdsl.compiler.printer import format_atom, format_decl, format_oac, print_module

__all__ = [
    "CODES",
    "CompileResult",
    "Diagnostic",
    "Note",
    "check_modules",
    "collect_files",
    "compile_paths",
    "compile_sources",
    "format_atom",
    "format_decl",
    "format_oac",
    "load_library",
    "parse_file",
    "parse_source",
    "parse_text",
    "print_module",
    "read_source",
    "render",
    "render_one",
]
