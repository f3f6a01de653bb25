"""What ``oacc reproduce`` starts from: the demonstration, the library and the scene.

**The bundled demonstration.** With no recording given, the pipeline runs on the
paper's dough task: ``data/dough.c3d`` of the source tree (seed 2013 of
``oacc synth dough``) when the package runs from a checkout or an editable install,
where ``data/`` sits next to the ``oacdsl`` package. An installed wheel carries no
``data/``; then the same demonstration is generated in memory from the same seed
(:func:`~oacdsl.segmentation.synth.dough_demonstration`, deterministic, about a
second), which the synth tests check equals the bundled file.

**The library.** ``--library DIR`` (default: ``library/`` in the working folder, else
the source tree's ``library/``), every ``.oac`` file under it except ``drafts/``.
**The scene** is ``--scene NAME`` of the library, a ``.oac`` file with one scene, or
the library's scene whose tracked instances are the recording's marker groups.
Everything here is checked before anything is written: a missing file, a recording
the scene does not describe, a broken library are one-line errors (exit 2).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from oacdsl.errors import InputError, MatchingError, UsageError
from oacdsl.library import Library
from oacdsl.model import Scene
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording

__all__ = ["BUNDLED_NAME", "Inputs", "bundled_recording", "default_name", "load_inputs", "source_root"]

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
    """A name for the composed OAC from the recording's file name: ``Pour-01.c3d`` → ``pour_01``."""
    stem = Path(source.split(" ")[0].split(":")[-1]).name
    for suffix in (".mmm.xml", ".xml", ".c3d", ".tsv", ".csv", ".json"):
        if stem.lower().endswith(suffix):
            stem = stem[: -len(suffix)]
            break
    name = re.sub(r"\W+", "_", stem.lower()).strip("_") or "demonstration"
    return name if name[0].isalpha() else f"demo_{name}"


@dataclass(frozen=True)
class Inputs:
    """The checked inputs of a reproduction."""

    recording: Recording
    source: str
    library: Library
    library_path: Path
    scene: Scene
    params: AasParams
    #: The --scene FILE when it lies outside the library (its instances are unknown there).
    outside_scene: Path | None = None


def load_inputs(
    recording: str | None,
    library: str | None,
    scene: str | None,
    params: AasParams,
    *,
    fmt: str | None = None,
    preset: str | None = None,
) -> Inputs:
    """Read and check everything (see the module docstring); raises OacError subclasses."""
    from oacdsl.cli.demo_input import open_library, resolve_scene
    from oacdsl.cli.segment_cmd import apply_grouping
    from oacdsl.segmentation.grouping import apply_scene_groups

    library_path = Path(library) if library is not None else default_library()
    lib = open_library(library_path)
    if recording is None:
        if fmt or preset:
            raise UsageError("--format and --preset need a RECORDING (the bundled one needs neither)")
        rec, source = bundled_recording()
    else:
        from oacdsl.segmentation.readers import read_recording

        if not Path(recording).is_file():
            raise InputError("no such recording file", location=recording)
        rec, source = apply_grouping(read_recording(recording, fmt), preset), recording
    try:
        lib, sc, outside = resolve_scene(lib, tuple(rec.instances), scene)
    except MatchingError as error:  # no scene fits the recording: a problem of the input
        raise InputError(error.message, location=source) from None
    if any(i.markers for i in sc.instances):
        rec = apply_scene_groups(rec, sc)
    tracked = {i.name for i in sc.tracked()}
    unknown = sorted(set(rec.instances) - tracked)
    if unknown:
        known = ", ".join(sorted(tracked))
        raise InputError(
            f"marker groups {', '.join(unknown)} are not tracked instances of scene {sc.name!r} ({known})",
            location=source,
        )
    if not rec.instances:
        raise InputError("the recording has no marker groups to segment", location=source)
    return Inputs(rec, source, lib, library_path, sc, params, outside)
