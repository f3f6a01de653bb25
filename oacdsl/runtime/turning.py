"""Poses of a turned object: a rotation from two axes, a pose placed by its bounding box, angles
round a circle, and whether a tilt is nearer on edge than upright (metres, radians; numpy only)."""

from __future__ import annotations

import math

import numpy as np

from oacdsl.runtime.bodies import Body
from oacdsl.runtime.shapes import corners
from oacdsl.runtime.transforms import make_T

__all__ = ["frame_zx", "hull_points", "placed_by_box", "round_angles", "on_edge"]

#: Points on each rim of a round solid (its top and bottom circles) that stand for it.
RIM_POINTS = 24


def frame_zx(z: np.ndarray, x: np.ndarray) -> np.ndarray:
    """The rotation whose z axis is along ``z`` and whose x axis is ``x`` made perpendicular to it."""
    z = np.asarray(z, dtype=float) / np.linalg.norm(z)
    x = np.asarray(x, dtype=float) - float(np.dot(x, z)) * z
    x = x / np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def hull_points(body: Body) -> np.ndarray:
    """(P, 3) points whose convex hull holds ``body``, object frame (m): a round solid's top and
    bottom circles (its bounding box's corners stick out of it once it is turned on edge), any
    other solid's bounding-box corners."""
    out = [corners(body)] if not body.round else []
    if body.round:
        a = round_angles(RIM_POINTS)
        ring = np.column_stack([np.cos(a), np.sin(a), np.zeros_like(a)])
        for s in body.solids:
            r = s.dims.get("radius", 0.0)
            for z in (s.at[2], s.top):
                out.append(ring * r + np.array([0.0, 0.0, z]))
    return np.concatenate(out)


def placed_by_box(body: Body, r_obj: np.ndarray, xy: np.ndarray, low_z: float) -> np.ndarray:
    """T_world_object turned ``r_obj`` with the middle of its bounding box (of
    :func:`hull_points`) over ``xy`` and its lowest point at ``low_z`` (m)."""
    c = hull_points(body) @ r_obj.T
    mid = (c.min(axis=0) + c.max(axis=0)) / 2
    return make_T(r_obj, (xy[0] - mid[0], xy[1] - mid[1], low_z - float(c[:, 2].min())))


def round_angles(n: int) -> np.ndarray:
    """``n`` angles evenly round a circle from 0, rad."""
    return np.linspace(0.0, math.tau, n, endpoint=False)


def on_edge(tilt_rad: float) -> bool:
    """The tilt (of an object's axis from the vertical) is nearer a quarter turn than upright
    or upside down."""
    edge = abs(tilt_rad - math.pi / 2)
    return edge < tilt_rad and edge < math.pi - tilt_rad
