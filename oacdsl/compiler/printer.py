"""The canonical printer: one layout for every model, comments kept.

Deterministic: the model already keeps parents, instance classes, instances
and atoms sorted; the printer keeps declarations, parameters, markers and
steps in their order (a ``together { … }`` block's too: the runtime runs them as written). Layout rules:

* four spaces of indentation, one blank line between declarations except
  between consecutive one-line ``class`` or ``grasp`` declarations;
* instances one per line with their colons aligned;
* ``pre``/``effect``/``execute`` aligned on one column; a section goes one
  atom per line when an atom carries a comment or the line passes 100 columns;
  parameters likewise go one per line when one carries a comment;
* leading comments on their own lines above the node, notes after it.

``parse_text(print_module(m)) == m`` and printing is idempotent (tests check both).

The words (names, numbers, quantities, atoms, comments) are in
:mod:`~oacdsl.compiler.printer_words`, the layout of classes, scenes and grasps in
:mod:`~oacdsl.compiler.printer_scene`, that of OACs in :mod:`~oacdsl.compiler.printer_oac`.
"""

from __future__ import annotations

from oacdsl.compiler.printer_oac import oac_lines
from oacdsl.compiler.printer_scene import class_lines, grasp_lines, scene_lines
from oacdsl.compiler.printer_words import comment_lines, format_atom, format_quantity
from oacdsl.errors import LanguageError
from oacdsl.model import Decl, Grasp, Module, Oac, ObjectClass, Scene

__all__ = ["format_atom", "format_decl", "format_oac", "format_quantity", "print_module"]


def _decl_lines(decl: Decl) -> list[str]:
    if isinstance(decl, ObjectClass):
        body = class_lines(decl)
    elif isinstance(decl, Scene):
        body = scene_lines(decl)
    elif isinstance(decl, Grasp):
        body = grasp_lines(decl)
    elif isinstance(decl, Oac):
        body = oac_lines(decl)
    else:
        raise LanguageError(f"cannot print {type(decl).__name__}: not a declaration")
    return comment_lines(decl.comments, "") + body


def format_decl(decl: Decl) -> str:
    """One declaration in canonical form (with its comments), ending in a newline."""
    return "\n".join(_decl_lines(decl)) + "\n"


def format_oac(oac: Oac) -> str:
    """One OAC in canonical form, ending in a newline (what the composer writes)."""
    return format_decl(oac)


def _tight(prev: Decl, decl: Decl) -> bool:
    if any(isinstance(d, ObjectClass) and d.geometry is not None for d in (prev, decl)):
        return False
    return isinstance(decl, ObjectClass | Grasp) and type(prev) is type(decl) and not decl.comments


def print_module(module: Module) -> str:
    """The whole file in canonical form ("" for a file with nothing in it)."""
    if not module.decls:
        only = comment_lines((*module.comments, *module.trailing), "")
        return "\n".join(only) + "\n" if only else ""
    lines: list[str] = comment_lines(module.comments, "")
    if lines:
        lines.append("")
    prev: Decl | None = None
    for decl in module.decls:
        if prev is not None and not _tight(prev, decl):
            lines.append("")
        lines += _decl_lines(decl)
        prev = decl
    if module.trailing:
        lines.append("")
        lines += comment_lines(module.trailing, "")
    return "\n".join(lines) + "\n"
