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

The defaults (bundled demonstration, library, name) are in :mod:`oacdsl.pipeline.bundled`,
the library and scene in :mod:`oacdsl.pipeline.library_scene`; all are imported from here.
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from oacdsl.errors import InputError, UsageError
from oacdsl.library import Library
from oacdsl.matching.agency import Travel, hand_travel
from oacdsl.model import Scene
from oacdsl.pipeline.bundled import (
    BUNDLED_NAME,
    bundled_recording,
    default_library,
    default_name,
    source_root,
)
from oacdsl.pipeline.library_scene import check_tracked as _check_tracked
from oacdsl.pipeline.library_scene import open_library, resolve_scene
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
        keyframes = tuple(_keyframe(n, k, instances, path) for n, k in enumerate(doc["keyframes"]))
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


def _keyframe(index: int, doc: Any, instances: tuple[str, ...], path: Path) -> Keyframe:
    """Keyframe ``index`` (counted from 0, as ``oacc segment`` numbers them) of a segmentation
    document; a one-line error naming it (``FILE: keyframe N: …``) when it is malformed."""
    where = f"keyframe {index}"
    try:
        change = doc.get("change_s")
        if change is not None and (isinstance(change, bool) or not isinstance(change, (int, float))
                                   or not math.isfinite(change)):
            raise ValueError(f"change_s must be a finite number of seconds, got {json.dumps(change)}")
        return Keyframe(
            int(doc["frame"]),
            float(doc["time_s"]),
            WorldState.of(instances, [(str(a), str(b)) for a, b in doc["relations"]]),
            None if change is None else float(change),
        )
    except (KeyError, TypeError, ValueError, AttributeError) as error:
        what = f"missing key {error}" if isinstance(error, KeyError) else str(error)
        raise InputError(f"{where}: {what}", location=str(path)) from error


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
