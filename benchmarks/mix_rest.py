"""Where KIT Mix's two servers come to rest when let go of leaning in the bowl (no robot).

    python benchmarks/mix_rest.py [--library DIR] [--seconds S] [--verbose]
    python benchmarks/mix_rest.py --leans RECORDING [RECORDING …]

The bowl and the two servers of ``scene kit_mix`` (``library/kit``, or ``--library DIR``: a
copy with other server shapes) are built as ``oacc run`` builds them; each server is put in the
bowl leaning, with its head's edge on the floor (raised until it no longer cuts into the bowl,
i.e. onto the rim when it leans farther than the rim lets it) and let go of; after ``--seconds``
of simulation the benchmark notes whether the two touched at any moment and how far each ends
from the vertical (the verifier calls above 45° "on its side": the demonstrated servers end on
their sides). Poses, in the bowl's frame (x away from the robot, y to its left, cm): the head's
middle at (x, y), the server leaning ``lean`` degrees towards the horizontal direction
``toward`` degrees from x. Two families, each printed as "free" (never touched) and "free and
on its side" out of the poses tried:

- *mirrored*: the left hand's server at (x, y) leaning towards +toward, the right's at
  (x, -y) towards -toward, as ``mix_both { lean … }`` lets them go (x -7…-1, y 3.5…6.5,
  toward 0…45°, lean 48° and 56°);
- *crossed*: one server on the middle line from the near wall, leaning away from the robot,
  the other's head by the middle, leaning to the right (toward -80…-100°);
- *outward*: as the person left them, each leaning out towards its own side (toward ±90°), the
  heads 3.5…6.5 cm either side of the middle line (x -2…2, lean 25°, 35°, 45°).

``--leans``: instead, how far each server's long axis (its markers' principal direction) is
from the vertical at the first and at the last frame of recordings (the demonstration, a
robot's ``execution.c3d``): the demonstrated servers start lying and end leaning; the verifier
judges their turn from how they started (docs/verify.md).

This measures the physics the skill works in, not the skill: a server leaning on a round rim
rolls (its round head on its edge and its round handle on the rim) until its line passes
through the bowl's middle, where the other one is; modelled flat (``library/kit`` since
2026-11-26: a flat box handle, a shallow square head) it stays where it falls. On-their-sides
counts the verifier's class relative to a server that started standing, as the robot's do.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT)]

TOOLS = ("salad_fork", "salad_spoon")
BOWL = "mixing_bowl_green"
BINDING = {"h1": "left_hand", "f": "salad_fork", "h2": "right_hand", "s": "salad_spoon", "b": BOWL}
#: Where the objects stand before the servers are put in the bowl (robot frame, m).
PLACES = {BOWL: (0.55, 0.0), "salad_fork": (0.45, 0.45), "salad_spoon": (0.45, -0.45)}


def _world(library: Path):  # type: ignore[no-untyped-def]
    from oacdsl.api import load_library
    from oacdsl.runtime.executor import prepare

    run = prepare(load_library(library), "mix_both", BINDING, scene="kit_mix", places=PLACES)
    return run.world, run.context.body(BOWL).floor


def _pose(x_cm: float, y_cm: float, toward_deg: float, lean_deg: float, head_m: float):  # type: ignore[no-untyped-def]
    """(R_bowl_tool, base position in the bowl frame, m) of a server leaning as described."""
    from oacdsl.runtime.transforms import rot_axis

    u = np.array([math.cos(math.radians(toward_deg)), math.sin(math.radians(toward_deg)), 0.0])
    r = rot_axis(np.cross((0.0, 0.0, 1.0), u), math.radians(lean_deg))
    return r, np.array([x_cm / 100, y_cm / 100, head_m * math.sin(math.radians(lean_deg))])


def trial(world, floor_m: float, poses, seconds: float) -> tuple[bool, list[float], list[np.ndarray]]:  # type: ignore[no-untyped-def]
    """Put both servers at ``poses`` (one (x, y, toward, lean) each) on the bowl's floor
    (``floor_m`` above its base), let them go; (whether they touched, each one's end lean in
    degrees, each head's end (x, y) in cm)."""
    import mujoco

    m, d = world.model, world.data
    t_bowl = world.body_pose(BOWL)
    floor = t_bowl[:3, 3] + t_bowl[:3, 2] * (floor_m + 0.001)
    joint = {t: int(m.body(t).jntadr[0]) for t in TOOLS}
    placed = {t: _pose(*p, head_m=0.03) for t, p in zip(TOOLS, poses, strict=True)}
    lift = dict.fromkeys(TOOLS, 0.0)

    def put() -> dict[str, float]:
        for t, (r, base) in placed.items():
            q = np.zeros(4)
            mujoco.mju_mat2Quat(q, (t_bowl[:3, :3] @ r).reshape(-1))
            a, v = m.jnt_qposadr[joint[t]], m.jnt_dofadr[joint[t]]
            d.qpos[a:a + 3] = floor + t_bowl[:3, :3] @ base + (0.0, 0.0, lift[t])
            d.qpos[a + 3:a + 7] = q
            d.qvel[v:v + 6] = 0.0
        mujoco.mj_forward(m, d)
        deepest = dict.fromkeys(TOOLS, 0.0)
        for i in range(d.ncon):
            c = d.contact[i]
            pair = {m.body(int(m.geom_bodyid[c.geom1])).name, m.body(int(m.geom_bodyid[c.geom2])).name}
            for t in TOOLS:
                if pair == {t, BOWL}:
                    deepest[t] = min(deepest[t], float(c.dist))
        return deepest

    for _ in range(50):  # raised until neither cuts into the bowl (onto the rim, leaning far)
        cut = [t for t, dist in put().items() if dist < -0.001]
        if not cut:
            break
        for t in cut:
            lift[t] += 0.002
    touched = False
    for step in range(round(seconds / m.opt.timestep)):
        mujoco.mj_step(m, d)
        touched = touched or (step % 5 == 0 and world.touching(*TOOLS))
    leans, heads = [], []
    for t in TOOLS:
        pose = world.body_pose(t)
        leans.append(math.degrees(math.acos(min(1.0, float((t_bowl[:3, :3].T @ pose[:3, 2])[2])))))
        heads.append(100 * (t_bowl[:3, :3].T @ (pose[:3, 3] - t_bowl[:3, 3]))[:2])
    return touched, leans, heads


def families() -> dict[str, list[tuple[tuple[float, ...], tuple[float, ...]]]]:
    mirrored = [((x, y, a, lean), (x, -y, -a, lean))
                for x in (-7, -5, -3, -1) for y in (3.5, 4.5, 5.5, 6.5) if x * x + y * y <= 8.5 ** 2
                for a in (0, 15, 30, 45) for lean in (48, 56)]
    crossed = [((fx, 0, 0, 60), (x, y, a, lean))
               for fx in (-8, -7, -6) for x in (-1.5, -0.5, 0.5, 1.5) for y in (0.5, 1.5, 2.5)
               for a in (-80, -90, -100) for lean in (30, 50)]
    outward = [((x, y, 90, lean), (x, -y, -90, lean))
               for x in (-2, 0, 2) for y in (3.5, 4.5, 5.5, 6.5) for lean in (25, 35, 45)]
    return {"mirrored": mirrored, "crossed": crossed, "outward": outward}


def axis_leans(path: Path) -> str:
    """One line: each server's long axis from the vertical (degrees) at the first and the last
    frame that shows all its markers."""
    from oacdsl.segmentation.readers import read_recording

    rec = read_recording(path)
    out = []
    for tool in TOOLS:
        pts = rec.group_positions(tool)
        seen = np.flatnonzero(np.isfinite(pts).all(axis=(1, 2)))
        ends = []
        for f in (int(seen[0]), int(seen[-1])):
            p = pts[f] - pts[f].mean(axis=0)
            axis = np.linalg.svd(p)[2][0]
            ends.append(math.degrees(math.acos(min(1.0, abs(float(axis[2]))))))
        out.append(f"{tool} {ends[0]:.0f}° → {ends[1]:.0f}°")
    return f"{path}: " + ", ".join(out) + " (long axis from the vertical, first → last frame)"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--library", type=Path, default=ROOT / "library" / "kit")
    parser.add_argument("--seconds", type=float, default=2.0, help="simulated time after letting go")
    parser.add_argument("--verbose", action="store_true", help="one line per pose")
    parser.add_argument("--leans", type=Path, nargs="+", metavar="RECORDING",
                        help="print the servers' leans at the first and last frame of recordings")
    args = parser.parse_args()
    if args.leans:
        for path in args.leans:
            print(axis_leans(path))
        return 0
    world, floor_m = _world(args.library)
    start = (world.data.qpos.copy(), world.data.qvel.copy())
    for name, poses in families().items():
        free = on_side = 0
        for pair in poses:
            world.data.qpos[:], world.data.qvel[:] = start
            touched, leans, heads = trial(world, floor_m, pair, args.seconds)
            free += not touched
            on_side += (not touched) and min(leans) > 45.0
            if args.verbose:
                where = "  ".join(f"({h[0]:.1f}, {h[1]:.1f}) {lean:.0f}°"
                                  for h, lean in zip(heads, leans, strict=True))
                print(f"{name} {pair}: {'touched' if touched else 'free'}  {where}")
        print(f"{name:9} {len(poses):4} poses: {free:3} free, {on_side:3} free and on their sides",
              flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
