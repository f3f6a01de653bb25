"""What ``oacc run`` checks before the simulation starts: the library and scene
(:func:`load_inputs`, also ``oacc plan``'s), the first-frame positions of ``--demonstration``
for a scene laid out as demonstrated, that ``--frames``, ``--video`` and ``--execution``
can be written, and the OAC, its scene and ``--bind`` (:func:`run_scene`,
:func:`check_binding`): exit 2 if not."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
from typing import Any

from oacdsl.errors import RuntimeFailure, UsageError, did_you_mean
from oacdsl.model import Scene

__all__ = ["check_binding", "check_outputs", "demonstrated", "load_inputs", "run_scene", "writable_folder"]


def demonstrated(
    args: argparse.Namespace, library: Any, scene: str | None, bindings: dict[str, str], layout: str | None
) -> tuple[dict[str, Any], dict[str, Any], dict[str, Any]] | None:
    """First-frame positions of --demonstration for a 'layout demonstrated', where it sets
    objects down (:func:`~oacdsl.runtime.demo_places.set_down_places`) and which way it turns
    them (:func:`~oacdsl.runtime.demo_layout.first_frame_poses`), else None (a warning
    when the scene wants them but no recording is given)."""
    from oacdsl.runtime.binding import choose_scene

    oac = library.oacs.get(args.name)
    if oac is None:
        return None  # prepare() names the problem
    sc = choose_scene(library, oac, scene, bindings)
    wanted = (layout or sc.layout) == "demonstrated"
    if args.demonstration is None:
        if wanted:
            print(
                f"oacc: warning: scene {sc.name} is laid out as demonstrated, but no --demonstration"
                " was given: objects without a place take free slots",
                file=sys.stderr,
            )
        return None
    from oacdsl.runtime.demo_layout import demonstrated_poses
    from oacdsl.segmentation.grouping import group_recording
    from oacdsl.segmentation.readers import read_recording

    if not Path(args.demonstration).is_file():
        raise UsageError(f"{args.demonstration}: no such recording file")
    # grouped as oacc reproduce groups it: a recognised marker set (KIT) gives the hands
    grouped, _ = group_recording(read_recording(args.demonstration), None)
    from oacdsl.runtime.demo_places import scene_hands, set_down_places

    names, hands = [i.name for i in sc.tracked()], scene_hands(library, sc)
    first, headings = demonstrated_poses(grouped, sc, library)
    if any(i.markers for i in sc.instances):  # grouped by the scene, as demonstrated_positions does
        from oacdsl.segmentation.grouping import apply_scene_groups

        grouped = apply_scene_groups(grouped, sc)
    return first, set_down_places(grouped, names, hands), headings


def load_inputs(paths: list[str], scene: str | None) -> tuple[Any, str | None]:
    """The library from ``paths`` (plus the scene file, when ``scene`` is a file) and the scene's name."""
    try:
        from oacdsl.compiler import load_library, parse_file
    except ImportError as error:  # the language part is not in this build
        raise UsageError(f"cannot load .oac files: {error}") from None
    for path in paths:
        if not Path(path).exists():
            raise UsageError(f"{path}: no such file or folder")
    if scene is not None and (scene.endswith(".oac") or Path(scene).is_file()):
        if not Path(scene).is_file():
            raise UsageError(f"{scene}: no such file")
        module = parse_file(scene)
        names = [d.name for d in module.decls if isinstance(d, Scene)]
        if len(names) != 1:
            raise UsageError(f"{scene}: expected one scene declaration, found {len(names)}")
        return load_library([*paths, scene]), names[0]
    return load_library(paths), scene


def run_scene(library: Any, name: str, scene: str | None, bindings: dict[str, str]) -> Scene:
    """The scene OAC ``name`` runs in (``--scene``, else the one that fits it and ``--bind``), as
    the runtime chooses it; an OAC or scene that is not there is a usage error (exit 2)."""
    from oacdsl.runtime.binding import choose_scene

    if name not in library.oacs:
        raise UsageError(f"no oac {name!r} in the library{did_you_mean(name, library.oacs)}")
    try:
        return choose_scene(library, library.oacs[name], scene, bindings)
    except RuntimeFailure as error:
        raise UsageError(error.message) from None


def check_binding(library: Any, name: str, scene: Scene, bindings: dict[str, str]) -> None:
    """Every parameter of OAC ``name`` bound in ``scene`` (``--bind`` first) as the runtime binds
    them, but before anything heavy (the run store, a demonstration, MuJoCo, a cluster): an
    instance that is not there, not of the parameter's class, or a parameter the OAC lacks is a
    usage error (exit 2) on one line, naming the ``--bind`` it is about."""
    from oacdsl.runtime.binding import bind

    try:
        bind(library, library.oacs[name], scene, bindings)
    except RuntimeFailure as error:
        raise UsageError(error.message) from None


def writable_folder(folder: Path, flag: str) -> None:
    """Create ``folder`` if needed and check that a file can be written in it (exit 2 if not)."""
    import tempfile

    from oacdsl.errors import InputError

    if folder.exists() and not folder.is_dir():
        raise UsageError(f"{flag}: {folder} exists and is not a folder")
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except (FileExistsError, NotADirectoryError):  # a parent is a file
        raise UsageError(f"{flag}: cannot make the folder {folder}: a parent is a file") from None
    except OSError as error:
        why = error.strerror or error
        raise InputError(f"{flag}: cannot make this folder: {why}", location=str(folder)) from None
    try:
        fd, probe = tempfile.mkstemp(prefix=".oacc-probe-", dir=folder)
        os.close(fd)
        os.unlink(probe)
    except OSError as error:
        why = error.strerror or error
        raise InputError(f"{flag}: cannot write here: {why}", location=str(folder)) from None


def check_outputs(args: argparse.Namespace) -> None:
    """Fail before the simulation when ``--frames`` or ``--video`` cannot be written."""
    if args.frames:
        writable_folder(Path(args.frames), "--frames")
    if args.video:
        video = Path(args.video)
        if video.suffix.lower() != ".mp4":
            writable_folder(video, "--video")
        elif video.is_dir():
            raise UsageError(f"--video {video}: is a folder; give a file name ending in .mp4")
        else:
            from oacdsl.atomic import check_target

            writable_folder(video.parent, "--video")
            check_target(video)
