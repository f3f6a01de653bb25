"""End orientation of an object, against the demonstration's (docs/verify.md, end state).

Two measures per object, in each recording:

- the **turn since its start**: the angle between the axis that pointed up at the first frame
  and the vertical at the end (rigid fit of ≥ 3 markers, :mod:`oacdsl.segmentation.poses`);
- for an **elongated** marker constellation (its largest principal extent at least
  ``elongated_ratio`` times the second), the **long axis** from the vertical at the start and
  at the end, sign-free (0 to 90°): the line through its markers, whichever end is up.

**The rule.** The execution's start pose of an object is a choice of its scene, not part of
the task: the KIT servers lie on the table in front of the person (their long axes 88° and 87°
from the vertical) and stand on their heads in the robot's scene (the library models long
tools standing on their working end, where the hand can take them from the side). Judged by
each one's turn since its own start, the same end pose — leaning 31° from the vertical in the
bowl — is a turn of 57° for the person's server and of 31° for the robot's: two different
body axes compared. So when both constellations are elongated, their long axes' start tilts
differ by more than ``tilt_rad`` and the demonstration turns the long axis by more than
``tilt_rad`` (its end pose is what the task made: the servers left leaning in the bowl), what
is compared is what is comparable in world terms: the long axis's **end** tilt from the
vertical, demonstration against execution. Otherwise the turn since the start is compared,
as before: where the starts agree, where a constellation is not elongated (a cup, a bowl, a
board; there the sign matters: a cup upside down is 180° from upright), and where the
demonstration leaves the long axis's tilt as it was — the person's tablespoon (Stir), ladle
(Scoop) and the dough's mixer start and end leaning or lying (61° → 66°, 57° → 57°, 74° →
73°), the robot's start and end standing (0° → 0°): each left as its scene started it, which
the end tilts alone would call 57–73° apart; a robot that knocked its standing tool over
(0° → 90°) still fails, by its turn.

An orientation passes when the two compared tilts differ by at most ``tilt_rad``. The
classes — upright below ``upright_max_rad``, upside down above π minus it, on its side in
between — describe a tilt in the text only; they are no rule: a bowl's 44° and 48° are the
same pose, however the 45° boundary falls between them (a cup left on its side against an
upright one is 90° apart and still fails).

Limits: with the long axis, a tool turned end over end compares equal (a server left head up
against the person's head down, when their starts differ): the marker constellations of the
person's and the robot's objects are not the same, so no end of the axis is known on both.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from oacdsl.verify_tolerances import VerifyTolerances

__all__ = ["Orientation", "axis_tilts", "compare_orientation", "orientation_name"]


@dataclass(frozen=True)
class Orientation:
    """One object's orientation measures (module docstring), radians; None when not measured."""

    #: The start's up axis from the vertical at the end (turn since the start).
    turn_rad: float | None
    #: (start, end): the long axis from the vertical, sign-free; None when the constellation
    #: is not elongated or has fewer than three markers.
    axis_rad: tuple[float, float] | None = None


def orientation_name(tilt_rad: float, upright_max_rad: float = math.radians(45.0)) -> str:
    """The class that describes a tilt: upright, on its side, upside down."""
    if tilt_rad < upright_max_rad:
        return "upright"
    if tilt_rad > math.pi - upright_max_rad:
        return "upside down"
    return "on its side"


def _principal(pts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(extents (3,) in decreasing order, m; axes (3, 3), rows) of a (k, 3) constellation."""
    p = pts - pts.mean(axis=0)
    axes = np.linalg.svd(p)[2]
    proj = p @ axes.T
    extents = proj.max(axis=0) - proj.min(axis=0)
    return extents, axes


def axis_tilts(start_m: np.ndarray, end_m: np.ndarray, elongated_ratio: float) -> tuple[float, float] | None:
    """The long axis's tilt from the vertical (rad, 0 to π/2) in the (k, 3) marker positions
    ``start_m`` and ``end_m`` (one rigid constellation), or None when it has fewer than three
    markers seen in both or its largest principal extent is less than ``elongated_ratio``
    times the second."""
    seen = np.isfinite(start_m).all(axis=1) & np.isfinite(end_m).all(axis=1)
    if seen.sum() < 3:
        return None
    extents, _ = _principal(start_m[seen])
    if not extents[0] >= elongated_ratio * max(float(extents[1]), 1e-9):
        return None
    out = []
    for pts in (start_m[seen], end_m[seen]):
        axis = _principal(pts)[1][0]
        out.append(float(np.arccos(min(1.0, abs(float(axis[2]))))))
    return out[0], out[1]


def compare_orientation(
    name: str, demo: Orientation, run: Orientation, tolerances: VerifyTolerances
) -> tuple[bool, str, str, str, str] | None:
    """(passed, demonstration, execution, tolerance, detail) of one object's orientation, or
    None when it is not measured in both recordings (module docstring)."""
    deg, tol = math.degrees, tolerances.tilt_rad
    up = tolerances.upright_max_rad
    if demo.axis_rad is not None and run.axis_rad is not None \
            and abs(demo.axis_rad[0] - run.axis_rad[0]) > tol \
            and abs(demo.axis_rad[1] - demo.axis_rad[0]) > tol:
        (ds, de), (rs, re) = demo.axis_rad, run.axis_rad
        ok = abs(de - re) <= tol
        dv = f"long axis {deg(de):.0f}° from the vertical (at the start {deg(ds):.0f}°)"
        rv = f"long axis {deg(re):.0f}° from the vertical (at the start {deg(rs):.0f}°)"
        detail = "" if ok else (
            f"{name}'s long axis ends {deg(re):.0f}° from the vertical, the demonstration's"
            f" {deg(de):.0f}° (the two started {deg(rs):.0f}° and {deg(ds):.0f}° from it, and the"
            " demonstration turned it: the end tilts are compared)"
        )
        within = (f"end tilt of the long axis within {deg(tol):.0f}°"
                  " (the starts differ; the demonstration turned it)")
        return ok, dv, rv, within, detail
    if demo.turn_rad is None or run.turn_rad is None:
        return None
    d, r = demo.turn_rad, run.turn_rad
    dc, rc = orientation_name(d, up), orientation_name(r, up)
    ok = abs(d - r) <= tol
    detail = "" if ok else (
        f"{name} ends {rc} ({deg(r):.0f}° from how it stood), the demonstration's {dc} ({deg(d):.0f}°)"
    )
    within = f"turn since the start within {deg(tol):.0f}°"
    return ok, f"{dc} {deg(d):.0f}°", f"{rc} {deg(r):.0f}°", within, detail
