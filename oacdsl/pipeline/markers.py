"""Virtual markers on the simulated robot and objects, for the closed loop.

The robot's execution is observed the way the demonstration was: by markers whose
trajectories the same AAS segments. :class:`VirtualMarkers` is an observer of the
control loop (like the runtime's :class:`~oacdsl.runtime.recorder.MarkerRecorder`); at
every ``1 / rate_hz`` seconds of simulated time it stores the poses of the bodies that
carry markers (a copy of a few rows of MuJoCo's ``xpos``/``xmat``), and
:meth:`VirtualMarkers.to_recording` turns them into a
:class:`~oacdsl.segmentation.recording.Recording` with one marker group per instance.

**Where the markers sit.** Like the demonstration's markers, functionally: on the
surfaces by which an instance takes part in the task's relations.

- A hand: the centre of every face of its palm, finger plate and thumb boxes, and a
  20 mm grid on the faces that grip (palm and finger plate: -x of the hand frame; thumb: +z;
  see :mod:`oacdsl.runtime.hands`).
Containers are the objects whose shape has a ``shell`` (:mod:`oacdsl.geometry`); a cup
below means a container with a grasp declared for it, a bowl one without.

- A cup: rings of 12 on its outer wall every 20 mm from the rim down to 40 % of its
  height (where a hand holds it, as the demonstration's rim and handle markers), and its
  floor inside (where a liquid lies; floor markers sit one ball radius above the floor, where
  the centre of a resting ball is).
- A bowl: its floor inside on a 20 mm grid, and a ring low on the outside wall (where
  something standing next to it would touch it). Nothing on the rim: a cup poured
  over the bowl passes close to the rim without being *in* it, as in the demonstration.
- Any other object (mixer, sponge, tray): its collision shapes — a grid of at most 6 × 6
  cells of about 20 mm on every box face; a thin cylinder (a grip, radius up to 25 mm) has
  rings of 6 every 20 mm along it, a thicker one (a mixer's head) a ring round the middle;
  both the centres of their caps and a ring on each cap at 60 % of the radius. A disc (a
  cylinder 5 cm or more across its radius and at most half as high: a plate) has a 20 mm
  grid on both faces and a ring every 20 mm round its rim: a hand pinching its edge or a
  sponge on it touches it far from the sparse rings.
- A liquid: the centre of every ball (the liquid is where its balls are; the
  demonstration's single "big marker" stands for the same thing).

The grids are dense enough that two surfaces in contact have a pair of markers 5–8 mm
apart (measured on the dough task's grasps), well inside the distance below.

**Distance.** The demonstration's markers sit 5–9 cm off the surfaces that touch, so
its AAS uses d = 150 mm; virtual markers sit *on* the surfaces and have no noise, so
the closed loop uses :data:`ROBOT_DISTANCE_M` = 15 mm: below the 18 mm between the
centres of two touching balls and below the gap between a liquid's balls and the hand
outside the cup and of the balls to a mixer in their bowl (25 mm and more), above the
14 mm by which a ball resting anywhere on a 20 mm floor grid can miss its nearest marker.

**Merge window.** :data:`ROBOT_MERGE_S` = 1 s (or the demonstration's, if longer). The
robot's liquid is ten or so frictionless balls: after they leave the cup they roll on the
bowl's floor for up to 0.7 s before one rests there long enough (``n`` frames slower than
``v``) to start touching it, while the demonstration's liquid marker rests 0.16 s after it
leaves the cup. With the demonstration's 0.3 s, a pour would be two keyframes (the liquid
leaves the cup; later, it is in the bowl); 1 s makes it one, as in the demonstration. Every
robot step lasts 4 s or more, so the window never merges two steps.

**Detector.** Always ``"paper"`` (:data:`ROBOT_MODE`), whatever the demonstration's. The
adaptive detector learns per-pair contact distances from co-motion because the
demonstration's markers sit centimetres off the touching surfaces; the virtual markers sit
*on* them, without noise, and :data:`ROBOT_DISTANCE_M` is tuned for them, so Eq. 1/2 with
that fixed distance is the right rule here. Under the adaptive detector the robot's
recording gets a different initial world state than the demonstration and the closed loop
fails to verify.

The speed ``v`` and the frames ``n`` are the demonstration's.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording

__all__ = [
    "MARKER_RATE_HZ",
    "ROBOT_DISTANCE_M",
    "ROBOT_MERGE_S",
    "ROBOT_MODE",
    "VirtualMarkers",
    "robot_params",
]

#: Sampling rate of the virtual markers, Hz of simulated time (the demonstration's rate).
MARKER_RATE_HZ = 100.0
#: AAS distance threshold for markers that sit on the surfaces, metres.
ROBOT_DISTANCE_M = 0.015
#: AAS merge window for the robot's recording, seconds (at least the demonstration's).
ROBOT_MERGE_S = 1.0
#: AAS touch detector for the robot's recording: the paper's Eq. 1/2 (on-surface markers).
ROBOT_MODE = "paper"
#: Spacing of the markers on a bowl's floor, metres.
FLOOR_SPACING_M = 0.02
#: Spacing of the markers on the surfaces that grip or are gripped (hands, grips, boxes), metres.
GRIP_SPACING_M = 0.02
#: Cylinders up to this radius are grips (rings all along them), metres.
GRIP_RADIUS_M = 0.025
#: Cylinders at least this wide and at most half as high as wide are discs (a plate, a
#: tray): a grid on both faces and a rim ring, so that a hand pinching the edge or a
#: sponge anywhere on the face has a marker within the distance, metres.
DISC_RADIUS_M = 0.05
#: Height of a container's floor markers above its floor when the scene has no liquid, metres.
DEFAULT_BALL_RADIUS_M = 0.009
#: At most this many grid cells along one side of a box face.
MAX_CELLS = 6

Points = list[tuple[float, float, float]]


def robot_params(demonstration: AasParams) -> AasParams:
    """The demonstration's AAS parameters with the distance for on-surface markers, the
    robot's merge window and always the paper's detector (see the module docstring)."""
    return replace(
        demonstration,
        distance_m=ROBOT_DISTANCE_M,
        merge_s=max(demonstration.merge_s, ROBOT_MERGE_S),
        mode=ROBOT_MODE,
    )


def _ring(radius: float, z: float, k: int, phase: float = 0.0) -> Points:
    return [
        (radius * math.cos(phase + 2 * math.pi * i / k), radius * math.sin(phase + 2 * math.pi * i / k), z)
        for i in range(k)
    ]


def _disc(radius: float, z: float, spacing: float) -> Points:
    n = int(radius / spacing)
    return [
        (i * spacing, j * spacing, z)
        for i in range(-n, n + 1)
        for j in range(-n, n + 1)
        if math.hypot(i * spacing, j * spacing) <= radius + 1e-9
    ]


def _box_face(half: np.ndarray, axis: int, sign: int, spacing: float) -> Points:
    """Cell-centred grid on the face ``sign`` · ``axis`` of a box with half sizes ``half``."""
    u, v = (i for i in range(3) if i != axis)
    nu, nv = (min(MAX_CELLS, max(1, math.ceil(2 * half[k] / spacing))) for k in (u, v))
    out = []
    for i in range(nu):
        for j in range(nv):
            p = [0.0, 0.0, 0.0]
            p[axis] = sign * float(half[axis])
            p[u] = float(half[u]) * ((2 * i + 1) / nu - 1)
            p[v] = float(half[v]) * ((2 * j + 1) / nv - 1)
            out.append((p[0], p[1], p[2]))
    return out


def _geom_local(model: Any, g: int, grip_face: tuple[int, int] | None = None) -> Points:
    """Points on geom ``g`` in its own frame (see the module docstring)."""
    import mujoco

    size = model.geom_size[g]
    kind = int(model.geom_type[g])
    if kind == mujoco.mjtGeom.mjGEOM_BOX:
        centres = [p for a in range(3) for s in (-1, 1) for p in _box_face(size, a, s, math.inf)]
        if grip_face is not None:  # a hand: the face centres and a grid on the face that grips
            return [*centres, *_box_face(size, grip_face[0], grip_face[1], GRIP_SPACING_M)]
        return [p for a in range(3) for s in (-1, 1) for p in _box_face(size, a, s, GRIP_SPACING_M)]
    if kind in (mujoco.mjtGeom.mjGEOM_CYLINDER, mujoco.mjtGeom.mjGEOM_CAPSULE):
        r, h = float(size[0]), float(size[1])
        caps = [(0.0, 0.0, -h), (0.0, 0.0, h), *_ring(0.6 * r, -h, 6), *_ring(0.6 * r, h, 6)]
        if r >= DISC_RADIUS_M and 2 * h <= r:  # a disc (a plate): grids on both faces, a dense rim
            k = math.ceil(2 * math.pi * r / GRIP_SPACING_M)
            return [*_disc(r, -h, GRIP_SPACING_M), *_disc(r, h, GRIP_SPACING_M), *_ring(r, 0.0, k)]
        if r > GRIP_RADIUS_M:  # a body (a mixer's head): caps and a ring round the middle
            return [*caps, *_ring(r, 0.0, 8, math.pi / 8)]
        n = max(1, math.ceil(2 * h / GRIP_SPACING_M))  # a grip: rings all along it
        rings = (p for k in range(n) for p in _ring(r, h * ((2 * k + 1) / n - 1), 6, k * math.pi / 6))
        return [*caps, *rings]
    return [(0.0, 0.0, 0.0)]  # spheres, ellipsoids, meshes: the centre


def _body_points(
    model: Any, body: int, grip_face: tuple[int, int] | None = None, skip: str | None = None
) -> np.ndarray:
    """Points on the collision shapes of ``body``, in the body frame (geoms whose name
    starts with ``skip`` left out)."""
    import mujoco

    out = []
    for g in np.flatnonzero(model.geom_bodyid == body):
        if skip is not None and model.geom(int(g)).name.startswith(skip):
            continue
        rot = np.zeros(9)
        mujoco.mju_quat2Mat(rot, model.geom_quat[g])
        local = np.asarray(_geom_local(model, int(g), grip_face), dtype=float)
        out.append(local @ rot.reshape(3, 3).T + model.geom_pos[g])
    return np.concatenate(out) if out else np.zeros((0, 3))


def _hand_grip_face(body_name: str) -> tuple[int, int]:
    """The face of a hand link's boxes that grips (runtime.hands): palm and finger plate -x, thumb +z."""
    return (2, 1) if body_name.startswith("thumb_") else (0, -1)


def _object_points(model: Any, instance: str, shape: Any, body: int, ball_radius: float) -> np.ndarray:
    """Markers of an object (``shape``: its :class:`~oacdsl.runtime.bodies.Body`): its
    collision shapes, except for an open container (see the module docstring): a graspable
    one (a cup) on its outer wall's upper part and its floor, one that is not (a bowl) on
    its floor and low on its outer wall; the other parts of a compound (a jug's handle)
    by their collision shapes."""
    cont = shape.shell
    if cont is None:
        return _body_points(model, body)
    radius, height, inner = cont.dims["radius"], cont.top, shape.inner_radius
    x0, y0, _ = cont.at
    # the floor markers sit one ball radius above the floor inside, where a resting ball's centre is
    floor = shape.floor + ball_radius
    if shape.graspable:  # the outer wall's upper part (where a hand holds it), the floor inside
        n = max(1, round(0.6 * height / GRIP_SPACING_M))
        rings = [
            p for k in range(n + 1) for p in _ring(radius, height * (1 - 0.6 * k / n), 12, k * math.pi / 12)
        ]
        points = [*rings, (0.0, 0.0, floor), *_ring(0.5 * inner, floor, 4)]
    else:
        points = [*_disc(inner - ball_radius, floor, FLOOR_SPACING_M), *_ring(radius, 0.25 * height, 8)]
    out = np.asarray(points, dtype=float) + np.array([x0, y0, 0.0])
    if len(shape.solids) == 1:
        return out
    shell_name = f"{instance}/part{shape.solids.index(cont)}/"
    return np.concatenate([out, _body_points(model, body, skip=shell_name)])


class VirtualMarkers:
    """Records the poses of the bodies that carry markers; an observer of the control loop.

    ``world`` is the :class:`~oacdsl.runtime.simworld.SimWorld` of the run (read for
    its model and layout only); add the recorder with ``controller.add_observer``.
    """

    def __init__(self, world: Any, rate_hz: float = MARKER_RATE_HZ) -> None:
        self.rate_hz = rate_hz
        model = world.model
        bodies: list[int] = []
        # (instance, [(index into bodies, local points (k, 3))])
        self._groups: list[tuple[str, list[tuple[int, np.ndarray]]]] = []

        def slot(body: int) -> int:
            bodies.append(body)
            return len(bodies) - 1

        for inst, side in sorted(world.layout.hands.items()):
            parts = [
                (slot(b), _body_points(model, b, _hand_grip_face(model.body(b).name)))
                for b in world.hand_bodies[side]
            ]
            self._groups.append((inst, [p for p in parts if len(p[1])]))
        balls = [b.ball_radius for b in world.layout.bodies.values() if b.ball_radius > 0]
        ball_radius = max(balls, default=DEFAULT_BALL_RADIUS_M)
        for p in world.layout.placements:
            body = model.body(p.name).id
            points = _object_points(model, p.name, p.body, body, ball_radius)
            self._groups.append((p.name, [(slot(body), points)]))
        for liquid, balls in sorted(world.built.balls.items()):
            origin = np.zeros((1, 3))
            self._groups.append((liquid, [(slot(model.body(b).id), origin) for b in balls]))
        self._groups.sort(key=lambda g: g[0])
        self._bodies = np.asarray(bodies, dtype=int)
        self.times_s: list[float] = []
        self._xpos: list[np.ndarray] = []
        self._xmat: list[np.ndarray] = []

    @property
    def instances(self) -> tuple[str, ...]:
        return tuple(name for name, _ in self._groups)

    def marker_counts(self) -> dict[str, int]:
        """Instance → number of markers."""
        return {name: sum(len(local) for _, local in parts) for name, parts in self._groups}

    def __call__(self, world: Any) -> None:
        self.times_s.append(world.time_s)
        self._xpos.append(world.data.xpos[self._bodies].copy())
        self._xmat.append(world.data.xmat[self._bodies].copy())

    @property
    def n_frames(self) -> int:
        return len(self.times_s)

    def _blocks(self, instances: Sequence[str] | None) -> list[tuple[str, list[np.ndarray]]]:
        """(instance, its parts' (F, k, 3) world positions, metres) in instance order."""
        if not self._xpos:
            raise RuntimeFailure("the run recorded no marker frames")
        xpos = np.asarray(self._xpos)  # (F, B, 3)
        xmat = np.asarray(self._xmat).reshape(len(self._xmat), -1, 3, 3)  # (F, B, 3, 3)
        return [
            (name, [np.matmul(local, xmat[:, b].transpose(0, 2, 1)) + xpos[:, b][:, None, :]
                    for b, local in parts])
            for name, parts in self._groups
            if instances is None or name in instances
        ]

    def points(self, instances: Sequence[str] | None = None) -> dict[str, np.ndarray]:
        """Instance → (F, k, 3) marker positions in the world frame, metres."""
        return {name: np.concatenate(blocks, axis=1) for name, blocks in self._blocks(instances)}

    def to_recording(self, source: str = "robot", instances: Sequence[str] | None = None) -> Recording:
        """The markers as a recording at :attr:`rate_hz` (markers ``instance:mK``): the same
        recording as ``recording_from_points(self.points(instances), ...)``, built with one copy
        of the (F, M, 3) positions instead of two."""
        blocks = self._blocks(instances)
        names: list[str] = []
        index: dict[str, tuple[int, ...]] = {}
        for name, parts in blocks:
            k = sum(p.shape[1] for p in parts)
            index[name] = tuple(range(len(names), len(names) + k))
            names.extend(f"{name}:m{i + 1}" for i in range(k))
        positions = np.concatenate([p for _, parts in blocks for p in parts], axis=1)
        times = np.arange(positions.shape[0]) / float(self.rate_hz)
        return Recording(source, float(self.rate_hz), times, tuple(names), positions, index)
