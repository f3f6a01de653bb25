"""Comments of a drafted class that point past the markers: what stands on the object (its
top is higher than its own markers say) and library classes named like it (perhaps the same
object). Each is a list of comment lines, empty when there is nothing to say."""

from __future__ import annotations

from collections.abc import Collection, Mapping

import numpy as np

from oacdsl.draft.estimate import ShapeEstimate
from oacdsl.draft.names import library_classes_alike
from oacdsl.draft.support import Support
from oacdsl.segmentation.recording import Recording

__all__ = ["alike_notes", "carried_notes", "lying_notes", "stacked_notes"]


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


#: A box at least this long (m) and at most a quarter as wide and as high lies like a tool.
LYING_TOOL_M = 0.12


def lying_notes(est: ShapeEstimate) -> list[str]:
    """For a long, narrow, low box (KIT's knife 312 x 33 x 12 mm, salad servers): the robot
    builds every shape upright and never turns an object, and a tool a hand works with stands
    on its working end on the robot, taken from the side high up its handle (docs/kit.md,
    "Long tools stand up"); a knife drafted lying and taken from above stopped the hand at
    65 N on its way down."""
    if est.shape != "box":
        return []
    long_m, short_m = max(est.length_m, est.width_m), min(est.length_m, est.width_m)
    if long_m < LYING_TOOL_M or 4 * short_m > long_m or 4 * est.height_m > long_m:
        return []
    return [f"# long, narrow and low ({long_m * 1000:.0f} mm): if it is a tool lying on the table (a knife, a"
            " spoon), model it standing on its working end, handle up, with a side grasp high up the"
            " handle (docs/kit.md, 'Long tools stand up'): every shape stands upright and objects are"
            " never turned; taken from above as it lies, the hand meets the table first."]
