"""Grouping markers into instances (marker groups).

Four sources, in the order a reader or a user applies them:

* **prefix** — labels ``boite:gauche_ext`` form the group ``boite`` (labels without
  a ``:`` stay ungrouped). When no label carries a ``:``, the text before the first
  ``_`` is the prefix instead (``pillow_top`` → ``pillow``), and a label without
  ``_`` is a group of its own (``hand``).
* **subjects** — a C3D ``SUBJECTS`` group lists the prefixes explicitly (readers).
* **motion** — an MMM file has one motion per object (readers).
* **mapping** — an explicit ``{instance: [marker, …]}``, e.g. from a scene's
  ``Instance.markers`` (:func:`apply_scene_groups`), or a built-in preset
  (:data:`PRESETS`, :func:`apply_preset`), which is also applied unasked when the
  recording holds every marker of exactly one preset (:func:`recognise_preset`).

A marker name in a mapping matches a label exactly, or the part after the prefix
(``gauche_ext`` matches ``boite:gauche_ext`` when that is unique), or is a glob
pattern (``pillow_*``).
"""

from __future__ import annotations

import fnmatch
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

from oacdsl.errors import RecordingError, did_you_mean
from oacdsl.segmentation.recording import Recording

if TYPE_CHECKING:  # the model is only needed for the annotation: keep this module light
    from oacdsl.model import Scene

__all__ = [
    "KIT_HANDS",
    "PRESETS",
    "prefix_groups",
    "resolve_markers",
    "with_mapping",
    "apply_scene_groups",
    "apply_preset",
    "recognise_preset",
    "group_recording",
]

#: Hand and wrist markers of the KIT/MMM (Vicon) marker set: pinky and thumb side of
#: the hand, index finger, pinky and thumb side of the wrist.
KIT_HANDS: dict[str, tuple[str, ...]] = {
    "left_hand": ("LHPS", "LHTS", "LIFD", "LWPS", "LWTS"),
    "right_hand": ("RHPS", "RHTS", "RIFD", "RWPS", "RWTS"),
}

#: Built-in marker mappings by name; a preset replaces the group(s) holding its
#: markers (the subject's body) with its own groups and keeps every other group.
PRESETS: dict[str, Mapping[str, Sequence[str]]] = {"kit": KIT_HANDS}


def prefix_groups(marker_names: Sequence[str]) -> dict[str, list[str]]:
    """Group labels by prefix: ``group:marker``, else ``group_marker``; see the module doc."""
    sep = ":" if any(":" in n for n in marker_names) else "_"
    groups: dict[str, list[str]] = {}
    for name in marker_names:
        head, found, tail = name.partition(sep)
        if found and head and tail:
            groups.setdefault(head, []).append(name)
        elif sep == "_" and not found:
            groups.setdefault(name, []).append(name)
    return groups


def _is_pattern(name: str) -> bool:
    return any(c in name for c in "*?[")


def resolve_markers(recording: Recording, names: Sequence[str], instance: str) -> tuple[int, ...]:
    """Indices of ``names`` in the recording (exact label, unique un-prefixed label, or glob)."""
    labels = recording.marker_names
    index = {n: i for i, n in enumerate(labels)}
    bare: dict[str, list[int]] = {}
    for i, n in enumerate(labels):
        if ":" in n:
            bare.setdefault(n.split(":", 1)[1], []).append(i)
    out: list[int] = []
    for name in names:
        if name in index:
            found = [index[name]]
        elif _is_pattern(name):
            found = [i for i, n in enumerate(labels) if fnmatch.fnmatchcase(n, name)]
        else:
            found = bare.get(name, [])
            if len(found) > 1:
                options = ", ".join(labels[i] for i in found)
                raise RecordingError(
                    f"instance {instance!r}: marker {name!r} is ambiguous ({options})",
                    location=recording.source,
                )
        if not found:
            raise RecordingError(
                f"instance {instance!r}: marker {name!r} is not in the recording"
                f"{did_you_mean(name, [*labels, *bare])}",
                location=recording.source,
            )
        out.extend(i for i in found if i not in out)
    return tuple(out)


def _rebuild(recording: Recording, groups: Mapping[str, tuple[int, ...]]) -> Recording:
    return Recording(
        recording.source,
        recording.rate_hz,
        recording.times_s,
        recording.marker_names,
        recording.positions_m,
        dict(groups),
        recording.first_frame,
    )


def with_mapping(
    recording: Recording, mapping: Mapping[str, Sequence[str]], keep_others: bool = False
) -> Recording:
    """Groups given by marker names; with ``keep_others`` the existing groups stay too."""
    groups: dict[str, tuple[int, ...]] = dict(recording.groups) if keep_others else {}
    for inst, names in mapping.items():
        if not names:
            raise RecordingError(
                f"instance {inst!r}: the mapping lists no markers", location=recording.source
            )
        groups[inst] = resolve_markers(recording, names, inst)
    return _rebuild(recording, groups)


def apply_scene_groups(recording: Recording, scene: Scene) -> Recording:
    """Groups = the scene's tracked instances.

    An instance with ``markers`` takes those markers; one without takes the
    recording's group of the same name. Environment instances (the table) are
    dropped, and so are groups of the recording that the scene does not name.
    """
    groups: dict[str, tuple[int, ...]] = {}
    for inst in scene.tracked():
        if inst.markers:
            groups[inst.name] = resolve_markers(recording, inst.markers, inst.name)
        elif inst.name in recording.groups:
            groups[inst.name] = tuple(recording.groups[inst.name])
        else:
            available = ", ".join(recording.instances) or "none"
            hint = did_you_mean(inst.name, recording.groups)
            hint = hint if hint.startswith(" (did you mean") else ""  # the groups are listed anyway
            raise RecordingError(
                f"scene {scene.name!r}: instance {inst.name!r} has no marker group in the recording"
                f" and lists no markers{hint} (groups in the recording: {available})",
                location=recording.source,
            )
    return _rebuild(recording, groups)


def apply_preset(recording: Recording, name: str) -> Recording:
    """Apply a built-in preset (e.g. ``kit``): its groups replace those holding its markers."""
    if name not in PRESETS:
        raise RecordingError(f"unknown marker preset {name!r}{did_you_mean(name, PRESETS)}")
    mapping = PRESETS[name]
    new: dict[str, tuple[int, ...]] = {}
    for inst, names in mapping.items():
        try:
            new[inst] = resolve_markers(recording, names, inst)
        except RecordingError as err:
            raise RecordingError(f"preset {name!r}: {err.message}", location=recording.source) from None
    used = {i for idx in new.values() for i in idx}
    kept = {g: idx for g, idx in recording.groups.items() if not used.intersection(idx) and g not in new}
    return _rebuild(recording, {**kept, **new})


def _has_markers(recording: Recording, names: Sequence[str]) -> bool:
    try:
        resolve_markers(recording, names, "?")
    except RecordingError:
        return False
    return True


def recognise_preset(recording: Recording) -> tuple[Recording, str | None]:
    """Apply the preset whose every marker the recording holds, if exactly one does.

    A KIT/MMM recording names its subject's hand markers ``LHPS``, ``RWTS``, …: its hands
    become ``left_hand`` and ``right_hand`` without asking. Returns the recording
    (unchanged when no preset or several fit) and the preset's name or ``None``.
    Instances the recording already has with a preset's names are kept as they are.
    """
    fits = [
        name
        for name, mapping in PRESETS.items()
        if not set(mapping) & set(recording.groups)
        and all(_has_markers(recording, names) for names in mapping.values())
    ]
    if len(fits) != 1:
        return recording, None
    return apply_preset(recording, fits[0]), fits[0]


def recognised_note(recording: Recording, preset: str) -> str:
    """What to tell the user when ``preset`` was recognised unasked in ``recording``."""
    hands = ", ".join(f"{inst} = {' '.join(names)}" for inst, names in PRESETS[preset].items())
    return (
        f"{recording.source}: marker set {preset!r} recognised ({hands});"
        " --preset none keeps the file's groups"
    )


def group_recording(recording: Recording, preset: str | None) -> tuple[Recording, str | None]:
    """The recording grouped as the command line asks: a named preset, ``"none"`` (the
    file's own groups), or ``None``: a recognised preset. Returns the preset recognised
    unasked (for a note to the user), else ``None``."""
    if preset == "none":
        return recording, None
    if preset and preset not in PRESETS:
        raise RecordingError(f"unknown marker preset {preset!r}{did_you_mean(preset, [*PRESETS, 'none'])}")
    if preset:
        return apply_preset(recording, preset), None
    return recognise_preset(recording)
