"""The Python API: what the command line does, for scripts and notebooks.

Each function is the command of the same name without its printing; they take paths or
the objects the previous one returned, return typed results (the same records the CLI
prints) and raise the same errors, all subclasses of :class:`~oacdsl.errors.OacError`
whose ``str()`` is the CLI's one-line message::

    import oacdsl

    demo = oacdsl.load_demonstration("data/dough.c3d", "library")
    seg = oacdsl.segment(demo.recording)                  # keyframes (AAS)
    matches = oacdsl.match(demo)                           # one SubActionMatch per sub-action
    comp = oacdsl.compose(demo, "dough_again")             # Algorithm 1, in memory
    print(comp.text)                                       # the new OAC as .oac text
    result = oacdsl.run(demo.library, comp.oac, scene=demo.scene)   # needs the 'robot' extra

Nothing here writes a file unless asked (:func:`compose` with ``write_to``); the robot
functions import MuJoCo and placo only when called. docs/api.md has a worked example.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

from oacdsl.errors import UsageError

if TYPE_CHECKING:  # keep ``import oacdsl`` light: the records are imported when used
    from oacdsl.library import Library
    from oacdsl.matching.composer import Composition
    from oacdsl.matching.demonstration import SubActionMatch
    from oacdsl.model import Oac, Scene
    from oacdsl.runtime.results import RunResult
    from oacdsl.segmentation.params import AasParams
    from oacdsl.segmentation.recording import Recording
    from oacdsl.segmentation.result import Segmentation

__all__ = [
    "Composed",
    "Demonstration",
    "compose",
    "load_demonstration",
    "load_library",
    "match",
    "read_recording",
    "run",
    "segment",
]

PathLike = str | Path


@dataclass(frozen=True)
class Demonstration:
    """A recording read and checked against a library, as ``oacc match`` and ``compose`` see it.

    Attributes:
        recording: the marker trajectories, grouped into the scene's instances.
        library: the OAC library (every file of every path given).
        scene: the library's scene whose tracked instances the recording's groups are.
        source: the recording's path as given (or ``data/dough.c3d`` for the bundled one).
        params: the segmentation parameters (AAS) used by :func:`match` and :func:`compose`.
        library_paths: the library's folders or files, as given.
    """

    recording: Recording
    library: Library
    scene: Scene
    source: str
    params: AasParams
    library_paths: tuple[Path, ...] = ()


@dataclass(frozen=True)
class Composed:
    """A composed OAC: ``composition`` (Algorithm 1's record: steps, pre, effect, provenance),
    ``oac`` (the model), ``text`` (canonical ``.oac`` text) and ``path`` (where it was written,
    None when only composed in memory)."""

    composition: Composition
    oac: Oac
    text: str
    path: Path | None = None


def load_library(*paths: PathLike) -> Library:
    """The library of ``.oac`` files under ``paths`` (folders or files), checked as
    ``oacc compile`` checks it; :class:`~oacdsl.errors.LanguageError` names the first error."""
    from oacdsl.pipeline.inputs import default_library, open_library

    return open_library([Path(p) for p in paths] or [default_library()])


def read_recording(
    path: PathLike, *, format: str | None = None, preset: str | None = None, allow_truncated: bool = False
) -> Recording:
    """A motion-capture recording (C3D, MMM XML, TSV, CSV), grouped into marker groups as
    ``oacc segment`` groups it: ``preset`` None recognises a known marker set (the KIT hands),
    ``"none"`` keeps the file's groups."""
    from oacdsl.errors import InputError
    from oacdsl.segmentation.grouping import group_recording
    from oacdsl.segmentation.readers import read_recording as read

    if not Path(path).exists():
        raise InputError("no such recording file", location=str(path))
    recording, _ = group_recording(read(path, format, allow_truncated=allow_truncated), preset)
    return recording


def _params(params: AasParams | None, overrides: Mapping[str, Any]) -> AasParams:
    from oacdsl.segmentation.params import AasParams

    base = params if params is not None else AasParams()
    try:
        return replace(base, **overrides)
    except TypeError as error:
        raise UsageError(f"segment: {error}") from None


def segment(recording: Recording, params: AasParams | None = None, **overrides: Any) -> Segmentation:
    """The keyframes where objects start or stop touching (AAS); ``overrides`` are fields of
    :class:`~oacdsl.segmentation.params.AasParams` (``mode="paper"``, ``merge_s=0.5`` …)."""
    from oacdsl.segmentation import segment as aas

    return aas(recording, _params(params, overrides))


def load_demonstration(
    recording: PathLike | None = None,
    *library: PathLike,
    scene: str | None = None,
    params: AasParams | None = None,
    format: str | None = None,
    preset: str | None = None,
    allow_truncated: bool = False,
) -> Demonstration:
    """Read ``recording`` (None: the bundled dough demonstration) and resolve its scene in the
    library of ``library`` paths (none: ``library/``), as ``oacc match`` does."""
    from oacdsl.pipeline.inputs import load_inputs

    inputs = load_inputs(
        recording,
        [Path(p) for p in library] or None,
        scene,
        params if params is not None else _params(None, {}),
        fmt=format,
        preset=preset,
        allow_truncated=allow_truncated,
    )
    if inputs.recording is None:  # load_inputs reads segmentations only when asked to
        raise UsageError("load_demonstration reads a recording, not a segmentation")
    return Demonstration(
        inputs.recording, inputs.library, inputs.scene, inputs.source, inputs.params, inputs.library_paths
    )


def match(demonstration: Demonstration, segmentation: Segmentation | None = None) -> list[SubActionMatch]:
    """Every sub-action of the demonstration (its segmentation, made here when not given) matched
    to the library's OACs with the strict rule, as ``oacc match`` reports them."""
    from oacdsl.matching import Matcher
    from oacdsl.matching.agency import hand_travel
    from oacdsl.matching.demonstration import match_segmentation

    seg = segmentation if segmentation is not None else segment(demonstration.recording, demonstration.params)
    unmerged = replace(demonstration.params, merge_s=0.0)  # when a keyframe is split
    return match_segmentation(seg, Matcher.from_library(demonstration.library, demonstration.scene),
                              unmerged=lambda: segment(demonstration.recording, unmerged),
                              travel=hand_travel(demonstration.recording))


def compose(
    demonstration: Demonstration,
    name: str,
    *,
    demo_params: bool = True,
    write_to: PathLike | None = None,
    force: bool = False,
) -> Composed:
    """Compose the matched sub-actions into a new OAC ``name`` (Algorithm 1), each step with the
    skill parameters of its demonstrated motion unless ``demo_params`` is False. In memory;
    ``write_to`` a ``.oac`` path writes it there as ``oacc compose -o`` does (checked against the
    library first, written atomically; an existing different file needs ``force``)."""
    from oacdsl.matching.demonstration import compose_demonstration
    from oacdsl.matching.emit import emit, render

    if not name.isidentifier() or not name.isascii():
        raise UsageError(f"name {name!r}: a name is letters, digits and '_', not starting with a digit")
    matches = match(demonstration)
    comp = compose_demonstration(name, matches, demonstration.library, demonstration.scene).composition
    if demo_params:
        from oacdsl.matching.composedparams import with_demo_params
        from oacdsl.matching.demoparams import demonstrated_motions

        motions = demonstrated_motions(demonstration.recording, [m.sub_action for m in matches])
        comp = with_demo_params(comp, motions, demonstration.library, demonstration.scene)
    header = [f"Composed by oacdsl.compose from {demonstration.source} (scene {demonstration.scene.name})."]
    if write_to is None:
        return Composed(comp, comp.oac, render([comp.oac], f"{name}.oac", header))
    target = Path(write_to)
    paths = demonstration.library_paths
    emitted = emit([comp.oac], target, library=paths[0] if paths else None, header=header, force=force,
                   also=paths[1:])
    return Composed(comp, comp.oac, emitted.text, emitted.path)


def run(
    library: Library,
    oac: Oac | str,
    *,
    binding: Mapping[str, str] | None = None,
    scene: Scene | str | None = None,
    seed: int | None = None,
    places: Mapping[str, tuple[float, float]] | None = None,
    fill: Mapping[str, str] | None = None,
    observers: Sequence[Any] = (),
) -> RunResult:
    """Execute ``oac`` on the simulated ARMAR-III as ``oacc run`` does (needs the ``robot``
    extra): every step judged by its predicted effects. A robot failure is in the result
    (``success``, ``failed_step``, ``error``); a wrong call raises
    :class:`~oacdsl.errors.RuntimeFailure`."""
    try:
        from oacdsl.runtime.executor import execute
    except ImportError as error:
        raise UsageError(f"run needs the 'robot' extra (pip install -e '.[robot]'): {error}") from None
    return execute(library, oac, binding, scene, seed, fill=fill, places=places, observers=observers)
