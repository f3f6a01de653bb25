"""Where an object's solids are: the corners of their bounding boxes, in any pose.

The skills that bring one object onto another (``touch``, ``stir``, ``cut`` …) ask where
the held object's lowest point or its tip is and where the target's top is, whatever
way either is turned. A solid's bounding box is enough for that (metres, object frame:
origin at the centre of the object's base, z up).
"""

from __future__ import annotations

import numpy as np

from oacdsl.runtime.bodies import Body
from oacdsl.runtime.simworld import SimWorld

__all__ = ["corners", "half_width", "world_corners", "lowest_z", "highest_z", "long_axis", "tip_local",
           "hand_reach_below", "hand_corners"]


def corners(body: Body) -> np.ndarray:
    """(8k, 3) corners of the bounding boxes of ``body``'s k solids, object frame (m)."""
    out = []
    for s in body.solids:
        d = s.dims
        if s.kind in ("box", "rack"):
            hx, hy, h = d["length"] / 2, d["width"] / 2, d["height"]
        elif s.kind == "sphere":
            hx = hy = d["radius"]
            h = 2 * d["radius"]
        elif s.kind == "mesh":
            hx = hy = body.mesh_extent[0]
            h = body.mesh_extent[1]
        else:
            hx = hy = d.get("radius", 0.0)
            h = d.get("height", 0.0)
        ax, ay, az = s.at if s.kind != "mesh" else (0.0, 0.0, 0.0)
        for x in (-hx, hx):
            for y in (-hy, hy):
                for z in (0.0, h):
                    out.append((ax + x, ay + y, az + z))
    return np.array(out, dtype=float).reshape(-1, 3)


def half_width(body: Body) -> float:
    """Half the object's narrowest horizontal extent (of its bounding boxes, object frame), m: how
    far its middle stays in from an edge it must not pass (a sponge's 3.5 cm)."""
    c = corners(body)
    return float(np.min(np.ptp(c[:, :2], axis=0))) / 2


def world_corners(body: Body, t_world_obj: np.ndarray) -> np.ndarray:
    """The corners of :func:`corners` in the world, for the object at ``t_world_obj``."""
    c = corners(body)
    return c @ t_world_obj[:3, :3].T + t_world_obj[:3, 3]


def lowest_z(body: Body, t_world_obj: np.ndarray) -> float:
    """Height (m) of the object's lowest point in the world."""
    return float(world_corners(body, t_world_obj)[:, 2].min())


def highest_z(body: Body, t_world_obj: np.ndarray) -> float:
    """Height (m) of the object's highest point in the world."""
    return float(world_corners(body, t_world_obj)[:, 2].max())


def long_axis(body: Body) -> np.ndarray:
    """The object-frame axis (unit) along which the object is longest: x, y or z."""
    c = corners(body)
    span = c.max(axis=0) - c.min(axis=0)
    axis = np.zeros(3)
    axis[int(np.argmax(span))] = 1.0
    return axis


def tip_local(body: Body, direction: np.ndarray) -> np.ndarray:
    """The object-frame point at the far end along ``direction`` (object frame): the middle of
    the bounding box's face that way (a spoon's bowl end, a knife's point), m."""
    c = corners(body)
    d = np.asarray(direction, dtype=float)
    lo, hi = c.min(axis=0), c.max(axis=0)
    mid = 0.5 * (lo + hi)
    far = float((c @ d).max())
    return mid + (far - float(mid @ d)) * d


def hand_corners(world: SimWorld, side: str) -> np.ndarray:
    """(8k, 3) corners of the bounding boxes of hand ``side``'s k geoms (palm, finger plate,
    thumb, as they are now; eight per geom, one geom after the other) in its grasp frame
    ``grasp_{side}`` (m): where the hand is around what it holds, to place with any pose of
    the grasp frame."""
    m, d = world.model, world.data
    t_grasp = world.frame_pose(f"grasp_{side}")
    bodies = np.array(sorted(world.hand_bodies[side]))
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
    pts = [(m.geom_aabb[g, :3] + signs * m.geom_aabb[g, 3:]) @ d.geom_xmat[g].reshape(3, 3).T + d.geom_xpos[g]
           for g in np.flatnonzero(np.isin(m.geom_bodyid, bodies))]
    return (np.concatenate(pts) - t_grasp[:3, 3]) @ t_grasp[:3, :3]


def hand_reach_below(world: SimWorld, side: str, r_world_grasp: np.ndarray | None = None) -> float:
    """How far (m) hand ``side`` (palm, fingers, thumb as they are now) reaches below its
    grasp centre: the lowest corner of its geoms' bounding boxes, with the hand turned to
    ``r_world_grasp`` (default: as it is)."""
    m, d = world.model, world.data
    t_grasp = world.frame_pose(f"grasp_{side}")
    turn = np.eye(3) if r_world_grasp is None else r_world_grasp @ t_grasp[:3, :3].T
    bodies = np.array(sorted(world.hand_bodies[side]))
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
    low = np.inf
    for g in np.flatnonzero(np.isin(m.geom_bodyid, bodies)):
        centre, half = m.geom_aabb[g, :3], m.geom_aabb[g, 3:]
        pts = (centre + signs * half) @ d.geom_xmat[g].reshape(3, 3).T + d.geom_xpos[g]
        low = min(low, float(((pts - t_grasp[:3, 3]) @ turn.T)[:, 2].min()))
    return -low
