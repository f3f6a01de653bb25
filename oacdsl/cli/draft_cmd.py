"""``oacc draft RECORDING``: a draft ``.oac`` scene for a recording nobody wrote a scene for."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from oacdsl.cli.reading import add_reading_options

DESCRIPTION = """\
Write a draft .oac file for a motion-capture recording: a class per object with
a box (or cylinder) sized from its markers, a mass guess and its markers in the
object frame; a scene whose instances are exactly the recording's marker groups
(hands: Hand), with 'table : Table environment' and 'layout demonstrated'; and
the demonstration's sub-actions as comments, so that you see which OACs it
needs. Every number's comment says how it was found. Edit the draft, check it
with 'oacc compile', then let 'oacc compose --propose' draft the OACs.

The recording is read and segmented exactly as 'oacc segment' does (the KIT/MMM
hand markers become left_hand and right_hand unasked). With --library, classes
the library defines (Hand, Table, Graspable, or a class named like an object)
are used, not written again, and the draft is checked together with the
library; without it, the draft carries the base classes it needs. The draft
always compiles and is in canonical form (oacc fmt --check accepts it).
"""

EPILOG = """\
examples:
  oacc draft their_lab.c3d                         # print the draft
  oacc draft Stir.mmm.xml --library library -o stir.oac
  oacc compile stir.oac library                    # after editing it
  oacc compose Stir.mmm.xml --library stir.oac --library library --name stir --propose
  oacc draft demo.c3d --name kitchen2 -o kitchen2.oac --force   # replace an older draft
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    from oacdsl.cli.aas_options import PRESET_HELP, add_aas_options

    p = sub.add_parser(
        "draft",
        help="draft a .oac scene (classes with estimated geometry) for a recording",
        description=DESCRIPTION,
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("recording", metavar="RECORDING", help="a .c3d, .mmm.xml/.xml, .tsv or .csv file")
    p.add_argument("--name", metavar="NAME",
                   help="the scene's name (default: from the file name, as oacc compose names things)")
    p.add_argument("--library", metavar="DIR", action="append",
                   help="an OAC library (folder or file; repeatable): its classes are used, not written"
                        " again, and the draft must compile with it")
    p.add_argument("-o", "--out", metavar="FILE", help="write the draft here (default: standard output)")
    p.add_argument("--force", action="store_true", help="replace FILE if it exists")
    g = p.add_argument_group("reading and segmenting the recording (as oacc segment; values carry units)")
    g.add_argument("--format", metavar="FMT", help="read as this format, not by the file's extension")
    g.add_argument("--preset", metavar="NAME", help=PRESET_HELP)
    add_reading_options(g)
    add_aas_options(g)
    p.set_defaults(func=run, scene=None, scene_name=None)


def run(args: argparse.Namespace) -> int:
    from oacdsl.cli.aas_options import params_from_args
    from oacdsl.cli.segment_cmd import load
    from oacdsl.draft.scene import draft_scene
    from oacdsl.errors import InputError, InvalidRecording, UsageError
    from oacdsl.pipeline.inputs import default_name
    from oacdsl.segmentation import segment
    from oacdsl.segmentation.comotion import AdaptiveSettings
    from oacdsl.segmentation.tooluse import agents_of

    params = params_from_args(args)  # bad units fail before any reading
    name = args.name if args.name is not None else _free(default_name(args.recording))
    _check_name(name)
    out = Path(args.out) if args.out else None
    if out is not None and out.exists() and out.resolve() == Path(args.recording).resolve():
        raise UsageError("--out names the recording itself; give the .oac file to write", location=str(out))
    if out is not None and out.exists() and not args.force:
        raise UsageError("the file exists; give --force to replace it", location=str(out))
    if out is not None and not out.is_dir():
        from oacdsl.atomic import check_target

        check_target(out)  # a FIFO, a device, a read-only file, a name too long: refused now
    if out is not None and out.is_dir():
        raise UsageError("is a folder; --out names the .oac file to write", location=str(out))
    library, sources = _library(args.library or [])
    if library is not None and name in library.scenes:
        raise UsageError(f"the library already has a scene {name!r}; choose another with --name")
    if not Path(args.recording).exists():
        raise InputError("no such recording file", location=args.recording)
    recording = load(args)
    instances = recording.instances
    hands = [instances[i] for i in agents_of(instances, AdaptiveSettings().agent_pattern)]
    if not [g for g in instances if g not in hands]:
        shown = ", ".join(instances) or "none"
        raise InvalidRecording(f"no object with markers: the marker groups are {shown} (hands only); a scene"
                               " needs the objects' markers grouped (C3D prefixes 'cup:m1', or --preset)",
                               location=recording.source)
    if not hands:
        print(f"oacc: note: {recording.source}: no marker group is a hand (a name with 'hand' in it): every"
              " group is drafted as an object; rename the hands' groups or give --preset", file=sys.stderr)
    seg = segment(recording, params)
    target = str(out) if out is not None else "DRAFT.oac"
    libs = " ".join(f"--library {p}" for p in args.library or [])
    same = _same_scenes(library, set(instances), name) if library is not None else ""
    pick = f" --scene {name}" if same else ""  # else compose finds two scenes that fit
    hint = f"oacc compose {args.recording} --library {target} {libs}{pick} --name NAME --propose"
    draft = draft_scene(recording, seg, name, library, hands=hands, compose_hint=hint.replace("  ", " "))
    _check_compiles(draft.text, target, sources)
    if same:
        print(f"oacc: note: {same}", file=sys.stderr)
    if out is None:
        sys.stdout.write(draft.text)
        return 0
    from oacdsl.atomic import write_atomic

    try:
        write_atomic(out, draft.text)
    except OSError as error:
        raise InputError(f"cannot write: {error.strerror or error}", location=str(out)) from None
    objects = len(draft.classes) - len(hands)
    print(f"wrote {out}: scene {name}, {len(draft.classes)} instances ({len(hands)} hands,"
          f" {objects} objects), {len(draft.written)} classes drafted", file=sys.stderr)
    return 0


def _free(name: str) -> str:
    """A default scene name that is a keyword of the language (``scene.c3d``) gets ``_scene``."""
    from oacdsl.compiler.grammar import keywords

    return f"{name}_scene" if name in keywords() else name


def _check_name(name: str) -> None:
    from oacdsl.compiler.grammar import keywords, name_pattern
    from oacdsl.errors import UsageError

    if not name_pattern().fullmatch(name) or name in keywords():
        raise UsageError(f"--name {name!r}: a scene name is letters, digits and '_', not starting with"
                         " a digit, and not a keyword of the language")


def _library(paths: list[str]) -> tuple[Any, dict[str, str]]:
    """The library of ``--library`` paths (None without any) and its sources (path → text)."""
    from oacdsl.compiler import compile_sources, read_source
    from oacdsl.errors import InputError
    from oacdsl.library import Library
    from oacdsl.matching.emit import library_files

    if not paths:
        return None, {}
    sources: dict[str, str] = {}
    for p in paths:
        path = Path(p)
        if not path.exists():
            raise InputError("no such library folder or file", location=p)
        files = library_files(path)
        if not files:
            raise InputError("no .oac files in the library", location=p)
        sources.update({str(f): read_source(f) for f in files})
    result = compile_sources(sources)
    if not result.ok:
        raise result.error()
    return Library(result.modules), sources


def _check_compiles(text: str, target: str, sources: dict[str, str]) -> None:
    """The draft compiles (with the library's sources); a failure here is a bug of the drafter."""
    from oacdsl.compiler import compile_sources
    from oacdsl.errors import LanguageError

    result = compile_sources({**sources, target: text})
    if not result.ok:
        first = result.errors[0]
        raise LanguageError(f"{first.header()} (the draft does not compile; nothing was written)")


def _same_scenes(library: Any, instances: set[str], name: str) -> str:
    """A note when scenes of the library have the recording's instances ('' when none has)."""
    same = sorted(s.name for s in library.scenes.values() if {i.name for i in s.tracked()} == instances)
    if not same:
        return ""
    return (f"scene {', '.join(same)} of the library has the same instances; compose with --scene {name}"
            " to use the draft's")
