"""The library (``--library``: folders and files compiled as one, stale learned files left
out) and the scene (``--scene``: a name, a file, or found by the demonstration's instances),
checked against the demonstration's tracked instances (see :mod:`oacdsl.pipeline.inputs`)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from oacdsl.errors import InputError, UsageError
from oacdsl.library import Library
from oacdsl.model import Scene

__all__ = ["check_tracked", "open_library", "resolve_scene"]


def open_library(path: Path | Sequence[Path], left_out: list[str] | None = None) -> Library:
    """The library at ``path`` (a folder without its drafts/, or a file; or several of them, loaded
    as one library), as ``--library`` reads it.

    A composed OAC in a ``learned/`` folder that no longer compiles with the rest of the library
    (an OAC it calls was changed since) is left out, and ``left_out`` (when given) hears which
    file and why: what an earlier composition wrote never stops matching and composing, and
    the next composition of that name replaces the file while it is unedited
    (:mod:`oacdsl.matching.emit`). Errors in any other file stop as before.
    """
    from oacdsl.compiler.parser import read_bytes
    from oacdsl.matching.emit import LEARNED, compile_leaving_out, library_files

    files: list[Path] = []
    for one in [path] if isinstance(path, Path) else path:
        if not one.exists():
            raise InputError("no such library folder or file (give one with --library DIR)",
                             location=str(one))
        found = library_files(one)
        if not found:
            raise InputError("no .oac files in the library", location=str(one))
        files += [f for f in found if f not in files]
    sources: dict[str, str | bytes] = {str(f): read_bytes(f) for f in files}
    stale = {str(f) for f in files if f.parent.name == LEARNED} if len(files) > 1 else set()
    result, dropped = compile_leaving_out(sources, stale)
    if not result.ok:
        raise result.error()
    if left_out is not None:
        left_out += [
            f"{f} left out: it no longer compiles with the library ({why}); composing that name"
            " again replaces it while unedited"
            for f, why in dropped
        ]
    return Library(result.modules)


def resolve_scene(
    library: Library, instances: tuple[str, ...], value: str | None
) -> tuple[Library, Scene, Path | None]:
    """The scene for ``--scene value`` (a name, a .oac file, or None: found by ``instances``), the
    library it belongs to, and the scene file when it lies outside the library."""
    from oacdsl.matching.demonstration import find_scene

    if value is None or not (value.endswith(".oac") or Path(value).is_file()):
        return library, find_scene(library, instances, value), None
    from oacdsl.compiler import compile_sources, parse_file, read_source

    path = Path(value)
    if not path.is_file():
        raise InputError("no such scene file", location=value)
    inside = {Path(m.path).resolve() for m in library.modules}
    if path.resolve() in inside:  # already part of the library
        named = [d.name for d in parse_file(path).decls if isinstance(d, Scene)]
        if len(named) != 1:
            raise UsageError(f"{value}: a scene file must hold exactly one scene, it holds {len(named)}")
        return library, library.scenes[named[0]], None
    sources = {m.path: read_source(Path(m.path)) for m in library.modules if Path(m.path).is_file()}
    sources[str(path)] = read_source(path)
    result = compile_sources(sources)
    if not result.ok:
        raise result.error()
    extra = next(m for m in result.modules if m.path == str(path))
    scenes = [d for d in extra.decls if isinstance(d, Scene)]
    if len(scenes) != 1:
        raise UsageError(f"{value}: a scene file must hold exactly one scene, it holds {len(scenes)}")
    merged = Library(result.modules)
    return merged, merged.scenes[scenes[0].name], path



def check_tracked(instances: tuple[str, ...], scene: Scene, source: str, what: str) -> None:
    """The demonstration's instances are the tracked instances of the scene, no more and no fewer."""
    tracked = {i.name for i in scene.tracked()}
    unknown = sorted(set(instances) - tracked)
    if unknown:
        known = ", ".join(sorted(tracked))
        raise InputError(
            f"{what} {', '.join(unknown)} are not tracked instances of scene {scene.name!r} ({known})",
            location=source,
        )
    lacking = sorted(tracked - set(instances))
    if lacking:  # as oacc segment refuses it: a tracked instance the demonstration cannot show
        raise InputError(
            f"scene {scene.name!r}: tracked instance{'s' if len(lacking) > 1 else ''} {', '.join(lacking)}"
            f" not among the demonstration's {what} ({', '.join(sorted(instances)) or 'none'});"
            " mark an instance the recording does not track 'untracked'",
            location=source,
        )
