"""From a DSL grasp declaration and an object's simulated pose to a hand pose.

A ``grasp Cls { type T approach A offset (x, y, z) }`` gives the grasp point in the
object frame (metres) and the direction the hand comes from. The runtime puts the
hand's grasp centre (``grasp_r``/``grasp_l``: the facts' *TCP Power* point, 50 mm in
front of the palm) on that point, and orients the hand:

* ``side``: the hand comes horizontally from its own side of the object (the right
  hand from the right), palm facing the object, fingers pointing away from the robot;
* ``top``: the hand comes down, palm facing down, fingers pointing away from the
  robot (or along the offset's horizontal direction, e.g. outward over a bowl's rim);
* ``front``: the hand comes from the robot towards the object, palm facing it, fingers up.
* ``type handle`` with ``side``: a vertical handle (a bar along the object's z) centred
  at ``offset``; the hand comes at it from outside, towards the object's axis, and wraps
  it (see :func:`_handle_plans`). Its direction is the object's, never turned.
* ``type pinch`` with ``top``: the edge of a flat object (a tray, a plate) is pinched
  between the fingertips, beside the edge, and the folded thumb, on the top
  (see :func:`_pinch_plans`); ``offset`` is a point of the top edge.
* ``type rim`` with ``top`` on a round container: the hand comes down with its fingers
  pointing down and its palm facing the centre, the wall of the rim between the finger
  plate (outside) and the folded thumb (inside); ``offset`` gives the rim's radius and
  height (see :func:`_rim_plans`).

Rotationally symmetric objects (every solid round and on the z axis, e.g. a cup, a bowl,
a stick mixer: :attr:`~oacdsl.runtime.bodies.Body.round`) have no preferred azimuth:
the offset is turned about the object's vertical axis to face the hand's approach,
keeping its radius and height; a side grasp of any object at a point on its vertical axis
(a standing tool's handle) likewise. A few variants (the side approach turned by ±30°/±60°,
top grasps along other headings or tilted by 25°) are offered in order of preference;
the skill takes the first the whole-body IK reaches. The approach stops early when
the hand touches the object (guarded move), so an offset a few centimetres off still works.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.model import Grasp
from oacdsl.runtime.transforms import make_T, rot_axis

__all__ = [
    "GraspPlan",
    "plan_grasps",
    "side_clearance",
    "APPROACHES",
    "hand_rotation_for",
    "RIM_GAP_H",
    "HAND_BELOW_CENTRE_M",
    "ON_AXIS_M",
]

APPROACHES = ("side", "top", "front")
#: Distance of the pre-grasp pose from the grasp point, along the approach, metres.
PRE_GRASP_M = 0.20
#: How far the guarded approach may go past the grasp point, metres.
OVERSHOOT_M = 0.06
#: How far the sideways hand reaches below its grasp centre (the little finger's edge), metres.
HAND_BELOW_CENTRE_M = 0.064
#: A grasp point this near the object's vertical axis is on it (any side approach reaches it), m.
ON_AXIS_M = 0.005
#: Free space kept between a sideways hand and its object's support, m: more than the closed
#: loop's 15 mm (``pipeline.markers.ROBOT_DISTANCE_M``): a hand holding an object on a board
#: is not seen touching the board (issue 11, KIT Cut).
CLEARANCE_M = 0.020
#: The least free space under the hand for an object too low for :data:`CLEARANCE_M`, m.
MIN_CLEARANCE_M = 0.012
#: How far the sideways hand's lower edge stays below the object's top, m (its lowest
#: 2.5 cm held the 4.5 cm cucumber of KIT Cut).
GRIP_HEIGHT_M = 0.025
#: Rim grasp from above, fingers pointing down, palm facing the container's centre: where
#: the wall's middle goes, relative to the grasp centre, along -x_H (the palm normal),
#: metres. The finger plate's face is at x_H = -14 mm, the folded thumb's at -45 mm: the
#: wall (7 mm thick) goes midway, the plate outside it, the thumb inside.
RIM_GAP_H = 0.021
#: The finger plate's middle across the hand (y_H, right hand; mirrored for the left)
#: relative to the grasp centre, metres: the plate is centred on the rim point.
RIM_PLATE_ACROSS_M = 0.0075
#: How far the fingertips of a hand pointing down reach below its grasp centre, metres.
FINGERS_BELOW_CENTRE_M = 0.078
#: Free space kept between those fingertips and the support, metres: more than
#: :data:`CLEARANCE_M`, because when a bowl held by its rim is set down, the hand sinks
#: by the arm's tracking lag (~1 cm) after the weld lets go.
RIM_CLEARANCE_M = 0.025
#: Pinch of a flat object's edge (``type pinch approach top``): the fingers point down past
#: the edge, splayed outwards by this angle (rad), so that the palm faces the object's top
#: and the folded thumb comes down on it while the finger plate's tip is beside the edge.
PINCH_TILT_RAD = np.radians(18.0)
#: The finger plate's palm-side face at its tip, relative to the grasp centre, in the hand
#: frame H: this far behind it along the palm normal and this far ahead along the fingers, m.
FINGERTIP_BEHIND_M = 0.0364
FINGERTIP_AHEAD_M = 0.0786
#: Height of the fingertips above the support in a pinch, m (below a plate's top).
PINCH_TIP_ABOVE_SUPPORT_M = 0.004
#: Gap between the fingertips and the edge, outwards, m.
PINCH_TIP_OUTSIDE_M = 0.004


@dataclass(frozen=True)
class GraspPlan:
    """Where the hand goes: grasp pose, pre-grasp pose and the approach direction (world)."""

    grasp: np.ndarray
    pre_grasp: np.ndarray
    approach: np.ndarray
    end: np.ndarray


def hand_rotation_for(palm_normal: np.ndarray, fingers: np.ndarray) -> np.ndarray:
    """R_world_hand with the palm facing ``palm_normal`` and the fingers along ``fingers``.

    Hand frame (the facts' Hand Base): x = back of the hand (-palm normal), y = across
    the fingers, z = along the fingers.
    """
    n = palm_normal / np.linalg.norm(palm_normal)
    a = fingers - np.dot(fingers, n) * n
    a /= np.linalg.norm(a)
    y = np.cross(n, a)
    return np.column_stack([-n, y, a])


def side_clearance(height_m: float | None) -> float:
    """Free space (m) kept under a sideways hand's lower edge for an object whose top is
    ``height_m`` above its support (None: unknown): :data:`CLEARANCE_M`, less (down to
    :data:`MIN_CLEARANCE_M`) when the hand would keep under :data:`GRIP_HEIGHT_M` of it."""
    if height_m is None:
        return CLEARANCE_M
    return min(CLEARANCE_M, max(MIN_CLEARANCE_M, height_m - GRIP_HEIGHT_M))


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def plan_grasps(
    grasp: Grasp,
    symmetric: bool,
    t_world_object: np.ndarray,
    side: str,
    forward: np.ndarray | None = None,
    support_z: float | None = None,
    top_z: float | None = None,
) -> list[GraspPlan]:
    """Candidate grasps of an object (rotationally ``symmetric`` or not) at ``t_world_object``
    by hand ``side``, most natural first (the skill takes the first the whole-body IK can reach).

    ``forward``: the robot's forward direction in the world (default +x). ``support_z``:
    height of the surface the object stands on (m); a side or front grasp is raised so that
    the hand (which reaches :data:`HAND_BELOW_CENTRE_M` below its grasp centre when it
    is held sideways) keeps :func:`side_clearance` over it. ``top_z``: height of the
    object's top (m; None: unknown, as if tall enough).
    """
    if grasp.approach not in APPROACHES:
        raise RuntimeFailure(
            f"grasp {grasp.cls}: unknown approach {grasp.approach!r}"
            f" (the runtime knows {', '.join(APPROACHES)})"
        )
    fwd = _unit(np.array(forward if forward is not None else (1.0, 0.0, 0.0), dtype=float))
    up = np.array([0.0, 0.0, 1.0])
    r_obj, p_obj = t_world_object[:3, :3], t_world_object[:3, 3]
    offset = np.array(grasp.offset, dtype=float)
    radius = float(np.hypot(offset[0], offset[1]))
    plans: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []  # (point, rotation, approach)
    if grasp.approach == "side" and grasp.type == "handle":
        plans = _handle_plans(offset, r_obj, p_obj, fwd, side)
    elif grasp.approach == "side":
        base = np.cross(up, fwd) if side == "r" else -np.cross(up, fwd)  # the right hand comes from the right
        # a grasp point on the object's vertical axis (a standing tool's handle) is the same
        # point from any side: like a round object's, it may be taken turned
        turns = (0.0, -30.0, 30.0, -60.0, 60.0) if symmetric or radius < ON_AXIS_M else (0.0,)
        for deg in turns:
            d = rot_axis(up, np.radians(deg if side == "r" else -deg)) @ base
            point = p_obj + (np.array([0.0, 0.0, offset[2]]) - radius * d if symmetric else r_obj @ offset)
            plans.append(
                (
                    point,
                    hand_rotation_for(d, _unit(np.cross(d, up)) if side == "r" else _unit(np.cross(up, d))),
                    d,
                )
            )
    elif grasp.approach == "top" and grasp.type == "rim" and symmetric:
        return _rim_plans(offset, p_obj, fwd, side, support_z)
    elif grasp.approach == "top" and grasp.type == "pinch":
        return _pinch_plans(offset, r_obj, p_obj, fwd, side, support_z, symmetric)
    elif grasp.approach == "top":
        if symmetric:
            headings = [rot_axis(up, np.radians(a)) @ fwd for a in (0.0, -45.0, 45.0, -90.0, 90.0)]
        else:
            axes = [r_obj[:, 0], -r_obj[:, 0], r_obj[:, 1], -r_obj[:, 1]]
            headings = sorted(
                (_unit(np.array([a[0], a[1], 0.0])) for a in axes), key=lambda h: -float(h @ fwd)
            )
        for tilt, h in ((tilt, h) for tilt in (0.0, 25.0) for h in headings):  # untilted first
            point = p_obj + (np.array([0.0, 0.0, offset[2]]) + radius * h if symmetric else r_obj @ offset)
            tilted = rot_axis(np.cross(up, h), np.radians(tilt))
            plans.append((point, hand_rotation_for(tilted @ -up, tilted @ h), tilted @ -up))
    else:  # front: from the robot towards the object, fingers up
        d = fwd
        point = p_obj + (np.array([0.0, 0.0, offset[2]]) - radius * fwd if symmetric else r_obj @ offset)
        plans.append((point, hand_rotation_for(d, up), d))
    out = []
    clear = side_clearance(None if top_z is None or support_z is None else top_z - support_z)
    for point, rot, d in plans:
        point = point.copy()
        if support_z is not None and grasp.approach != "top":
            point[2] = max(point[2], support_z + HAND_BELOW_CENTRE_M + clear)
        out.append(
            GraspPlan(
                make_T(rot, point),
                make_T(rot, point - PRE_GRASP_M * d),
                d,
                make_T(rot, point + OVERSHOOT_M * d),
            )
        )
    return out


def _rim_plans(
    offset: np.ndarray, p_obj: np.ndarray, fwd: np.ndarray, side: str, support_z: float | None
) -> list[GraspPlan]:
    """A rim grasp from above of a round container (``type rim approach top``): the hand
    comes down with its fingers pointing down and its palm facing the centre, the finger
    plate outside the wall and the folded thumb inside, so that the wall at the rim point
    (``offset``: radius and height, turned to face the hand) goes into the gap between them. The hand is kept
    high enough for its fingertips to clear the support."""
    up = np.array([0.0, 0.0, 1.0])
    radius = float(np.hypot(offset[0], offset[1]))
    toward_hand = np.cross(up, fwd) if side == "l" else -np.cross(up, fwd)
    # rim points: the near side of the container first, then turned towards the hand's side
    headings = [rot_axis(up, np.radians(a)) @ -fwd for a in (0.0, 45.0, -45.0, 90.0, -90.0)]
    headings.sort(key=lambda h: -float(h @ (toward_hand - fwd)))
    out = []
    for h in headings:
        rot = hand_rotation_for(-h, -up)  # palm facing the centre, x_H (back of the hand) outwards
        across = RIM_PLATE_ACROSS_M if side == "r" else -RIM_PLATE_ACROSS_M
        point = p_obj + np.array([0.0, 0.0, offset[2]]) + (radius - RIM_GAP_H) * h - across * rot[:, 1]
        if support_z is not None:
            point[2] = max(point[2], support_z + FINGERS_BELOW_CENTRE_M + RIM_CLEARANCE_M)
        out.append(
            GraspPlan(
                make_T(rot, point),
                make_T(rot, point + PRE_GRASP_M * up),
                -up,
                make_T(rot, point - 0.01 * up),
            )
        )
    return out


def _pinch_plans(
    offset: np.ndarray,
    r_obj: np.ndarray,
    p_obj: np.ndarray,
    fwd: np.ndarray,
    side: str,
    support_z: float | None,
    symmetric: bool,
) -> list[GraspPlan]:
    """A pinch of a flat object's edge from above (``type pinch approach top``).

    ``offset`` is a point of the object's top edge (object frame); the edge faces away
    from the object's axis. The hand comes down with its fingers pointing down just
    outside the edge, splayed outwards by :data:`PINCH_TILT_RAD`, the palm facing the
    object's top: the finger plate's tip ends beside the edge, below the top, and the
    folded thumb on the top, some 7 cm in from the edge; closing squeezes the edge
    between them. Edges tried: the offset's and the opposite one (turned to face the
    hand when the object is round), the one on the hand's side first."""
    up = np.array([0.0, 0.0, 1.0])
    radius = float(np.hypot(offset[0], offset[1]))
    if radius < 1e-6:
        raise RuntimeFailure("a pinch grasp needs an offset on the object's edge, away from its axis")
    toward_hand = -np.cross(up, fwd) if side == "r" else np.cross(up, fwd)
    if symmetric:
        outs = [rot_axis(up, np.radians(a)) @ toward_hand for a in (0.0, 30.0, -30.0, 60.0, -60.0)]
    else:
        out = r_obj @ np.array([offset[0], offset[1], 0.0])
        out = _unit(np.array([out[0], out[1], 0.0]))
        outs = sorted([out, -out], key=lambda u: -float(u @ toward_hand))
    top = p_obj[2] + offset[2]
    base = support_z if support_z is not None else p_obj[2]
    c, s = float(np.cos(PINCH_TILT_RAD)), float(np.sin(PINCH_TILT_RAD))
    plans = []
    for u in outs:
        fingers = s * u - c * up  # down, splayed outwards
        palm = -c * u - s * up  # towards the object's middle and down
        rot = hand_rotation_for(palm, fingers)
        across = RIM_PLATE_ACROSS_M if side == "r" else -RIM_PLATE_ACROSS_M
        edge = p_obj + radius * u
        tip = np.array([edge[0], edge[1], min(top, base + PINCH_TIP_ABOVE_SUPPORT_M)])
        tip += PINCH_TIP_OUTSIDE_M * u
        point = tip + FINGERTIP_BEHIND_M * palm - FINGERTIP_AHEAD_M * fingers - across * rot[:, 1]
        plans.append(
            GraspPlan(
                make_T(rot, point),
                make_T(rot, point + PRE_GRASP_M * up),
                -up,
                make_T(rot, point - 0.003 * up),
            )
        )
    return plans


def _handle_plans(
    offset: np.ndarray, r_obj: np.ndarray, p_obj: np.ndarray, fwd: np.ndarray, side: str
) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """(point, R_world_hand, approach) of a vertical handle at ``offset`` (object frame).

    A handle off the object's axis (a jug's) sticks out horizontally along the offset: the
    hand comes at it from outside, towards the axis, palm facing the axis, the grasp
    centre on the bar and the fingers across it, pointing away from the robot when
    they can. A handle on the axis (a stick) is taken from the hand's own side. The bar is
    round: the approach may also be turned by ±30° about it."""
    up = np.array([0.0, 0.0, 1.0])
    point = p_obj + r_obj @ offset
    out = r_obj @ np.array([offset[0], offset[1], 0.0])
    out[2] = 0.0
    if float(np.linalg.norm(out)) < 1e-6:  # on the axis: come from the hand's own side
        base = np.cross(up, fwd) if side == "r" else -np.cross(up, fwd)
    else:
        base = -_unit(out)
    plans = []
    for deg in (0.0, -30.0, 30.0):
        d = rot_axis(up, np.radians(deg)) @ base
        across = _unit(np.cross(d, up))
        for fingers in sorted((across, -across), key=lambda f: -float(f @ fwd)):
            plans.append((point, hand_rotation_for(d, fingers), d))
    return plans
