"""Comments of a drafted class that point past the markers: what stands on the object (its
top is higher than its own markers say) and library classes named like it (perhaps the same
object). Each is a list of comment lines, empty when there is nothing to say."""

from __future__ import annotations

from collections.abc import Collection, Mapping

import numpy as np

from oacdsl.draft.names import library_classes_alike
from oacdsl.draft.support import Support
from oacdsl.segmentation.recording import Recording

__all__ = ["alike_notes", "carried_notes", "stacked_notes"]


def carried_notes(recording: Recording, group: str, support: Mapping[str, Support],
                  instances: Mapping[str, str], base_z_m: float) -> list[str]:
    """For each object standing on ``group`` at its first frame (a lid on its bottle): the
    object's top may reach that object's lowest marker, above its own highest marker."""
    notes = []
    for other, stand in sorted(support.items()):
        if stand.on != group:
            continue
        pts = recording.group_positions(other)[stand.frame]
        low = float(np.nanmin(pts[:, 2]))
        name, up_mm = instances[other], (low - base_z_m) * 1000
        notes.append(f"# {name} stands on it at frame {stand.frame}: its top may reach up to {name}'s lowest"
                     f" marker ({low * 1000:.0f} mm, {up_mm:.0f} mm above its base), higher than the height"
                     " below (its own highest marker).")
    return notes


def alike_notes(group: str, instance: str, candidates: Collection[str], cls: str) -> list[str]:
    """The library classes that share a word with ``group`` (``board``: ``CuttingBoard``), and
    how to keep the drafted size with that class's grasp and OACs (a subclass)."""
    alike = library_classes_alike(group, candidates)
    if not alike:
        return []
    return [f"# the library's {', '.join(alike)} share{'s' if len(alike) == 1 else ''} a word with"
            f" '{group}': '{instance} : {alike[0]}' in the scene instead of the class below takes"
            " its geometry, grasp and the OACs written for it; 'class"
            f" {cls} : {alike[0]}' below instead of ': Graspable' keeps its grasp and OACs with this"
            " class's geometry."]


def stacked_notes(recording: Recording, group: str, under: str, frame: int, base_z_m: float) -> list[str]:
    """For an object drafted on ``under`` from ``under``'s highest marker (a lid on its bottle):
    ``under``'s top may be higher, up to this object's lowest marker, and this object lower."""
    pts = recording.group_positions(group)[frame]
    low_m, high_m = float(np.nanmin(pts[:, 2])), float(np.nanmax(pts[:, 2]))
    if low_m - base_z_m < 0.005:
        return []
    return [f"# {under}'s top may be higher, up to this object's lowest marker ({low_m * 1000:.0f} mm,"
            f" {(low_m - base_z_m) * 1000:.0f} mm above that base): then this object is only"
            f" {(high_m - low_m) * 1000:.0f} mm high, from there to its highest marker, or a little more."]
