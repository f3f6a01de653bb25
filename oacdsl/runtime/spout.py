"""Where a container's top is open: the middle of the widest gap in what closes it (a carton's
spout), the way a pour turns it to face its target."""

from __future__ import annotations

import math

import numpy as np

from oacdsl.runtime.bodies import Body

__all__ = ["spout_direction"]


def spout_direction(body: Body) -> np.ndarray | None:
    """The horizontal direction (object frame, unit) of the middle of the widest gap in what
    closes a container's top (a carton's opening), or None when the rim is open all round
    (a cup) or closed all round."""
    shell = body.shell
    if shell is None:
        return None
    rim_z, r = shell.top, shell.dims["radius"] - shell.dims["wall"]
    lids = [s for s in body.solids if s is not shell and s.top >= rim_z - 0.01]
    angles = np.radians(np.arange(0.0, 360.0, 5.0))
    open_ = np.ones(len(angles), dtype=bool)
    for a_i, a in enumerate(angles):  # a point of the opening near the wall at each azimuth
        x, y = 0.8 * r * math.cos(a), 0.8 * r * math.sin(a)
        for lid in lids:
            d, (cx, cy, _) = lid.dims, lid.at
            if lid.kind == "box":
                covered = abs(x - cx) <= d["length"] / 2 and abs(y - cy) <= d["width"] / 2
            else:
                covered = math.hypot(x - cx, y - cy) <= d.get("radius", 0.0)
            open_[a_i] &= not covered
    if open_.all() or not open_.any():
        return None
    # the widest run of open angles (the circle wraps around)
    start = int(np.argmin(open_))  # a closed angle: runs begin after it
    best, run, best_mid = 0, 0, 0.0
    for k in range(1, len(angles) + 1):
        i = (start + k) % len(angles)
        run = run + 1 if open_[i] else 0
        if run > best:
            best, best_mid = run, float(angles[i]) - math.radians(5.0) * (run - 1) / 2
    return np.array([math.cos(best_mid), math.sin(best_mid), 0.0])
