"""An object's shape as the segmentation measures it: signed distances and surface samples.

A :class:`ShapeModel` is the library's geometry of one class (``shape`` lines and ``markers``,
docs/language.md) in the object frame (metres; origin at the centre of the object's base, z
up): a union of primitives, each with the centre of its base at ``at`` and its axis along z.
It answers two questions, vectorised over points:

- :meth:`ShapeModel.signed_distance`: how far a point lies outside the shape (negative
  inside), the minimum over its primitives;
- :meth:`ShapeModel.surface_points`: points on its surface, at most
  :data:`SURFACE_SPACING_M` apart (coarser for a large shape, at most
  :data:`MAX_SURFACE_POINTS`), for the distance from another shape's surface.

An open container (``shell``) counts as its solid outline, a cylinder: what is inside a
cup (a spoon stirring, a ladle scooping) touches it. Shapes the segmentation cannot measure
(``mesh``, and the runtime's ``hand``, ``table``, ``balls``) give no model: the instance
falls back to its markers. numpy only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from oacdsl.geometry import ResolvedGeometry, point_si, resolve, si
from oacdsl.library import Library
from oacdsl.model import Scene

__all__ = [
    "MAX_SURFACE_POINTS",
    "SURFACE_SPACING_M",
    "Primitive",
    "ShapeModel",
    "scene_shapes",
    "shape_model",
]

#: Largest spacing of a shape's surface samples, metres (1 cm: a contact's tolerance is larger).
SURFACE_SPACING_M = 0.01
#: Most surface samples of one shape; a larger shape gets a coarser spacing.
MAX_SURFACE_POINTS = 600

_MEASURED = ("box", "cylinder", "sphere", "capsule", "shell", "rack")


@dataclass(frozen=True)
class Primitive:
    """One solid: ``kind`` (box, cylinder, sphere, capsule; a shell is a cylinder), its sizes
    in metres (``size_m``: box (length, width, height); cylinder and capsule (radius, height);
    sphere (radius, 2 radius)), the centre of its base ``at_m`` in the object frame."""

    kind: str
    size_m: tuple[float, float, float]
    at_m: tuple[float, float, float]

    @property
    def height_m(self) -> float:
        return self.size_m[2] if self.kind == "box" else self.size_m[1]

    def signed_distance(self, p: np.ndarray) -> np.ndarray:
        """(N,) signed distance of (N, 3) object-frame points, metres (negative inside)."""
        q = p - np.asarray(self.at_m)
        h = self.height_m
        if self.kind == "box":
            half = np.array([self.size_m[0] / 2, self.size_m[1] / 2, h / 2])
            d = np.abs(q - np.array([0.0, 0.0, h / 2])) - half
            outside = np.linalg.norm(np.maximum(d, 0.0), axis=-1)
            result: np.ndarray = outside + np.minimum(d.max(axis=-1), 0.0)
            return result
        r = self.size_m[0]
        if self.kind == "sphere":
            return np.asarray(np.linalg.norm(q - np.array([0.0, 0.0, r]), axis=-1) - r)
        if self.kind == "capsule":
            z = np.clip(q[..., 2], r, max(r, h - r))
            axis = np.stack([np.zeros_like(z), np.zeros_like(z), z], axis=-1)
            return np.asarray(np.linalg.norm(q - axis, axis=-1) - r)
        radial = np.hypot(q[..., 0], q[..., 1]) - r  # cylinder (and shell: its outline)
        vertical = np.abs(q[..., 2] - h / 2) - h / 2
        outside = np.hypot(np.maximum(radial, 0.0), np.maximum(vertical, 0.0))
        return np.asarray(outside + np.minimum(np.maximum(radial, vertical), 0.0))

    def surface_points(self, spacing_m: float) -> np.ndarray:
        """(P, 3) object-frame points on the surface, at most about ``spacing_m`` apart."""
        h = self.height_m
        if self.kind == "box":
            a, b, c = self.size_m
            pts = []
            for axis, (u, v) in enumerate(((b, c), (a, c), (a, b))):
                gu, gv = _grid(u, spacing_m), _grid(v, spacing_m)
                uu, vv = (g.ravel() for g in np.meshgrid(gu, gv, indexing="ij"))
                for side in (-0.5, 0.5):
                    w = np.full(uu.shape, side * (a, b, c)[axis])
                    cols = [uu, vv]
                    cols.insert(axis, w)
                    pts.append(np.stack(cols, axis=-1))
            out = np.concatenate(pts) + np.array([0.0, 0.0, c / 2])
        elif self.kind == "sphere":
            out = _sphere(self.size_m[0], spacing_m) + np.array([0.0, 0.0, self.size_m[0]])
        else:
            r = self.size_m[0]
            if self.kind == "capsule":
                cap = _sphere(r, spacing_m)
                low, high = r, max(r, h - r)
                wall = _ring_stack(r, low, high, spacing_m)
                lower = cap[cap[:, 2] <= 0] + np.array([0.0, 0.0, low])
                upper = cap[cap[:, 2] >= 0] + np.array([0.0, 0.0, high])
                out = np.concatenate([wall, lower, upper])
            else:
                out = np.concatenate([_ring_stack(r, 0.0, h, spacing_m), _disc(r, 0.0, spacing_m),
                                      _disc(r, h, spacing_m)])
        return out + np.asarray(self.at_m)


def _grid(length: float, spacing: float) -> np.ndarray:
    n = max(2, math.ceil(length / spacing) + 1)
    return np.linspace(-length / 2, length / 2, n)


def _circle(r: float, spacing: float) -> np.ndarray:
    n = max(8, math.ceil(2 * math.pi * r / spacing))
    a = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    return np.stack([r * np.cos(a), r * np.sin(a)], axis=-1)


def _ring_stack(r: float, z0: float, z1: float, spacing: float) -> np.ndarray:
    ring = _circle(r, spacing)
    zs = np.linspace(z0, z1, max(2, math.ceil((z1 - z0) / spacing) + 1))
    return np.concatenate([np.column_stack([ring, np.full(len(ring), z)]) for z in zs])


def _disc(r: float, z: float, spacing: float) -> np.ndarray:
    radii = np.linspace(r, 0.0, max(2, math.ceil(r / spacing) + 1))[:-1]
    rings = [np.zeros((1, 2))] + [_circle(float(rr), spacing) for rr in radii]
    flat = np.concatenate(rings)
    return np.column_stack([flat, np.full(len(flat), z)])


def _sphere(r: float, spacing: float) -> np.ndarray:
    n = max(12, math.ceil(4 * math.pi * r * r / (spacing * spacing)))
    i = np.arange(n) + 0.5
    phi = np.arccos(1 - 2 * i / n)
    theta = math.pi * (1 + 5**0.5) * i
    return r * np.stack([np.cos(theta) * np.sin(phi), np.sin(theta) * np.sin(phi), np.cos(phi)], axis=-1)


@dataclass(frozen=True)
class ShapeModel:
    """A class's shape (a union of :class:`Primitive`) and its declared markers (``markers_m``,
    (k, 3) object frame, metres; (0, 3) when the library gives none)."""

    primitives: tuple[Primitive, ...]
    markers_m: np.ndarray

    def signed_distance(self, points_m: np.ndarray) -> np.ndarray:
        """(...,) signed distance of (..., 3) object-frame points to the shape, metres."""
        p = np.asarray(points_m, dtype=np.float64)
        out = self.primitives[0].signed_distance(p)
        for prim in self.primitives[1:]:
            out = np.minimum(out, prim.signed_distance(p))
        return out

    def surface_points(self) -> np.ndarray:
        """(P, 3) points on the shape's outer surface (points inside another primitive of the
        compound dropped), at most :data:`MAX_SURFACE_POINTS`; computed once."""
        return self._surface

    @cached_property
    def _surface(self) -> np.ndarray:
        spacing = SURFACE_SPACING_M
        while True:
            pts = np.concatenate([p.surface_points(spacing) for p in self.primitives])
            if len(self.primitives) > 1:
                pts = pts[self.signed_distance(pts) > -1e-6]
            if len(pts) <= MAX_SURFACE_POINTS:
                return pts
            spacing *= 1.25

    @cached_property
    def extents_m(self) -> tuple[float, float, float]:
        """The shape's bounding box sizes along its axes, sorted, metres."""
        pts = np.concatenate([p.surface_points(0.02) for p in self.primitives])
        span = pts.max(axis=0) - pts.min(axis=0)
        a, b, c = sorted(float(s) for s in span)
        return (a, b, c)


def shape_model(geometry: ResolvedGeometry | None) -> ShapeModel | None:
    """The model of a resolved geometry, or None when one of its shapes cannot be measured
    (a mesh, the runtime's hand, table or balls) or there is none."""
    if geometry is None or not geometry.shapes:
        return None
    prims = []
    for shape in geometry.shapes:
        if shape.primitive not in _MEASURED:
            return None
        dims = {d.name: si(d.value, "length") for d in shape.dims if d.name != "mass"}
        at = point_si(shape.at) if shape.at is not None else (0.0, 0.0, 0.0)
        if shape.primitive in ("box", "rack"):  # a rack measured as its outer box
            size = (dims["length"], dims["width"], dims["height"])
        elif shape.primitive == "sphere":
            size = (dims["radius"], 2 * dims["radius"], 2 * dims["radius"])
        else:
            size = (dims["radius"], dims["height"], 0.0)
        kind = {"shell": "cylinder", "rack": "box"}.get(shape.primitive, shape.primitive)
        prims.append(Primitive(kind, size, at))
    markers = np.array([point_si(p) for p in geometry.markers], dtype=np.float64).reshape(-1, 3)
    return ShapeModel(tuple(prims), markers)


def scene_shapes(library: Library, scene: Scene) -> dict[str, ShapeModel]:
    """The scene's tracked instances (marker groups) whose geometry the segmentation can
    measure → their shape (the others: none, they are measured by their markers)."""
    out: dict[str, ShapeModel] = {}
    for inst in scene.tracked():
        model = shape_model(resolve(library, inst))
        if model is not None:
            out[inst.name] = model
    return out
