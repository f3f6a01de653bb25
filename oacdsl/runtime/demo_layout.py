"""``layout demonstrated``: the recording's first-frame layout mapped into the robot's reach.

The demonstrator's frame comes from the two hands at the first frame: *left* is the
horizontal direction from the right hand to the left hand, *up* is +z of the motion
capture, *forward* = left × up, and the origin is between the hands. Each object's
position in that frame (forward ``u``, left ``v``) is mapped onto the robot's table with
one uniform scale ``s ≤ 1`` (the arrangement shrinks to fit, never grows):
``y = s·v`` and ``x = X_CENTRE + s·(u − ū)``, so the objects keep the demonstration's
sides (left of the demonstrator → left of the robot) and their order along both axes.
Objects closer than their footprints plus a gap are then pushed apart along the line
joining them. An object's position is its markers' mean, but its height is that of its base
where the library gives its class a shape that its markers pose (the same fit as contacts from
geometry, :mod:`oacdsl.segmentation.shapefit`): a lid on its bottle then stands a bottle's
height above the bottle's base (whatever the height of their markers), and
:func:`oacdsl.runtime.layout.stacked_on` finds it on top (when both are posed). Light: numpy
only (the recording's reading is the caller's).

Units: metres throughout; the motion capture's z axis is up.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.library import Library
from oacdsl.model import Scene
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.shapefit import pose_shape
from oacdsl.segmentation.shapes import ShapeModel, scene_shapes

__all__ = [
    "X_CENTRE_M", "TableMap", "demonstrated_poses", "demonstrated_positions", "first_frame_poses",
    "first_frame_positions", "map_into_reach", "table_map",
]

#: Where the middle of the demonstrated arrangement goes (robot frame, metres, x forward).
X_CENTRE_M = 0.64
#: Least horizontal length of an object's unit x axis that gives it a heading (cos 60°: more
#: upright than that, an object lies on its side and its turn about the vertical is not its x's).
MIN_HEADING = 0.5
#: Least horizontal distance of a declared marker from the markers' mean that tells a turn, m.
MIN_SPREAD_M = 0.01
#: The region object centres are mapped into: x range and |y| limit (metres), inside the
#: table and within reach of the arms.
X_RANGE_M = (0.50, 0.80)
Y_LIMIT_M = 0.42


def first_frame_positions(recording: Recording, names: list[str],
                          shapes: Mapping[str, ShapeModel] | None = None) -> dict[str, np.ndarray]:
    """Each named marker group's markers' mean position (m) at the first frame where it is seen;
    its height (z) is its base's where ``shapes`` gives it a shape that its markers pose there
    (:func:`~oacdsl.segmentation.shapefit.pose_shape`)."""
    return first_frame_poses(recording, names, shapes)[0]


def first_frame_poses(
    recording: Recording, names: list[str], shapes: Mapping[str, ShapeModel] | None = None
) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """(positions, headings): :func:`first_frame_positions`, and, for each group whose shape
    its markers pose at that frame (its class declares ``markers``), the horizontal unit
    direction (x, y) of its object frame's x axis there (motion capture frame): how it was
    turned about the vertical. An object on its side (x axis within 60° of the vertical) has
    none, nor one whose declared markers all lie on its vertical axis. Groups without a posed
    shape have none either: their markers do not say which way their class's x axis lies."""
    out: dict[str, np.ndarray] = {}
    headings: dict[str, np.ndarray] = {}
    for name in names:
        if name not in recording.groups:
            continue
        pos = recording.group_positions(name)  # (frames, markers, 3)
        seen = np.isfinite(pos).all(axis=2)
        frames = np.flatnonzero(seen.any(axis=1))
        if frames.size:
            f = int(frames[0])
            out[name] = pos[f][seen[f]].mean(axis=0)
            model = (shapes or {}).get(name)
            posed = pose_shape(recording, name, model)[0] if model is not None else None
            if posed is not None and np.isfinite(posed.T_world_object[f, 2, 3]):
                out[name][2] = posed.T_world_object[f, 2, 3]  # the base's height
                x_axis = posed.T_world_object[f, :2, 0]
                if float(np.linalg.norm(x_axis)) >= MIN_HEADING and _tells_turn(posed.model):
                    headings[name] = x_axis / float(np.linalg.norm(x_axis))
    return out, headings


def _tells_turn(model: ShapeModel) -> bool:
    """Whether the declared markers say how the object is turned about its vertical axis: not all
    on that axis (a mixer's markers on its shaft: any turn about it fits them alike)."""
    xy = model.markers_m[:, :2]
    return bool(len(xy)) and float(np.linalg.norm(xy - xy.mean(axis=0), axis=1).max()) >= MIN_SPREAD_M


def demonstrated_positions(recording: Recording, scene: Scene,
                           library: Library | None = None) -> dict[str, np.ndarray]:
    """First-frame positions (m) of the scene's tracked instances in ``recording``, whose
    marker groups are named after the instances or listed by their ``markers``; with the
    ``library``, posed by their classes' shapes where it gives them (:func:`first_frame_positions`)."""
    return demonstrated_poses(recording, scene, library)[0]


def demonstrated_poses(recording: Recording, scene: Scene, library: Library | None = None
                       ) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """:func:`demonstrated_positions` and the headings of :func:`first_frame_poses`."""
    if any(i.markers for i in scene.instances):
        from oacdsl.segmentation.grouping import apply_scene_groups

        recording = apply_scene_groups(recording, scene)
    shapes = scene_shapes(library, scene) if library is not None else None
    return first_frame_poses(recording, [i.name for i in scene.tracked()], shapes)


def _frame(hands: Mapping[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(origin, forward, left) of the demonstrator, horizontal unit vectors."""
    up = np.array([0.0, 0.0, 1.0])
    if "r" in hands and "l" in hands:
        left = np.asarray(hands["l"], float) - np.asarray(hands["r"], float)
        left[2] = 0.0
        if np.linalg.norm(left) > 1e-3:
            left /= np.linalg.norm(left)
            origin = 0.5 * (np.asarray(hands["l"], float) + np.asarray(hands["r"], float))
            return origin, np.cross(left, up), left
    origin = np.mean([np.asarray(h, float) for h in hands.values()], axis=0) if hands else np.zeros(3)
    return origin, np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])


@dataclass(frozen=True)
class TableMap:
    """The demonstration's horizontal frame onto the robot's table (module docstring): a point
    ``p`` (m, motion capture frame) goes to ``(X_CENTRE_M + scale·(u − u_mean), scale·v)`` with
    ``u = (p − origin)·forward`` and ``v = (p − origin)·left`` (before objects are pushed apart)."""

    origin: np.ndarray
    forward: np.ndarray
    left: np.ndarray
    u_mean: float
    scale: float

    def __call__(self, p: np.ndarray) -> np.ndarray:
        """Robot-table (x, y) of ``p``, m."""
        rel = np.asarray(p, float) - self.origin
        return np.array([X_CENTRE_M + self.scale * (float(rel @ self.forward) - self.u_mean),
                         self.scale * float(rel @ self.left)])

    def yaw_rad(self, heading: np.ndarray) -> float:
        """The robot-table yaw (rad, from the robot's x towards its y) of an object whose x axis
        points along ``heading`` (horizontal, motion capture frame): its angle from the
        demonstrator's forward towards the left (the map turns and scales, never mirrors)."""
        h = np.array([heading[0], heading[1], 0.0])
        return math.atan2(float(h @ self.left), float(h @ self.forward))


def table_map(
    objects: Mapping[str, np.ndarray], hands: Mapping[str, np.ndarray], radii: Mapping[str, float]
) -> TableMap:
    """The uniform map of ``objects`` (first-frame positions, m) onto the robot's table: the
    demonstrator's frame from ``hands``, the arrangement's middle at :data:`X_CENTRE_M`,
    shrunk (never grown) until every footprint (``radii``, m) fits the mapping region."""
    origin, forward, left = _frame(hands)
    names = sorted(objects)
    rel = np.array([np.asarray(objects[n], float) - origin for n in names]).reshape(-1, 3)
    u, v = rel @ forward, rel @ left
    if hands and names and float(np.mean(u)) < 0.0:  # the objects are behind: the hands were crossed
        forward, left, u, v = -forward, -left, -u, -v
    u_mean = float(np.mean(u)) if names else 0.0
    r = np.array([radii[n] for n in names])
    half_x = 0.5 * (X_RANGE_M[1] - X_RANGE_M[0])
    scale = 1.0
    for spread, room in ((np.abs(u - u_mean) + r, half_x), (np.abs(v) + r, Y_LIMIT_M)):
        widest = float(np.max(spread)) if names else 0.0
        if widest > room:
            scale = min(scale, room / widest)
    return TableMap(origin, forward, left, u_mean, scale)


def map_into_reach(
    objects: Mapping[str, np.ndarray],
    hands: Mapping[str, np.ndarray],
    radii: Mapping[str, float],
    gap_m: float,
    fixed: Mapping[str, tuple[tuple[float, float], float]] | None = None,
) -> dict[str, tuple[float, float]]:
    """Robot-table (x, y) for each object of ``objects`` (first-frame positions, m); ``hands``
    maps ``"r"``/``"l"`` to the demonstrator's hands; ``radii`` are footprints (m);
    ``fixed``: objects placed otherwise (a scene's ``at``, ``--place``: name → ((x, y),
    radius), m), which stay where they are while the mapped ones are pushed off them (an
    untracked sheet of dough placed by ``at`` under the rolling pin laid out as demonstrated:
    both were built in one another)."""
    if not objects:
        return {}
    names = sorted(objects)
    mapping = table_map(objects, hands, radii)
    still = [v for _, v in sorted((fixed or {}).items())]
    xy = np.array([mapping(objects[n]) for n in names] + [np.asarray(p, float) for p, _ in still])
    r = np.array([radii[n] for n in names] + [rad for _, rad in still], dtype=float)
    xy = _separate(xy, r, gap_m, moving=len(names))[: len(names)]
    r = r[: len(names)]
    out = {n: (float(x), float(y)) for n, (x, y) in zip(names, xy, strict=True)}
    for n, (x, y), rad in zip(names, xy, r, strict=True):
        if not (X_RANGE_M[0] - 0.05 <= x <= X_RANGE_M[1] + 0.05 and abs(y) + rad <= Y_LIMIT_M + 0.1):
            raise RuntimeFailure(
                f"the demonstrated layout does not fit on the robot's table: {n} would stand at"
                f" ({x:.2f}, {y:.2f}) m; give its place in the scene ('{n} at (x, y)') or with --place"
            )
    return out


def _separate(xy: np.ndarray, r: np.ndarray, gap_m: float, rounds: int = 200,
              moving: int | None = None) -> np.ndarray:
    """Push overlapping footprints apart along the line joining their centres (the one
    further left moves left on a tie), keeping them inside the mapping region; only the
    first ``moving`` ones move (default: all), the others are fixed and the one meeting
    them is pushed the whole way."""
    xy = xy.copy()
    n = len(xy)
    m = n if moving is None else moving
    for _ in range(rounds):
        moved = False
        for i in range(n):
            for j in range(i + 1, n):
                if i >= m:  # both fixed
                    continue
                d = xy[j] - xy[i]
                dist = float(np.linalg.norm(d))
                need = r[i] + r[j] + gap_m
                if dist >= need - 1e-9:
                    continue
                if dist > 1e-9:
                    direction = d / dist
                else:
                    direction = np.array([0.0, 1.0 if xy[j, 1] >= xy[i, 1] else -1.0])
                push = 0.5 * (need - dist) + 1e-4
                if j >= m:  # j is fixed: i moves the whole way
                    xy[i] -= 2.0 * push * direction
                else:
                    xy[i] -= push * direction
                    xy[j] += push * direction
                moved = True
        xy[:m, 0] = np.clip(xy[:m, 0], X_RANGE_M[0], X_RANGE_M[1])
        xy[:m, 1] = np.clip(xy[:m, 1], -(Y_LIMIT_M - r[:m]), Y_LIMIT_M - r[:m])
        if not moved:
            break
    return xy


def describe(xy: Mapping[str, tuple[float, float]]) -> str:
    """``red_cup (0.56, 0.28), …`` for messages, metres."""
    return ", ".join(f"{n} ({x:.2f}, {y:.2f})" for n, (x, y) in sorted(xy.items()) if math.isfinite(x))
