"""What ``oacc reproduce``, ``match`` and ``compose`` start from: demonstration, library, scene.

**The demonstration** is a motion-capture recording (``--format``, ``--preset``
as ``oacc segment``) or, for ``match`` and ``compose``, a segmentation already
made (the ``.json`` that ``oacc segment --json`` prints). With no recording
given, ``reproduce`` runs on the paper's dough task: ``data/dough.c3d`` of the
source tree (seed 2013 of ``oacc synth dough``) when the package runs from a
checkout or an editable install, where ``data/`` sits next to the ``oacdsl``
package. An installed wheel carries no ``data/``; then the same demonstration is
generated in memory from the same seed
(:func:`~oacdsl.segmentation.synth.dough_demonstration`, deterministic, about a
second), which the synth tests check equals the bundled file.

**The library.** ``--library DIR`` (``reproduce``'s default: ``library/`` in the
working folder, else the source tree's ``library/``), every ``.oac`` file under it
except ``drafts/``, or one file; ``match`` and ``compose`` take several (a drafted scene
and a library: one library). **The scene** is ``--scene NAME`` of the library, a
``.oac`` file with one scene, or the library's scene whose tracked instances are
the recording's marker groups; every instance of the demonstration must be one of
them. Everything here is checked before anything is written; each problem is a
one-line error (:mod:`oacdsl.errors`).
"""

from __future__ import annotations

import dataclasses
import json
import re
import unicodedata
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from oacdsl.errors import InputError, UsageError
from oacdsl.library import Library
from oacdsl.matching.agency import Travel, hand_travel
from oacdsl.model import Scene
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import Keyframe, Segmentation
from oacdsl.segmentation.shapes import ShapeModel
from oacdsl.world import WorldState

__all__ = [
    "BUNDLED_NAME",
    "Inputs",
    "bundled_recording",
    "default_library",
    "default_name",
    "load_inputs",
    "open_library",
    "read_segmentation_json",
    "resolve_scene",
    "source_root",
]

#: The bundled demonstration, relative to the source tree.
BUNDLED_NAME = "data/dough.c3d"


def source_root() -> Path | None:
    """The source tree the package runs from (a checkout or an editable install), else None."""
    root = Path(__file__).resolve().parents[2]
    return root if (root / "pyproject.toml").is_file() and (root / "oacdsl").is_dir() else None


def bundled_recording() -> tuple[Recording, str]:
    """The bundled dough demonstration and where it came from (the file, or ``synth:dough``)."""
    root = source_root()
    path = root / BUNDLED_NAME if root is not None else None
    if path is not None and path.is_file():
        from oacdsl.segmentation.readers import read_recording

        return read_recording(path), _shown(path)
    from oacdsl.segmentation.synth import DEFAULT_SEED, dough_demonstration

    return dough_demonstration(DEFAULT_SEED).recording, f"synth:dough (seed {DEFAULT_SEED}, generated)"


def _shown(path: Path) -> str:
    """``path`` relative to the working folder when it lies inside it."""
    try:
        return str(path.resolve().relative_to(Path.cwd().resolve()))
    except ValueError:
        return str(path)


def default_library() -> Path:
    """``library/`` in the working folder, else the source tree's ``library/``."""
    here = Path("library")
    root = source_root()
    if here.is_dir() or root is None or not (root / "library").is_dir():
        return here
    return root / "library"


def default_name(source: str) -> str:
    """A name for the composed OAC from the recording's file name: ``Pour-01.c3d`` → ``pour_01``,
    ``Crêpe.c3d`` → ``crepe`` (ASCII letters, digits and ``_``; at most 200 characters)."""
    stem = Path(source.split(" ")[0].split(":")[-1]).name
    for suffix in (".mmm.xml", ".xml", ".c3d", ".tsv", ".csv", ".json"):
        if stem.lower().endswith(suffix):
            stem = stem[: -len(suffix)]
            break
    ascii_stem = unicodedata.normalize("NFKD", stem.lower()).encode("ascii", "ignore").decode("ascii")
    name = re.sub(r"[^a-z0-9]+", "_", ascii_stem).strip("_") or "demonstration"
    name = name if name[0].isalpha() else f"demo_{name}"
    return name[:200].rstrip("_")  # an ASCII identifier, and NAME.oac a file name of any file system


@dataclass(frozen=True)
class Inputs:
    """The checked inputs: library, scene, and the demonstration as a recording or a segmentation."""

    library: Library
    library_path: Path
    scene: Scene
    source: str
    #: How a recording is (to be) segmented.
    params: AasParams
    #: The motion capture, grouped by the scene's markers (None when a segmentation was given).
    recording: Recording | None = None
    #: A segmentation given instead of a recording (``.json``).
    segmentation: Segmentation | None = None
    #: The --scene FILE when it lies outside the library (its instances are unknown there).
    outside_scene: Path | None = None
    #: Every --library given (folders or files, loaded as one library); ``library_path`` is the
    #: first folder among them (else the first).
    library_paths: tuple[Path, ...] = ()
    #: Learned files left out because they no longer compile (:func:`open_library`), one line each.
    warnings: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if (self.recording is None) == (self.segmentation is None):
            raise TypeError("Inputs holds a recording or a segmentation, exactly one")

    def motion_capture(self) -> Recording:
        """The recording; :class:`UsageError` when the demonstration was a segmentation."""
        if self.recording is None:
            raise UsageError(f"{self.source}: a segmentation (.json); this needs the motion capture")
        return self.recording

    def unmerged(self) -> Callable[[], Segmentation] | None:
        """The recording segmented without the merge window, on demand (None for a segmentation
        given as .json): when each relation of a merged keyframe changed
        (:func:`oacdsl.matching.demonstration.match_segmentation`)."""
        if self.recording is None:
            return None
        recording, params = self.recording, dataclasses.replace(self.params, merge_s=0.0)
        shapes = self.shapes()

        def run() -> Segmentation:
            from oacdsl.segmentation import segment

            return segment(recording, params, shapes=shapes)

        return run

    def travel(self) -> Travel | None:
        """How far each instance moved between two frames (None for a segmentation given as
        .json): a tie between matches broken by which hand moved
        (:func:`oacdsl.matching.demonstration.match_segmentation`)."""
        if self.recording is None:
            return None
        return hand_travel(self.recording)

    def shapes(self) -> dict[str, ShapeModel] | None:
        """The scene's shapes when contacts are measured from geometry (``params.contacts``), else None."""
        if self.params.contacts != "geometry":
            return None
        from oacdsl.segmentation.shapes import scene_shapes

        return scene_shapes(self.library, self.scene)

    def segmented(self) -> Segmentation:
        """The segmentation given, or the recording segmented with ``params``."""
        if self.segmentation is not None:
            return self.segmentation
        from oacdsl.segmentation import segment

        return segment(self.motion_capture(), self.params, shapes=self.shapes())


def read_segmentation_json(path: Path) -> Segmentation:
    """A segmentation from the document ``oacc segment --json`` prints."""
    from oacdsl.documents import read_document

    text = read_document(path, "a segmentation (oacc segment --json)")
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as error:
        raise InputError(f"not a JSON document: {error}", location=str(path)) from error
    except RecursionError:
        raise InputError("nested too deeply; not a segmentation", location=str(path)) from None
    try:
        instances = tuple(str(i) for i in doc["instances"])
        keyframes = tuple(
            Keyframe(
                int(k["frame"]),
                float(k["time_s"]),
                WorldState.of(instances, [(str(a), str(b)) for a, b in k["relations"]]),
            )
            for k in doc["keyframes"]
        )
        return Segmentation(
            str(doc.get("recording", path)),
            float(doc["rate_hz"]),
            int(doc["frames"]),
            instances,
            keyframes,
            dict(doc.get("parameters", {})),
        )
    except (KeyError, TypeError, ValueError) as error:
        what = f"missing key {error}" if isinstance(error, KeyError) else str(error)
        raise InputError(f"not a segmentation (oacc segment --json): {what}", location=str(path)) from error


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


def load_inputs(
    recording: str | Path | None,
    library: str | Path | Sequence[str | Path] | None,
    scene: str | None,
    params: AasParams,
    *,
    fmt: str | None = None,
    preset: str | None = None,
    allow_truncated: bool = False,
    segmentations: bool = False,
    note: Callable[[str], None] | None = None,
) -> Inputs:
    """Read and check everything (see the module docstring); raises OacError subclasses.

    ``recording`` None: the bundled demonstration. ``allow_truncated``: a C3D file cut
    short is read as far as its frames are complete, with a warning (else an error).
    ``segmentations``: a ``.json``
    recording is a segmentation (``match``, ``compose``). ``preset`` None: a marker
    set recognised in a recording file groups it, and ``note`` hears of it; ``"none"``:
    the file's own groups. No scene that fits the demonstration is a
    :class:`~oacdsl.errors.MatchingError`.
    """
    if library is None:
        paths = [default_library()]
    else:
        paths = [Path(library)] if isinstance(library, (str, Path)) else [Path(p) for p in library]
    library_path = next((p for p in paths if p.is_dir()), paths[0])  # where learned/ goes
    left_out: list[str] = []
    lib = open_library(paths, left_out)
    rec: Recording | None = None
    seg: Segmentation | None = None
    if recording is None:
        if fmt or preset or allow_truncated:
            raise UsageError(
                "--format, --preset and --allow-truncated need a RECORDING (the bundled one needs none)"
            )
        rec, source = bundled_recording()
    elif segmentations and Path(recording).suffix.lower() == ".json":
        if fmt or preset or allow_truncated:
            raise UsageError(
                f"--format, --preset, --allow-truncated: these read a recording; {recording} is"
                " a segmentation already (.json)"
            )
        source = str(recording)
        seg = read_segmentation_json(Path(recording))
    else:
        from oacdsl.segmentation.readers import read_recording

        source = str(recording)
        if not Path(recording).exists():  # a special file is refused by read_recording, unopened
            raise InputError("no such recording file", location=source)
        from oacdsl.segmentation.grouping import group_recording, recognised_note

        read = read_recording(recording, fmt, allow_truncated=allow_truncated)
        rec, recognised = group_recording(read, preset)
        if recognised is not None and note is not None:
            note(recognised_note(rec, recognised))
    instances = tuple(rec.instances if rec is not None else seg.instances if seg is not None else ())
    lib, sc, outside = resolve_scene(lib, instances, scene)
    if rec is not None and any(i.markers or i.ignored for i in sc.instances):  # ignored: dropped
        from oacdsl.segmentation.grouping import apply_scene_groups

        rec = apply_scene_groups(rec, sc)
        instances = tuple(rec.instances)
    _check_tracked(instances, sc, source, "marker groups" if rec is not None else "instances")
    if rec is not None and not instances:
        raise InputError("the recording has no marker groups to segment", location=source)
    return Inputs(lib, library_path, sc, source, params, rec, seg, outside, tuple(paths), tuple(left_out))


def _check_tracked(instances: tuple[str, ...], scene: Scene, source: str, what: str) -> None:
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
