"""Find, parse and validate the ``.oac`` files of a library.

A library is every ``.oac`` file under the given paths (folders are searched
recursively, in sorted order), merged: a file may use the classes, instances
and OACs of any other. There is no ``import``.
"""

from __future__ import annotations

import contextlib
import gc
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from oacdsl.compiler.checks import check_modules
from oacdsl.compiler.diagnostics import Diagnostic, language_error, sort_diagnostics
from oacdsl.compiler.parser import decode_source, normalize_newlines, parse_source, read_bytes
from oacdsl.errors import InputError, LanguageError, SourceEncodingError
from oacdsl.library import Library
from oacdsl.model import Module

__all__ = [
    "LIBRARY_MARK",
    "NEED_EVERY_FILE",
    "REPORT_MARK",
    "CompileResult",
    "collect_files",
    "compile_paths",
    "compile_sources",
    "load_library",
    "oac_files",
]

#: A folder below a library folder that holds a file of this name is a library of its own
#: (``library/kit/LIBRARY``): searching the folder above leaves it out.
LIBRARY_MARK = "LIBRARY"
#: A folder holding a file of this name is an ``oacc reproduce`` report folder (``--out``, which
#: :mod:`oacdsl.pipeline.publish` marks): its ``NAME.oac`` copies are results, not the library's.
REPORT_MARK = ".oacdsl-report"


def _left_out(folder: Path) -> bool:
    """A library of its own, or a report folder (marked, or of an older oacdsl: ``current`` → ``runs/``)."""
    if (folder / LIBRARY_MARK).is_file() or (folder / REPORT_MARK).is_file():
        return True
    return (folder / "current").is_symlink() and (folder / "runs").is_dir()


def oac_files(folder: Path) -> list[Path]:
    """The ``.oac`` files under ``folder``, sorted, leaving out every subfolder that is a
    library of its own (it holds a file called :data:`LIBRARY_MARK`) or a report folder of
    ``oacc reproduce`` (:data:`REPORT_MARK`)."""
    found = []
    for p in folder.rglob("*.oac"):
        parents = p.relative_to(folder).parents
        inside = [q for q in parents if q.parts]
        if p.is_file() and not any(_left_out(folder / q) for q in inside):
            found.append(p)
    return sorted(found)


@dataclass
class CompileResult:
    """What compiling a set of files found: modules, diagnostics, and the texts read."""

    modules: list[Module] = field(default_factory=list)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    sources: dict[str, str] = field(default_factory=dict)

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.is_error]

    @property
    def ok(self) -> bool:
        return not self.errors

    @property
    def undecodable(self) -> list[str]:
        """The files that are not UTF-8 text (E024)."""
        return sorted({d.span.file for d in self.diagnostics if d.code == "E024" and d.span is not None})

    def error(self) -> LanguageError:
        """The :class:`LanguageError` for these diagnostics (raise it when not ``ok``).

        A :class:`~oacdsl.errors.SourceEncodingError` (exit status 2) when a file is not UTF-8.
        """
        error = language_error(self.diagnostics, self.sources)
        if self.undecodable:
            return SourceEncodingError(str(error), diagnostics=error.diagnostics, rendered=error.rendered)
        return error


def collect_files(paths: Sequence[str | Path]) -> list[Path]:
    """The ``.oac`` files named by ``paths`` (files as given, folders searched recursively,
    leaving out subfolders that are libraries of their own: :func:`oac_files`).

    :class:`~oacdsl.errors.InputError` for a missing path or a folder without ``.oac`` files.
    """
    if not paths:
        raise InputError("no library path given")
    files: list[Path] = []
    for raw in paths:
        path = Path(raw)
        if path.is_dir():
            try:
                found = oac_files(path)
            except OSError as error:
                raise InputError(f"cannot list: {error.strerror or error}", location=str(path)) from None
            if not found:
                raise InputError("folder contains no .oac files", location=str(path))
            files += found
        elif path.is_file():
            files.append(path)
        elif path.exists():
            raise InputError("neither a file nor a folder", location=str(path))
        else:
            raise InputError("no such file or folder", location=str(path))
    unique: dict[Path, Path] = {}
    for f in files:
        unique.setdefault(f.resolve(), f)
    return list(unique.values())


#: Diagnostics about a name or declaration that a file with a syntax error may hold: left
#: out when one did not parse (unknown class, instance, variable or OAC, environment
#: instance, graspable instance without a grasp), so they are not reported by mistake.
NEED_EVERY_FILE = frozenset({"E003", "E004", "E005", "E013", "E021", "W004"})


def compile_sources(sources: Mapping[str, str | bytes]) -> CompileResult:
    """Parse and validate texts (path → text, or the file's bytes, decoded as UTF-8) as one library.

    Every problem is reported at once: a file that is not UTF-8 (E024) or has
    a syntax error (one per file: its parse stops there) leaves the others to
    be parsed, and the semantic checks run over the files that parsed. While a
    file is broken, diagnostics about names it may define
    (:data:`NEED_EVERY_FILE`) are left out.
    """
    result = CompileResult()
    broken = False
    with gc_paused():
        for path, source in sources.items():
            if isinstance(source, bytes):
                try:
                    text = decode_source(source, path)
                except SourceEncodingError as error:
                    result.sources[path] = source.decode("utf-8", errors="replace")
                    result.diagnostics += list(error.diagnostics)
                    broken = True
                    continue
            else:
                text = source
            text = normalize_newlines(text)  # CR LF and CR line ends count as lines, as in an editor
            result.sources[path] = text
            try:
                module, warnings = parse_source(text, path)
            except LanguageError as error:
                result.diagnostics += list(error.diagnostics)
                broken = True
                continue
            result.modules.append(module)
            result.diagnostics += warnings
        checked = check_modules(result.modules)
        if broken:
            checked = [d for d in checked if d.code not in NEED_EVERY_FILE]
        result.diagnostics += checked
    result.diagnostics = sort_diagnostics(result.diagnostics)
    return result


@contextlib.contextmanager
def gc_paused() -> Iterator[None]:
    """Pause Python's cyclic garbage collector for the block, then restore its previous state.

    Parsing allocates many small objects that all stay alive (the model) and
    make no reference cycles; the collector's repeated scans of them cost about
    a third of the time on a large library and grow with its size. Reference
    counting still frees everything as usual; a collection runs at the next
    allocation threshold after the block.
    """
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            gc.enable()


def compile_paths(paths: Sequence[str | Path]) -> CompileResult:
    """Read, parse and validate the library at ``paths`` (I/O problems raise InputError)."""
    files = collect_files(paths)
    return compile_sources({str(f): read_bytes(f) for f in files})


def load_library(paths: Sequence[str | Path]) -> Library:
    """The validated library at ``paths`` (files or folders, recursive ``*.oac``).

    Raises :class:`~oacdsl.errors.LanguageError` when there are errors (its str
    is the first error line ``file:line:col: error[CODE]: message``; it carries
    all ``.diagnostics``) and :class:`~oacdsl.errors.InputError` when a path
    cannot be read. Warnings do not stop loading (:func:`compile_paths` returns them).
    """
    if isinstance(paths, str | Path):
        paths = [paths]
    result = compile_paths(paths)
    if not result.ok:
        raise result.error()
    return Library(result.modules)
