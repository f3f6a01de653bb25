"""Generate the ARMAR-III URDF from the facts table (the single source of truth).

``urdf_text()`` builds the robot description that both placo (pinocchio) and MuJoCo
load; ``oacdsl/runtime/assets/armar3.urdf`` is this text, shipped generated (a test
checks it is up to date; ``python -m oacdsl.runtime.urdf`` rewrites it). The URDF
carries MuJoCo's ``<compiler discardvisual="false" fusestatic="false"/>`` block so
that fixed frames (hand, TCPs) stay bodies in MuJoCo; pinocchio ignores it.

Links are named ``<joint>_link`` and are parallel to the world at q = 0, except the
hands (``hand_r``/``hand_l``), whose frame is the facts' Hand Base frame.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from oacdsl.atomic import write_atomic
from oacdsl.runtime.armar3 import FRAMES, JOINTS
from oacdsl.runtime.geometry import Shape, body_shapes, rotation_to_rpy
from oacdsl.runtime.hands import GRASP_CENTRE_H, hand_boxes, hand_joints

__all__ = [
    "urdf_text",
    "URDF_PATH",
    "ASSETS",
    "COLLISIONS_PATH",
    "SELF_COLLISION_PAIRS",
    "collisions_text",
    "write_urdf",
    "hand_rotation",
    "link_world_positions",
]

ASSETS = Path(__file__).resolve().parent / "assets"
#: The generated robot description shipped with the package.
URDF_PATH = ASSETS / "armar3.urdf"

#: Link pairs placo keeps apart (read by placo from ``collisions.json`` next to the URDF):
#: hands and forearms against the torso and against each other (the platform column is
#: below the table top, where the skills never take a hand).
#: Self-collision avoidance costs per pair, so only pairs a manipulation task can bring
#: together are listed; MuJoCo ignores robot-robot contacts altogether.
SELF_COLLISION_PAIRS: tuple[tuple[str, str], ...] = (
    *(
        (f"{part}_{s}", body)
        for s in ("r", "l")
        for part in ("hand", "underarm")
        for body in ("hip_yaw_link",)
    ),
    ("hand_r", "hand_l"),
    ("underarm_r", "underarm_l"),
    ("hand_r", "underarm_l"),
    ("hand_l", "underarm_r"),
)
COLLISIONS_PATH = ASSETS / "collisions.json"

_HAND_MASS_KG = 0.8  # Hand Palm 1 in the facts


def _f(v: float) -> str:
    s = f"{v:.9f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def _v(v: tuple[float, ...] | np.ndarray) -> str:
    return " ".join(_f(float(x)) for x in v)


def link_world_positions() -> dict[str, np.ndarray]:
    """World position (m) of each body link's origin at q = 0."""
    pos: dict[str, np.ndarray] = {"base_link": np.zeros(3)}
    for j in JOINTS:
        parent = "base_link" if j.parent is None else f"{j.parent}_link"
        pos[f"{j.name}_link"] = pos[parent] + np.array(j.origin_m)
    return pos


def hand_rotation(side: str) -> np.ndarray:
    """R_world_hand at q = 0: columns are the Hand Base frame's axes."""
    frame = next(f for f in FRAMES if f.name == f"hand_base_{side}")
    return np.column_stack([np.array(a, dtype=float) for a in frame.axes])


def _geometry(shape: Shape) -> str:
    if shape.kind == "box":
        return f'<box size="{_v(shape.size)}"/>'
    if shape.kind == "cylinder":
        return f'<cylinder radius="{_f(shape.size[0])}" length="{_f(shape.size[1])}"/>'
    return f'<sphere radius="{_f(shape.size[0])}"/>'


def _inertial(mass: float, shapes: list[Shape]) -> str:
    if shapes:
        lo = np.min([np.array(s.xyz) - _half_extent(s) for s in shapes], axis=0)
        hi = np.max([np.array(s.xyz) + _half_extent(s) for s in shapes], axis=0)
    else:
        lo, hi = -np.full(3, 0.02), np.full(3, 0.02)
    c, d = (lo + hi) / 2, hi - lo
    ixx = mass * (d[1] ** 2 + d[2] ** 2) / 12
    iyy = mass * (d[0] ** 2 + d[2] ** 2) / 12
    izz = mass * (d[0] ** 2 + d[1] ** 2) / 12
    return (
        f'    <inertial><origin xyz="{_v(c)}" rpy="0 0 0"/><mass value="{_f(mass)}"/>'
        f'<inertia ixx="{ixx:.6g}" ixy="0" ixz="0" iyy="{iyy:.6g}" iyz="0" izz="{izz:.6g}"/></inertial>'
    )


def _half_extent(s: Shape) -> np.ndarray:
    if s.kind == "box":
        return np.array(s.size) / 2
    r = s.size[0]
    if s.kind == "sphere":
        return np.full(3, r)
    return np.full(3, max(r, s.size[1] / 2))


def _link(name: str, mass: float | None, shapes: list[Shape]) -> str:
    lines = [f"  <link name={quoteattr(name)}>"]
    if mass is not None:
        lines.append(_inertial(mass, shapes))
    for i, s in enumerate(shapes):
        origin = f'<origin xyz="{_v(s.xyz)}" rpy="{_v(s.rpy)}"/>'
        lines.append(
            f'    <visual name="{name}_v{i}">{origin}<geometry>{_geometry(s)}</geometry>'
            f'<material name="{name}_m{i}"><color rgba="{_v(s.rgba)}"/></material></visual>'
        )
        lines.append(
            f'    <collision name="{name}_c{i}">{origin}<geometry>{_geometry(s)}</geometry></collision>'
        )
    lines.append("  </link>")
    return "\n".join(lines)


def _joint(
    name: str,
    kind: str,
    parent: str,
    child: str,
    xyz: tuple[float, ...] | np.ndarray,
    rpy: tuple[float, ...] = (0.0, 0.0, 0.0),
    axis: tuple[float, ...] | None = None,
    limits: tuple[float, float] | None = None,
) -> str:
    lines = [
        f'  <joint name="{name}" type="{kind}">',
        f'    <parent link="{parent}"/><child link="{child}"/>',
        f'    <origin xyz="{_v(xyz)}" rpy="{_v(rpy)}"/>',
    ]
    if axis is not None:
        lines.append(f'    <axis xyz="{_v(axis)}"/>')
    if limits is not None:
        lines.append(
            f'    <limit lower="{_f(limits[0])}" upper="{_f(limits[1])}" effort="1000" velocity="10"/>'
        )
    lines.append("  </joint>")
    return "\n".join(lines)


def _to_link(shapes: list[Shape], origin: np.ndarray) -> list[Shape]:
    return [
        Shape(s.kind, s.size, tuple(float(x) for x in np.array(s.xyz) - origin), s.rpy, s.rgba)  # type: ignore[arg-type]
        for s in shapes
    ]


def _hand_shapes(side: str) -> dict[str, list[Shape]]:
    out: dict[str, list[Shape]] = {}
    color = (0.85, 0.85, 0.88, 1.0)
    for b in hand_boxes(side):
        out.setdefault(b.link, []).append(Shape("box", tuple(2 * h for h in b.half), b.centre, rgba=color))
    return out


def urdf_text() -> str:
    """The complete URDF of the model (deterministic)."""
    world = link_world_positions()
    shapes = body_shapes()
    parts = [
        '<?xml version="1.0"?>',
        "<!-- Generated by oacdsl.runtime.urdf from the ARMAR-III facts table; do not edit. -->",
        '<robot name="armar3">',
        '  <mujoco><compiler discardvisual="false" fusestatic="false" angle="radian"/></mujoco>',
        '  <link name="base_link"/>',
    ]
    for j in JOINTS:
        link = f"{j.name}_link"
        parent = "base_link" if j.parent is None else f"{j.parent}_link"
        parts.append(_link(link, j.mass_kg, _to_link(shapes.get(link, []), world[link])))
        parts.append(_joint(j.name, j.kind, parent, link, j.origin_m, axis=j.axis, limits=j.limits))
    for side in ("r", "l"):
        hshapes = _hand_shapes(side)
        hand = f"hand_{side}"
        parts.append(_link(hand, _HAND_MASS_KG, hshapes.get(hand, [])))
        parts.append(
            _joint(
                f"{hand}_fixed",
                "fixed",
                f"wrist_2_{side}_link",
                hand,
                (0.0, 0.0, 0.0),
                rotation_to_rpy(hand_rotation(side)),
            )
        )
        for hj in hand_joints(side):
            link = f"{hj.name}_link"
            parts.append(_link(link, hj.mass_kg, hshapes.get(link, [])))
            parts.append(
                _joint(hj.name, "revolute", hj.parent, link, hj.origin, axis=hj.axis, limits=hj.limits)
            )
        g = GRASP_CENTRE_H if side == "r" else (GRASP_CENTRE_H[0], -GRASP_CENTRE_H[1], GRASP_CENTRE_H[2])
        parts.append(f'  <link name="grasp_{side}"/>')
        parts.append(_joint(f"grasp_{side}_fixed", "fixed", hand, f"grasp_{side}", g))
    for fr in FRAMES:
        if fr.name.startswith("hand_base_"):
            continue
        rot = np.column_stack([np.array(a, dtype=float) for a in fr.axes])
        parts.append(f'  <link name="{fr.name}"/>')
        parts.append(
            _joint(
                f"{fr.name}_fixed", "fixed", f"{fr.parent}_link", fr.name, fr.offset_m, rotation_to_rpy(rot)
            )
        )
    parts.append("</robot>")
    return "\n".join(parts) + "\n"


def _link_name(part: str) -> str:
    return part if part.startswith(("hand_", "base_link")) or part.endswith("_link") else f"{part}_link"


def collisions_text() -> str:
    """placo's ``collisions.json``: the self-collision pairs as link names."""
    pairs = [[_link_name(a), _link_name(b)] for a, b in SELF_COLLISION_PAIRS]
    return json.dumps(pairs, indent=1) + "\n"


def write_urdf(path: Path = URDF_PATH) -> Path:
    """Write :func:`urdf_text` to ``path`` and :func:`collisions_text` next to it, atomically."""
    write_atomic(path, urdf_text())
    write_atomic(path.with_name("collisions.json"), collisions_text())
    return path


if __name__ == "__main__":  # python -m oacdsl.runtime.urdf  → regenerate the shipped asset
    print(write_urdf(), file=sys.stdout)
