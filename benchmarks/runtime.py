"""Runtime performance: IK solves per second and the dough sequence's real-time factor.

    python benchmarks/runtime.py [--repeats N] [--quick]

1. Whole-body IK: one control tick's problem (both hands' frame tasks, posture, joint
   and velocity limits, self-collision avoidance) solved repeatedly while the hand
   target moves. Baselines in the same process: the same problem without self-collision,
   and a pure-numpy damped-least-squares step on the same Jacobian. Target: ≥ 5,000 solves/s.
2. The paper's dough sequence (8 steps) executed headless without rendering: simulated
   time / wall time. Baseline: the bare physics of the same scene stepped for the same
   simulated time (no control, no IK). Target: ≥ 10× faster than real time.
Medians over the repeats are printed.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from oacdsl.runtime.ik import WholeBodyIK  # noqa: E402
from oacdsl.runtime.transforms import make_T  # noqa: E402


def _moving_target(ik: WholeBodyIK, k: int) -> np.ndarray:
    t = ik.frame("grasp_r")
    return make_T(t[:3, :3], t[:3, 3] + 0.002 * np.array([np.sin(k / 10), np.cos(k / 10), 0.0]))


def ik_rate(self_collision: bool, n: int) -> tuple[float, float]:
    """(solves per wall second, solves per CPU second) of one control tick's IK problem."""
    ik = WholeBodyIK(self_collision=self_collision)
    ik.set_hand_target("r", ik.frame("grasp_r"))
    start, cpu = time.perf_counter(), time.process_time()
    for k in range(n):
        ik.set_hand_target("r", _moving_target(ik, k))
        ik.step()
    return n / (time.perf_counter() - start), n / (time.process_time() - cpu)


def dls_rate(n: int, damping: float = 1e-3) -> float:
    """A damped-least-squares step in numpy on placo's Jacobian of the right hand (13 DOF)."""
    ik = WholeBodyIK(self_collision=False)
    robot = ik.robot
    names = [
        "base_x",
        "base_y",
        "base_yaw",
        "hip_pitch",
        "hip_roll",
        "hip_yaw",
        "shoulder_1_r",
        "shoulder_2_r",
        "upperarm_r",
        "elbow_r",
        "underarm_r",
        "wrist_1_r",
        "wrist_2_r",
    ]
    cols = [robot.get_joint_v_offset(j) for j in names]
    start = time.perf_counter()
    for k in range(n):
        goal = _moving_target(ik, k)
        t = robot.get_T_world_frame("grasp_r")
        e = goal[:3, 3] - t[:3, 3]
        jac = robot.frame_jacobian("grasp_r", "local_world_aligned")[:3, cols]
        dq = jac.T @ np.linalg.solve(jac @ jac.T + damping * np.eye(3), e)
        for j, d in zip(names, dq, strict=True):
            robot.set_joint(j, robot.get_joint(j) + d)
        robot.update_kinematics()
    return n / (time.perf_counter() - start)


def dough_rtf() -> tuple[float, float, float, bool]:
    """(simulated s, wall s, CPU s of this process, success) of one headless dough run."""
    from runtime_lib import task_library

    from oacdsl.runtime import execute

    lib = task_library()
    cpu = time.process_time()
    result = execute(lib, "dough")
    cpu = time.process_time() - cpu
    return result.metrics["sim_time_s"], result.metrics["wall_time_s"], cpu, result.success


def physics_rtf(sim_s: float) -> float:
    import mujoco
    from runtime_lib import task_library

    from oacdsl.runtime.build import build_model
    from oacdsl.runtime.layout import plan_layout
    from oacdsl.runtime.simworld import SimWorld

    lib = task_library()
    world = SimWorld(build_model(plan_layout(lib, lib.scenes["kitchen"])))
    n = int(sim_s / world.model.opt.timestep)
    start = time.perf_counter()
    mujoco.mj_step(world.model, world.data, nstep=n)
    return sim_s / (time.perf_counter() - start)


def main() -> int:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--solves", type=int, default=3000)
    parser.add_argument("--quick", action="store_true", help="IK only, no dough run")
    args = parser.parse_args()
    full_runs = [ik_rate(True, args.solves) for _ in range(args.repeats)]
    bare_runs = [ik_rate(False, args.solves) for _ in range(args.repeats)]
    full, full_cpu = (statistics.median(r[i] for r in full_runs) for i in (0, 1))
    bare, bare_cpu = (statistics.median(r[i] for r in bare_runs) for i in (0, 1))
    dls = statistics.median(dls_rate(args.solves) for _ in range(args.repeats))
    print(
        f"IK, whole body with self-collision : {full:7.0f} solves/s wall, {full_cpu:7.0f} per CPU s"
        "  (target >= 5000)"
    )
    print(
        f"IK, whole body, no self-collision  : {bare:7.0f} solves/s wall, {bare_cpu:7.0f} per CPU s"
        f"  (ratio full/bare {full / bare:.2f})"
    )
    print(f"numpy damped least squares, 13 DOF : {dls:7.0f} steps/s wall  (ratio full/dls {full / dls:.2f})")
    if args.quick:
        return 0
    runs = [dough_rtf() for _ in range(args.repeats)]
    sim = statistics.median(r[0] for r in runs)
    wall = statistics.median(r[1] for r in runs)
    cpu = statistics.median(r[2] for r in runs)
    ok = all(r[3] for r in runs)
    physics = physics_rtf(sim)
    print(
        f"dough sequence: {sim:.1f} s simulated in {wall:.2f} s wall (median of {len(runs)}),"
        f" real-time factor {sim / wall:.1f}x  (target >= 10x; all runs succeeded: {ok})"
    )
    print(
        f"  same runs by process CPU time    : {cpu:.2f} s, real-time factor {sim / cpu:.1f}x"
        f"  (load average now {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)"
    )
    print(
        f"bare physics of the same scene     : real-time factor {physics:.1f}x"
        f"  (ratio run/physics {sim / wall / physics:.2f})"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
