"""Turns beyond the wrist in a followed path: split into pieces with regrasps (``follow``).

A demonstrated path may turn the held object about its own axis further than a wrist can (a
lid unscrewed by 240°, 535° in KIT's Open). When the object can rest on the target between
two pieces (``follow`` decides: docs/runtime.md, "follow"),
:func:`~oacdsl.segmentation.followpath.twist_of` separates each
keyframe's rotation into a *twist* about the object's own axis, unwrapped over the path (any
angle, not the shortest arc), and the rest, the *swing*. ``retarget`` keeps the twist whole and
caps only the swing; :func:`split` cuts the twist into equal pieces of at most the wrist's
``turn`` (a keyframe put in where each piece ends) and names the keyframes after which the hand
lets go of the object and takes it again, turned back (``motion.rotate.regrasp``, recorded as
internal to the step). :func:`wound` is how far the hand has been turned back about the
object's axis at a keyframe: the hand follows the object's twist less that. numpy only;
radians, metres, seconds.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from oacdsl.runtime.retarget import Retargeted
from oacdsl.segmentation.followpath import from_rotvec, rotvec

__all__ = ["split", "wound"]


def split(r: Retargeted, turn_rad: float, piece_s: float = 0.0) -> tuple[Retargeted, tuple[int, ...]]:
    """``(path, regrasps)``: ``r`` with a keyframe put in wherever its twist (from the core's
    first keyframe) has gone one more piece's worth since the last regrasp, the pieces equal and
    at most ``turn_rad`` (as many as the widest twist needs), and those keyframes' indices: after
    reaching one, the hand takes the object again. A piece's turn lasts at least ``piece_s`` (the
    path slowed where it turns faster: a wrist at the end of its range lags a fast turn by
    centimetres, dragging the object across the target). No regrasps when the path has no twist
    or it stays within ``turn_rad`` (or ``turn_rad`` is 0)."""
    if r.twists_rad is None or turn_rad <= 0:
        return r, ()
    c = r.core
    theta = r.twists_rad - r.twists_rad[c]
    span = float(np.max(np.abs(theta[c:]), initial=0.0))
    if span <= turn_rad * (1 + 1e-9):
        return r, ()
    step = span / math.ceil(span / turn_rad - 1e-9)
    times, pos, rots, twists = [*r.times_s[: c + 1]], [*r.positions_m[: c + 1]], [*r.rotations[: c + 1]], [
        *r.twists_rad[: c + 1]]
    cuts: list[int] = []
    start = 0.0  # the twist where the current piece started (from the core's first keyframe)
    for k in range(c + 1, len(theta)):
        lo, hi = float(theta[k - 1]), float(theta[k])
        while abs(hi - start) > step * (1 + 1e-9):
            end = start + math.copysign(step, hi - start)
            f = (end - lo) / (hi - lo)  # where between keyframes k-1 and k the piece ends
            if f > 1e-6:  # (on keyframe k-1 itself: nothing to put in)
                times.append(r.times_s[k - 1] + f * (r.times_s[k] - r.times_s[k - 1]))
                pos.append(r.positions_m[k - 1] + f * (r.positions_m[k] - r.positions_m[k - 1]))
                rv0, rv1 = rotvec(r.rotations[k - 1]), rotvec(r.rotations[k])
                rots.append(from_rotvec(rv0 + f * (rv1 - rv0)))
                twists.append(r.twists_rad[c] + end)
            cuts.append(len(times) - 1)
            start = end
        times.append(r.times_s[k])
        pos.append(r.positions_m[k])
        rots.append(r.rotations[k])
        twists.append(r.twists_rad[k])
    dt = np.diff(np.array(times))
    if piece_s > 0:
        dt = np.maximum(dt, np.abs(np.diff(np.array(twists))) * piece_s / step)
    t = np.r_[times[0], times[0] + np.cumsum(dt)]
    out = replace(r, times_s=t, positions_m=np.array(pos), rotations=np.array(rots),
                  twists_rad=np.array(twists), slowed_s=r.slowed_s + float(t[-1] - r.times_s[-1]))
    return out, tuple(cuts)


def wound(r: Retargeted, regrasps: tuple[int, ...], k: int) -> float:
    """How far (rad) the hand has been turned back about the object's axis by the regrasps
    before keyframe ``k`` (the object's twist at the last of them; 0 before the first)."""
    if r.twists_rad is None:
        return 0.0
    done = [b for b in regrasps if b < k]
    return float(r.twists_rad[done[-1]] - r.twists_rad[r.core]) if done else 0.0
