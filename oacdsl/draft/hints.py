"""Comments of a drafted class that point past the markers: what stands on the object (its
top is higher than its own markers say) and library classes named like it (perhaps the same
object). Each is a list of comment lines, empty when there is nothing to say."""

from __future__ import annotations

from collections.abc import Collection, Mapping

import numpy as np

from oacdsl.draft.names import library_classes_alike
from oacdsl.draft.support import Support
from oacdsl.segmentation.recording import Recording

__all__ = ["alike_notes", "carried_notes"]


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


def alike_notes(group: str, instance: str, candidates: Collection[str]) -> list[str]:
    """The library classes that share a word with ``group`` (``board``: ``CuttingBoard``)."""
    alike = library_classes_alike(group, candidates)
    if not alike:
        return []
    return [f"# the library's {', '.join(alike)} share{'s' if len(alike) == 1 else ''} a word with"
            f" '{group}': '{instance} : {alike[0]}' in the scene instead of the class below takes"
            " its geometry, grasp and the OACs written for it."]
