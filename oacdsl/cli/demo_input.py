"""What ``oacc match`` and ``oacc compose`` share: reading a demonstration and a library.

A demonstration is a motion-capture recording, segmented here with the
project's defaults (the options are those of ``oacc segment``), or a
segmentation already made (the ``.json`` that ``oacc segment --json`` prints).
The library is every ``.oac`` file under ``--library`` (default ``library/``)
except its ``drafts/`` folder; the scene is ``--scene NAME`` of the library, a
``.oac`` file holding one scene, or the library's scene whose tracked instances
are the recording's marker groups.
"""

from __future__ import annotations

import argparse
import json
from dataclasses import dataclass
from pathlib import Path

from oacdsl.cli.segment_cmd import PRESET_HELP, add_aas_options
from oacdsl.errors import InputError, UsageError
from oacdsl.library import Library
from oacdsl.model import Scene
from oacdsl.segmentation.params import DEFAULT_MODE
from oacdsl.segmentation.result import Keyframe, Segmentation
from oacdsl.world import WorldState

__all__ = [
    "Inputs", "add_input_options", "load_inputs", "open_library", "read_segmentation_json", "resolve_scene",
]

def add_input_options(p: argparse.ArgumentParser) -> None:
    """The demonstration, library and scene arguments, and the segmentation options."""
    p.add_argument("recording", metavar="RECORDING",
                   help="motion capture (.c3d, .mmm.xml, .tsv, .csv) or a segmentation"
                        " (the .json of oacc segment --json)")
    p.add_argument("--library", metavar="DIR", default="library",
                   help="the OAC library: a folder (drafts/ left out) or a file (default: library/)")
    p.add_argument("--scene", metavar="NAME|FILE",
                   help="the scene of the demonstration (default: the library's scene whose tracked"
                        " instances are the recording's marker groups)")
    p.add_argument("--paper", action="store_true",
                   help="match by the paper's rule alone (pre holds before, effects after); default: strict,"
                        " the effects must also account for every changed relation")
    g = p.add_argument_group("reading and segmenting a recording (as oacc segment; values carry units)")
    g.add_argument("--format", metavar="FMT",
                   help="read as this format (c3d, mmm, tsv, csv), not by the file's extension")
    g.add_argument("--preset", metavar="NAME", help=PRESET_HELP)
    add_aas_options(g)


@dataclass(frozen=True)
class Inputs:
    library: Library
    library_path: Path
    scene: Scene
    segmentation: Segmentation
    source: str
    #: The --scene FILE when it lies outside the library (its instances are unknown there).
    outside_scene: Path | None = None


def read_segmentation_json(path: Path) -> Segmentation:
    """A segmentation from the document ``oacc segment --json`` prints."""
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except OSError as error:
        raise InputError(f"cannot read: {error.strerror or error}", location=str(path)) from error
    except (UnicodeDecodeError, json.JSONDecodeError) as error:
        raise InputError(f"not a JSON document: {error}", location=str(path)) from error
    try:
        instances = tuple(str(i) for i in doc["instances"])
        keyframes = tuple(
            Keyframe(int(k["frame"]), float(k["time_s"]),
                     WorldState.of(instances, [(str(a), str(b)) for a, b in k["relations"]]))
            for k in doc["keyframes"]
        )
        return Segmentation(str(doc.get("recording", path)), float(doc["rate_hz"]), int(doc["frames"]),
                            instances, keyframes, dict(doc.get("parameters", {})))
    except (KeyError, TypeError, ValueError) as error:
        what = f"missing key {error}" if isinstance(error, KeyError) else str(error)
        raise InputError(f"not a segmentation (oacc segment --json): {what}", location=str(path)) from error


def _library(path: Path) -> Library:
    from oacdsl.compiler import load_library
    from oacdsl.matching.emit import library_files

    if not path.exists():
        raise InputError("no such library folder or file (give one with --library DIR)", location=str(path))
    files = library_files(path)
    if not files:
        raise InputError("no .oac files in the library", location=str(path))
    return load_library(files)


def _scene(
    library: Library, instances: tuple[str, ...], value: str | None
) -> tuple[Library, Scene, Path | None]:
    """The scene (by name, from a file, or found by its instances), the library it belongs to,
    and the scene file when it lies outside the library."""
    from oacdsl.matching.demonstration import find_scene

    if value is not None and (value.endswith(".oac") or Path(value).is_file()):
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
    return library, find_scene(library, instances, value), None


def load_inputs(args: argparse.Namespace) -> Inputs:
    """Library, scene and segmentation for a ``match``/``compose`` command line."""
    library_path = Path(args.library)
    library = _library(library_path)
    source = Path(args.recording)
    if source.suffix.lower() == ".json":
        given = [f"--{k}" for k in ("format", "preset", "distance", "speed", "frames", "merge")
                 if getattr(args, k) is not None] + (["--mode"] if args.mode != DEFAULT_MODE else [])
        if given:
            raise UsageError(f"{', '.join(given)}: these read and segment a recording; {source} is a"
                             " segmentation already (.json)")
        segmentation = read_segmentation_json(source)
        library, scene, outside = _scene(library, segmentation.instances, args.scene)
    else:
        from oacdsl.cli.segment_cmd import apply_grouping, params_from_args
        from oacdsl.segmentation import segment
        from oacdsl.segmentation.grouping import apply_scene_groups
        from oacdsl.segmentation.readers import read_recording

        params = params_from_args(args)  # bad units fail before any reading
        recording = apply_grouping(read_recording(source, args.format), args.preset)
        library, scene, outside = _scene(library, recording.instances, args.scene)
        if any(i.markers for i in scene.instances):
            recording = apply_scene_groups(recording, scene)
        segmentation = segment(recording, params)
    tracked = {i.name for i in scene.tracked()}
    unknown = sorted(set(segmentation.instances) - tracked)
    if unknown:
        raise InputError(f"the demonstration's instances {', '.join(unknown)} are not tracked instances of"
                         f" scene {scene.name!r}", location=str(source))
    return Inputs(library, library_path, scene, segmentation, str(source), outside)


def open_library(path: Path) -> Library:
    """The library at ``path`` (a folder without its drafts/, or a file), as ``--library`` reads it."""
    return _library(path)


def resolve_scene(
    library: Library, instances: tuple[str, ...], value: str | None
) -> tuple[Library, Scene, Path | None]:
    """The scene for ``--scene value`` (a name, a .oac file, or None: found by ``instances``), the
    library it belongs to, and the scene file when it lies outside the library."""
    return _scene(library, instances, value)
