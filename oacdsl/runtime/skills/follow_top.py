"""Where ``follow``'s core goes on a solid target (a knife on a cucumber the other hand holds).

:func:`onto_top` moves the core so that the object's lowest end (a knife's edge) starts over
the target's box (at its far end from the hand that holds it, as ``touch`` goes);
:func:`on_top` fits the whole core into that box (:func:`~oacdsl.runtime.retarget.boxed`):
the room about the target's middle that a container's inside gives does not see that a
cucumber is 15 cm long and 4.5 cm wide. Metres, world and turned-target frames as in
:mod:`oacdsl.runtime.skills.follow`.
"""

from __future__ import annotations

import numpy as np

from oacdsl.runtime.bodies import Body
from oacdsl.runtime.retarget import FOLLOW, Retargeted, boxed
from oacdsl.runtime.shapes import corners as box_corners
from oacdsl.runtime.shapes import world_corners

__all__ = ["END_SPAN_M", "lowest_end", "on_top", "onto_top"]

#: The corners of an object within this of its lowest one make its lowest end, m.
END_SPAN_M = 0.01


def lowest_end(body: Body, t_world_obj: np.ndarray) -> np.ndarray:
    """The middle of ``body``'s lowest corners (within :data:`END_SPAN_M`) at ``t_world_obj``, world (m)."""
    pts = world_corners(body, t_world_obj)
    result: np.ndarray = pts[pts[:, 2] < pts[:, 2].min() + END_SPAN_M].mean(axis=0)
    return result


def on_top(plan: Retargeted, body_o: Body, t_world_obj: np.ndarray, body_t: Body,
           t_world_target: np.ndarray, r_frame: np.ndarray, holder: np.ndarray | None = None) -> Retargeted:
    """``plan`` with its core fitted so that the object's lowest end (at ``t_world_obj`` for the
    core's first keyframe) stays over the solid target's box, :data:`FOLLOW`'s ``top_margin_m``
    inside its edges (:func:`~oacdsl.runtime.retarget.boxed`). With ``holder`` (where the other
    hand holds the target, world): as far towards the box's end away from it as it fits."""
    end = lowest_end(body_o, t_world_obj)
    local = t_world_target[:3, :3].T @ (end - t_world_target[:3, 3])
    to_box = (t_world_target[:3, :3].T @ r_frame)[:2, :2]
    offset = local[:2] - to_box @ plan.positions_m[plan.core, :2]
    own = box_corners(body_t)
    lo, hi = own.min(axis=0)[:2] + FOLLOW.top_margin_m, own.max(axis=0)[:2] - FOLLOW.top_margin_m
    far = None
    if holder is not None:
        u = 0.5 * (lo + hi) - (t_world_target[:3, :3].T @ (holder - t_world_target[:3, 3]))[:2]
        a = int(np.argmax(np.abs(u)))
        far = (a, float(np.sign(u[a])))
    return boxed(plan, to_box, offset, lo, hi, far)


def onto_top(body_o: Body, t_world_obj: np.ndarray, body_t: Body, t_world_target: np.ndarray,
             r_frame: np.ndarray, holder: np.ndarray | None = None) -> np.ndarray:
    """How far (3,), in the turned target frame ``r_frame``, the object at ``t_world_obj`` must move
    across for its lowest end to be over the target's box, :data:`FOLLOW`'s ``top_margin_m``
    inside its edges (zero when it is). With ``holder`` (the point where the other hand holds the
    target, world): at the box's far end from it, as ``touch`` goes (a knife clear of the hand
    that holds the cucumber)."""
    end = lowest_end(body_o, t_world_obj)
    local = t_world_target[:3, :3].T @ (end - t_world_target[:3, 3])
    own = box_corners(body_t)
    lo, hi = own.min(axis=0)[:2], own.max(axis=0)[:2]
    mid = np.mean([lo, hi], axis=0)
    half = hi - mid
    if holder is not None:
        u = mid - (t_world_target[:3, :3].T @ (holder - t_world_target[:3, 3]))[:2]
        if float(np.linalg.norm(u)) > 0.0:
            u = u / float(np.linalg.norm(u))
            reach = min(float(h / abs(x)) for h, x in zip(half, u, strict=True) if abs(x) > 0.0)
            want = mid + u * max(reach - FOLLOW.top_margin_m, 0.0)
            return r_frame.T @ (t_world_target[:3, :3] @ np.append(want - local[:2], 0.0))
    lo, hi = lo + FOLLOW.top_margin_m, hi - FOLLOW.top_margin_m
    want = np.where(lo <= hi, np.clip(local[:2], lo, hi), mid)
    move = t_world_target[:3, :3] @ np.append(want - local[:2], 0.0)
    result: np.ndarray = r_frame.T @ move
    return result
