"""Write composed OACs and drafts back into the library as canonical ``.oac`` text.

The text comes from the canonical printer (:func:`oacdsl.compiler.print_module`), so
``parse(text)`` gives the same OAC back; the provenance notes become trailing
comments. Before anything is written the new file is compiled together with
the rest of the library (it must compile cleanly, drafts excepted: their
placeholder skill is reported on purpose), then written to a temporary file in
the same folder and renamed over the target (``os.replace``): never half a file.

Composing the same demonstration again never adds a duplicate. When the target
file already holds an OAC with the same meaning (comments, notes and layout
aside), nothing is written (``unchanged``). When it holds something else, that
may be a learned OAC its author has since reviewed or edited, so it is kept and
the call fails, naming the differences, unless ``force`` (``--force``) asks to
replace it (``replaced``). A composed OAC's file (one written with a ``header``)
starts with a fingerprint of the rest of its text (:data:`FINGERPRINT`): a file whose
fingerprint still matches was not edited since it was written, so a new composition
replaces it without ``force`` (a library change or an upgrade that changes the
composition does not stop ``oacc reproduce``); any edit keeps it.
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Literal

from oacdsl.atomic import write_atomic
from oacdsl.errors import InputError, LanguageError, MatchingError
from oacdsl.model import Module, Oac, atom_text

if TYPE_CHECKING:
    from oacdsl.compiler import CompileResult

__all__ = [
    "DRAFTS",
    "FINGERPRINT",
    "LEARNED",
    "Emitted",
    "compile_leaving_out",
    "differences",
    "emit",
    "fingerprinted",
    "library_files",
    "render",
    "unedited",
]

#: Subfolders of a library folder: composed OACs, and drafts for review.
LEARNED, DRAFTS = "learned", "drafts"

Status = Literal["written", "unchanged", "replaced"]


@dataclass(frozen=True)
class Emitted:
    """What ``emit`` did: the file, ``written`` / ``unchanged`` / ``replaced``, what changed."""

    path: Path
    status: Status
    text: str
    changes: str = ""


#: The first line of a composed OAC's file, followed by the first 16 hex digits of the SHA-256
#: of the rest of the file (UTF-8).
FINGERPRINT = "# Written by oacdsl; replaced by the next composition while unedited: "


def _digest(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def fingerprinted(text: str) -> str:
    """``text`` with the fingerprint line in front."""
    return f"{FINGERPRINT}{_digest(text)}\n{text}"


def unedited(target: Path) -> bool:
    """Whether ``target`` starts with a fingerprint that matches the rest of its text."""
    try:
        text = target.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError):
        return False
    first, newline, rest = text.partition("\n")
    return bool(newline) and first.startswith(FINGERPRINT) and first[len(FINGERPRINT):] == _digest(rest)


def library_files(library: Path) -> list[Path]:
    """The ``.oac`` files of a library folder (or the file itself), drafts and the
    subfolders that are libraries of their own left out (``oac_files``)."""
    from oacdsl.compiler.loader import oac_files

    if library.is_file():
        return [library]
    return [p for p in oac_files(library) if DRAFTS not in p.relative_to(library).parts[:-1]]


def compile_leaving_out(
    sources: Mapping[str, str | bytes], droppable: set[str]
) -> tuple[CompileResult, list[tuple[str, str]]]:
    """Compile ``sources`` (path → text) as one library, leaving out the files of ``droppable``
    (learned OACs) that have errors, until none has: the result and (file, its first error) for
    each file left out. A learned file that calls one left out goes too."""
    from oacdsl.compiler import compile_sources

    sources = dict(sources)
    dropped: list[tuple[str, str]] = []
    while True:
        result = compile_sources(sources)
        broken = sorted({d.span.file for d in result.errors if d.span is not None} & droppable)
        if result.ok or not broken:
            return result, dropped
        for f in broken:
            first = next(d for d in result.errors if d.span is not None and d.span.file == f)
            dropped.append((f, first.header()))
            del sources[f]
            droppable = droppable - {f}


def render(decls: Sequence[Oac], path: str, header: Sequence[str] = ()) -> str:
    """The canonical text of a file holding ``decls``; ``header`` becomes the first
    declaration's leading comment lines."""
    from oacdsl.compiler import print_module

    first, *rest = decls
    if header:
        first = first.model_copy(update={"comments": (*header, *first.comments)})
    return print_module(Module(path=path, decls=(first, *rest)))


def differences(old: Oac, new: Oac) -> str:
    """``pre +a <-> b -c <-> d; effect …; steps changed`` — what differs, for messages."""
    parts = ["parameters differ"] if old.params != new.params else []
    for label, a, b in (("pre", old.pre, new.pre), ("effect", old.effect, new.effect)):
        if a == b:
            continue
        plus = [f"+{atom_text(x)}" for x in b if x not in a]
        minus = [f"-{atom_text(x)}" for x in a if x not in b]
        parts.append(f"{label} " + " ".join(plus + minus))
    if (old.steps, old.skill) != (new.steps, new.skill):
        parts.append("steps differ")
    return "; ".join(parts) or "same meaning"


def _existing(target: Path) -> tuple[Oac, ...] | None:
    """The OACs of the file at ``target`` (None when it is not a valid .oac file)."""
    from oacdsl.compiler import parse_text, read_source

    try:
        module = parse_text(read_source(target), str(target))
    except (LanguageError, InputError):
        return None
    return tuple(d for d in module.decls if isinstance(d, Oac)) if len(module.decls) else ()


def _check(library: Path | None, target: Path, text: str, decls: Sequence[Oac], drafts: bool,
           also: Sequence[Path], pending: Mapping[Path, str]) -> None:
    """Compile ``text`` (to be ``target``) with the library, the folders and files ``also`` and the
    files about to be written (``pending``: path → text); raise on any error (with
    ``drafts``: on any error but the placeholder skill's)."""
    from oacdsl.compiler import read_source

    files = library_files(library) if library is not None and library.exists() else []
    others = [f for f in files if f.resolve() != target.resolve()]
    sources = {str(f): read_source(f) for f in others}
    for folder in (*also, *((target.parent,) if drafts else ())):  # drafts a composition may call
        for f in sorted(folder.glob("*.oac")) if folder.is_dir() else [folder] if folder.is_file() else []:
            if f.resolve() != target.resolve():
                sources.setdefault(str(f), read_source(f))
    names = {d.name for d in decls}
    for f in others:
        for oac in _existing(f) or ():
            if oac.name in names:
                raise MatchingError(
                    f"an OAC named {oac.name!r} is already defined in {f}; choose another --name"
                )
    for path, pending_text in pending.items():
        if path.resolve() != target.resolve():
            sources[str(path)] = pending_text
    sources[str(target)] = text
    # learned files that no longer compile (the library changed under them) do not stop a new one
    stale = {str(f) for f in others if f.parent.name == LEARNED}
    result, _ = compile_leaving_out(sources, stale)
    errors = [d for d in result.errors if not (drafts and d.code == "E016")]
    if errors:
        raise LanguageError(
            f"{errors[0].header()} (the new file does not compile with the library; nothing was written)"
        )


def emit(
    decls: Sequence[Oac],
    target: Path,
    *,
    library: Path | None,
    header: Sequence[str] = (),
    force: bool = False,
    drafts: bool = False,
    also: Sequence[Path] = (),
    pending: Mapping[Path, str] | None = None,
    write: bool = True,
) -> Emitted:
    """Write ``decls`` (one composed OAC, or drafts) to ``target`` after checking them
    against ``library`` (a folder or file; None: no check) and the ``.oac`` files in the
    folders ``also`` (or those files themselves); see the module docstring. ``drafts``: the placeholder skill
    ``TODO`` is allowed. ``pending``: files not written yet that the check must include
    (path → text). ``write=False`` checks everything and writes nothing."""
    if not decls:
        raise MatchingError("nothing to write")
    text = render(decls, str(target), header)
    if header:
        text = fingerprinted(text)
    status: Status = "written"
    changes = ""
    if target.exists():
        old = _existing(target)
        if old is not None and old == tuple(decls):
            return Emitted(target, "unchanged", text)
        changes = (
            differences(old[0], decls[0])
            if old and len(old) == 1 and len(decls) == 1
            else "different declarations"
        )
        if not force and not (header and unedited(target)):
            raise MatchingError(
                f"{target} already holds {'a different ' + repr(decls[0].name) if old else 'other content'}"
                f" ({changes}); pass --force to replace it, or choose another --name / -o",
                location=None,
            )
        status = "replaced"
    _check(library, target, text, decls, drafts, also, pending or {})
    if write:
        _write(target, text)
    return Emitted(target, status, text, changes)


def _write(target: Path, text: str) -> None:
    """Write ``text`` to a temporary file next to ``target`` and rename it over ``target``."""
    try:
        write_atomic(target, text)
    except OSError as error:
        raise InputError(f"cannot write: {error.strerror or error}", location=str(target)) from error
