"""The room two hands leave between them when each is at a grasp pose.

Two hands that grasp at once (``grasp_both``) must not meet. Their grasp centres are a poor
measure of that: a hand's palm sits 5 cm behind its grasp centre and its open thumb reaches
9 cm past it, so two hands taking two objects from their outer sides are much farther apart
than their grasp centres, and two hands taking them from the same side much nearer. Here
each hand is its collision boxes (:func:`~oacdsl.runtime.hands.hand_boxes`: palm, finger
plate, thumb) in the shape it has while it comes in (open, or with the thumb folded for a
grasp from above), placed so that its grasp centre is at the grasp pose, and the gap is the
smallest distance between a box of one hand and a box of the other (metres).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from oacdsl.runtime.hands import GRASP_CENTRE_H, hand_boxes, hand_joints
from oacdsl.runtime.transforms import make_T, rot_axis

__all__ = ["box_distance", "box_surface", "hand_box_poses", "hands_gap", "SAMPLE_M"]

#: Spacing of the points sampled on a box's surface to measure a gap, m (the gap is exact
#: to about half of it).
SAMPLE_M = 0.005


def hand_box_poses(
    side: str, t_world_grasp: np.ndarray, fingers: Mapping[str, float]
) -> list[tuple[np.ndarray, np.ndarray]]:
    """(T_world_box, half sizes in m) of each collision box of hand ``side`` when its grasp
    centre is at ``t_world_grasp`` and its finger joints at ``fingers`` (suffix → rad, as
    :data:`~oacdsl.runtime.hands.OPEN`)."""
    g = np.array(GRASP_CENTRE_H) * (1.0, 1.0 if side == "r" else -1.0, 1.0)
    t_world_hand = t_world_grasp @ make_T(None, -g)
    frames = {f"hand_{side}": t_world_hand}
    for j in hand_joints(side):
        angle = fingers[j.name.replace(f"_{side}_", "_")]
        local = make_T(rot_axis(np.array(j.axis), angle), np.array(j.origin))
        frames[f"{j.name}_link"] = frames[j.parent] @ local
    return [(frames[b.link] @ make_T(None, np.array(b.centre)), np.array(b.half)) for b in hand_boxes(side)]


def _surface(half: np.ndarray) -> np.ndarray:
    """Points on the surface of a box of ``half`` sizes about the origin, about
    :data:`SAMPLE_M` apart (m)."""
    axes = [np.linspace(-h, h, max(2, int(np.ceil(2 * h / SAMPLE_M)) + 1)) for h in half]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    on_face = np.any(np.isclose(np.abs(grid), half), axis=1)
    return grid[on_face]


def _distance(points: np.ndarray, t_world_box: np.ndarray, half: np.ndarray) -> float:
    """The smallest distance (m) from ``points`` (world) to the box."""
    local = (points - t_world_box[:3, 3]) @ t_world_box[:3, :3]
    outside = np.maximum(np.abs(local) - half, 0.0)
    return float(np.linalg.norm(outside, axis=1).min())


def hands_gap(
    a: tuple[str, np.ndarray, Mapping[str, float]], b: tuple[str, np.ndarray, Mapping[str, float]]
) -> float:
    """The smallest distance (m) between two hands, each given as (side, T_world_grasp,
    finger joints); 0 when they overlap."""
    boxes_a, boxes_b = hand_box_poses(*a), hand_box_poses(*b)
    points_a = [(_surface(h) @ t[:3, :3].T) + t[:3, 3] for t, h in boxes_a]
    points_b = [(_surface(h) @ t[:3, :3].T) + t[:3, 3] for t, h in boxes_b]
    gap = float("inf")
    for (ta, ha), pa in zip(boxes_a, points_a, strict=True):
        for (tb, hb), pb in zip(boxes_b, points_b, strict=True):
            gap = min(gap, _distance(pa, tb, hb), _distance(pb, ta, ha))
    return gap


def box_surface(half: np.ndarray) -> np.ndarray:
    """Points on the surface of a box of ``half`` sizes (m) about the origin, :data:`SAMPLE_M` apart."""
    return _surface(np.asarray(half, dtype=np.float64))


def box_distance(points: np.ndarray, t_world_box: np.ndarray, half: np.ndarray) -> float:
    """The smallest distance (m) from ``points`` (world) to a box at ``t_world_box``; 0 inside it."""
    return _distance(points, t_world_box, half)
