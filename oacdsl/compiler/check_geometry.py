"""Checks of object geometry (``class Cup : Container { shape … mass … }``).

Every shape of a class or an instance is checked against
:data:`oacdsl.geometry.PRIMITIVES`: a known shape (E030), known and complete
parameters (E031), known units of the right kind (E032), sizes positive and finite
(E033), a mesh file that exists beside the ``.oac`` file (E034), shapes that stand for
the robot's hand, its table or a liquid not mixed with others (E036), a known colour
(E037); a size over :data:`MAX_SIZE_M` written without a unit is probably millimetres
(W006); an instance that has no shape at all while other classes have some cannot be
built by the runtime (W007). E035 (a property given twice) is found while parsing.
"""

from __future__ import annotations

import math
from pathlib import Path

from oacdsl.compiler.context import Context
from oacdsl.errors import did_you_mean
from oacdsl.geometry import COLOURS, PRIMITIVES, RACK_FLOOR_M, RACK_WALL_M, ROLE_SHAPES, UNITS, resolve
from oacdsl.model import Geometry, ObjectClass, Point, Quantity, Scene, Shape

__all__ = ["MAX_SIZE_M", "check_geometry"]

#: A length written without a unit and longer than this (metres) gets W006.
MAX_SIZE_M = 5.0

_KIND_WORD = {"length": "a length", "mass": "a mass", "factor": "a plain number", "count": "a whole count"}


def _unit_of(unit: str) -> str | None:
    return next((kind for kind, factors in UNITS.items() if unit in factors and unit), None)


def _quantity(ctx: Context, q: Quantity, kind: str, what: str, positive: bool = True) -> float | None:
    """Check one quantity; its SI value, or None when it is wrong."""
    factors = UNITS[kind]
    if q.unit not in factors:
        other = _unit_of(q.unit)
        valid = ", ".join(u for u in factors if u) or "none"
        if other is not None:
            message = f"'{q.unit}' is a unit of {other}, but {what} is {_KIND_WORD[kind]} (units: {valid})"
        else:
            message = (
                f"unknown unit '{q.unit}' in {what}{did_you_mean(q.unit, [u for u in factors if u] or [''])}"
            )
            if kind in ("factor", "count"):
                message = f"{what} is a plain number and takes no unit ('{q.unit}' given)"
        ctx.add("E032", message, q.part("unit"))
        return None
    value = q.value * factors[q.unit]
    if not math.isfinite(value) or (positive and value <= 0.0):
        ctx.add(
            "E033",
            f"{what} must be a positive, finite {kind.replace('factor', 'number')} (got {q.value:g}{q.unit})",
            q.span,
        )
        return None
    if kind == "length" and not q.unit and abs(value) > MAX_SIZE_M:
        ctx.add(
            "W006",
            f"{what} is {value:g} m: a size without a unit is metres"
            f" (millimetres by mistake? write {q.value:g}mm)",
            q.span,
        )
    return value


def _point(ctx: Context, p: Point, what: str) -> None:
    for axis, q in (("x", p.x), ("y", p.y), ("z", p.z)):
        _quantity(ctx, q, "length", f"{axis} of {what}", positive=False)


def _shape(ctx: Context, shape: Shape, owner: str) -> None:
    spec = PRIMITIVES.get(shape.primitive)
    if spec is None:
        ctx.add(
            "E030",
            f"unknown shape '{shape.primitive}'{did_you_mean(shape.primitive, PRIMITIVES)}",
            shape.part("primitive"),
        )
        return
    values: dict[str, float] = {}
    seen: set[str] = set()
    for dim in shape.dims:
        if dim.name not in spec.params:
            hint = did_you_mean(dim.name, spec.params) if spec.params else " (it takes no sizes)"
            ctx.add("E031", f"{shape.primitive} has no parameter '{dim.name}'{hint}", dim.part("name"))
            continue
        if dim.name in seen:
            ctx.add("E031", f"parameter '{dim.name}' of {shape.primitive} is given twice", dim.part("name"))
            continue
        seen.add(dim.name)
        value = _quantity(ctx, dim.value, spec.params[dim.name], f"'{dim.name}' of {shape.primitive}")
        if value is not None:
            values[dim.name] = value
    missing = [p for p in spec.required if p not in seen]
    if missing:
        example = ", ".join(_example(p, spec.params[p]) for p in spec.required)
        ctx.add(
            "E031",
            f"{shape.primitive} of {owner} needs {', '.join(missing)}"
            f" (write e.g. {shape.primitive}({example}))",
            shape.part("primitive"),
        )
    if spec.takes_file and shape.file is None:
        ctx.add("E031", f'mesh of {owner} needs its file: mesh("name.stl")', shape.part("primitive"))
    if not spec.takes_file and shape.file is not None:
        ctx.add("E031", f"{shape.primitive} takes no file, only named sizes", shape.part("file"))
    if shape.at is not None:
        _point(ctx, shape.at, f"the position of a {shape.primitive}")
    _proportions(ctx, shape, values)
    if spec.takes_file and shape.file is not None and shape.span is not None:
        path = Path(shape.span.file).parent / shape.file
        if not path.is_file():
            ctx.add("E034", f"mesh file '{shape.file}' not found (looked for {path})", shape.part("file"))


def _proportions(ctx: Context, shape: Shape, v: dict[str, float]) -> None:
    """Sizes that are each positive but do not fit together."""
    if shape.primitive == "capsule" and {"radius", "height"} <= v.keys() and v["height"] <= 2 * v["radius"]:
        ctx.add("E033", "capsule height must be more than twice its radius (the caps)", shape.span)
    if shape.primitive == "shell" and {"radius", "wall"} <= v.keys() and v["wall"] >= v["radius"]:
        ctx.add("E033", "shell wall must be thinner than its radius", shape.span)
    if shape.primitive == "rack":
        _rack_proportions(ctx, shape, v)
    floor = v.get("floor", v.get("wall"))
    if shape.primitive == "shell" and "height" in v and floor is not None and floor >= v["height"]:
        ctx.add("E033", "shell floor must be thinner than its height", shape.span)


def _example(name: str, kind: str) -> str:
    """A size as an example of ``kind``: ``radius 5cm``, ``slots 4``."""
    return f"{name} {'4' if kind == 'count' else '5cm'}"


def _rack_proportions(ctx: Context, shape: Shape, v: dict[str, float]) -> None:
    """A rack's slots: a whole number, each wider than nothing between its walls, and its
    floor lower than its walls' top."""
    slots = v.get("slots")
    if slots is None:
        return
    if slots != round(slots):
        ctx.add("E033", f"rack slots must be a whole number (got {slots:g})", shape.span)
        return
    if "width" in v and v["width"] - (slots + 1) * v.get("wall", RACK_WALL_M) <= 0:
        ctx.add("E033", f"rack walls leave no room for {slots:g} slots in its width", shape.span)
    if "height" in v and v.get("floor", RACK_FLOOR_M) >= v["height"]:
        ctx.add("E033", "rack floor must be thinner than its height", shape.span)


def _geometry(ctx: Context, geometry: Geometry, owner: str) -> None:
    for shape in geometry.shapes:
        _shape(ctx, shape, owner)
    roles = [s for s in geometry.shapes if s.primitive in ROLE_SHAPES]
    if roles and len(geometry.shapes) > 1:
        ctx.add(
            "E036",
            f"{roles[0].primitive} stands for what the runtime provides and cannot be combined with"
            f" other shapes ({owner} has {len(geometry.shapes)})",
            roles[0].span,
        )
    if geometry.mass is not None:
        _quantity(ctx, geometry.mass, "mass", f"the mass of {owner}")
    if geometry.friction is not None and not (math.isfinite(geometry.friction) and geometry.friction > 0):
        ctx.add(
            "E033",
            f"the friction of {owner} must be positive (got {geometry.friction:g})",
            geometry.part("friction"),
        )
    if geometry.colour is not None and geometry.colour not in COLOURS:
        ctx.add(
            "E037",
            f"unknown colour '{geometry.colour}'{did_you_mean(geometry.colour, COLOURS)}",
            geometry.part("colour"),
        )
    for p in geometry.markers:
        _point(ctx, p, f"a marker of {owner}")


def _shapeless(ctx: Context, scene: Scene) -> None:
    """W007 for every instance that neither it nor its classes give a shape (``ignored`` ones
    are not built: they need none)."""
    for inst in scene.instances:
        if inst.ignored or (inst.geometry is not None and inst.geometry.shapes):
            continue
        if not all(c in ctx.library.classes for c in inst.classes):
            continue  # E003 already
        if resolve(ctx.library, inst) is None:
            ctx.add(
                "W007",
                f"instance '{inst.name}' has no shape: the robot's simulation cannot build it"
                f" (give {' or '.join(inst.classes)} a shape,"
                " e.g. '{ shape cylinder(radius 4cm, height 10cm) }')",
                inst.part("name"),
            )


def check_geometry(ctx: Context) -> None:
    """Check the geometry of every class and of every instance that overrides it; when the
    library gives any class a shape, warn about instances left without one (W007)."""
    shaped = any(c.geometry is not None and c.geometry.shapes for c in ctx.library.classes.values())
    for module in ctx.modules:
        for decl in module.decls:
            if isinstance(decl, ObjectClass) and decl.geometry is not None:
                _geometry(ctx, decl.geometry, f"class '{decl.name}'")
            elif isinstance(decl, Scene):
                for inst in decl.instances:
                    if inst.geometry is not None:
                        _geometry(ctx, inst.geometry, f"instance '{inst.name}'")
                if shaped:
                    _shapeless(ctx, decl)
