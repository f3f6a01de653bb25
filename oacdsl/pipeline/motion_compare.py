"""Demonstrated against executed motion, per sub-action: the report's motion section.

The robot's recording (its virtual markers, :mod:`oacdsl.pipeline.markers`) goes through
the same rigid fit (:func:`~oacdsl.segmentation.poses.fit_poses`) and the same
:func:`~oacdsl.segmentation.motion.sub_action_motion` as the demonstration. Each
demonstrated sub-action is paired with the robot's sub-action that the closed loop
aligned with it (``verification.alignment``: change *k* ends sub-action *k* − 1); the
robot's path is then shown in the frame the demonstration's was in (the same moved object
and target, when the robot's recording has both; a poured liquid is one marker in the
demonstration but many balls on the robot, so the robot's own choice of target could
differ). The document (``result.json``'s ``motion``) lists per sub-action both feature
sets and the skill parameters the step was given; the picture has one row per sub-action:
the demonstration's path on the left, the robot's on the right.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from oacdsl.segmentation.motion import SubActionMotion, sub_action_motion
from oacdsl.segmentation.motionfeatures import motion_features
from oacdsl.segmentation.poses import ObjectPoses, fit_poses, relative
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import SubAction

__all__ = ["PLOT_POINTS", "motion_doc", "save_comparison_plot"]


def _as_demonstrated(robot: SubActionMotion, demo: SubActionMotion, posed: Mapping[str, ObjectPoses]
                     ) -> SubActionMotion:
    """``robot`` re-expressed with the demonstration's moved object and target, when it can be."""
    moved, target = demo.moved, demo.target
    if moved is None or moved not in posed or (robot.moved, robot.target) == (moved, target):
        return robot
    if target is not None and target not in posed:
        return robot
    a, b = robot.start_frame, robot.end_frame
    T = posed[moved].T_world_object[a : b + 1]
    if target is not None:
        T = relative(posed[target].T_world_object[a : b + 1], T)
    return SubActionMotion(robot.index, a, b, robot.hand, moved, target, robot.relation, robot.times_s, T,
                           motion_features(robot.times_s, T), robot.residual_m)


def _pairs(verification: Mapping[str, Any]) -> dict[int, int]:
    """Demonstration sub-action → the robot's sub-action aligned with it (both from 0)."""
    demo, robot = verification.get("demonstration", []), verification.get("robot", [])
    out: dict[int, int] = {}
    for a in verification.get("alignment", []):
        d, r = a.get("demonstration"), a.get("robot")
        if d is not None and r is not None and d < len(demo) and r < len(robot):
            out.setdefault(int(demo[d]["index"]) - 1, int(robot[r]["index"]) - 1)
    return out


def motion_doc(demo_recording: Recording, demo_subs: Sequence[SubAction], robot_recording: Recording,
               robot_subs: Sequence[SubAction], verification: Mapping[str, Any],
               steps: Sequence[Mapping[str, Any]], plot: Path | None) -> dict[str, Any]:
    """The ``motion`` part of result.json; with ``plot``, the comparison picture is written there.

    ``demo_subs``/``robot_subs``: the sub-actions as matched (transient keyframes dropped);
    ``steps``: ``compose.steps`` (the OAC and the parameters of each sub-action's step).
    """
    demo_posed = fit_poses(demo_recording)
    robot_posed = fit_poses(robot_recording)
    pairs = _pairs(verification)
    rows: list[dict[str, Any]] = []
    shown: list[tuple[SubActionMotion, SubActionMotion | None]] = []
    for k, sub in enumerate(demo_subs):
        demo = sub_action_motion(demo_recording, sub, demo_posed)
        r = pairs.get(k)
        robot = None
        if r is not None and r < len(robot_subs):
            robot = _as_demonstrated(sub_action_motion(robot_recording, robot_subs[r], robot_posed), demo,
                                     robot_posed)
        step = steps[k] if k < len(steps) else {}
        rows.append({
            "index": k,
            "oac": step.get("oac"),
            "params": step.get("params"),
            "moved": demo.moved,
            "target": demo.target,
            "demonstrated": demo.features.to_json() if demo.features is not None else None,
            "robot_index": r,
            "robot_moved": robot.moved if robot is not None else None,
            "robot_target": robot.target if robot is not None else None,
            "executed": (robot.features.to_json() if robot is not None and robot.features is not None
                         else None),
        })
        if demo.moved is not None:
            shown.append((demo, robot))
    doc: dict[str, Any] = {"sub_actions": rows}
    if plot is not None and shown:
        save_comparison_plot(shown, plot)
        doc["plot"] = f"{plot.parent.name}/{plot.name}"
    return doc


#: Most points a panel draws (the robot's recording has 100 frames a second: a 16-panel
#: picture with every frame drew thousands of points per panel).
PLOT_POINTS = 150


def _thin(m: SubActionMotion) -> SubActionMotion:
    """Every k-th frame of ``m``'s path, at most :data:`PLOT_POINTS` (for drawing only)."""
    step = max(1, -(-len(m.times_s) // PLOT_POINTS))
    if step == 1:
        return m
    return dataclasses.replace(m, times_s=m.times_s[::step], T_target_object=m.T_target_object[::step])


def save_comparison_plot(pairs: Sequence[tuple[SubActionMotion, SubActionMotion | None]], out: Path) -> Path:
    """One row per sub-action: the demonstration's path (left), the robot's (right)."""
    from matplotlib.figure import Figure

    from oacdsl.segmentation.motionplot import draw_motion
    from oacdsl.segmentation.plots import save_figure

    # a fixed layout: constrained layout re-measures the labels of every panel while it saves
    fig = Figure(figsize=(7.0, 2.9 * len(pairs) + 0.3))
    fig.subplots_adjust(left=0.1, right=0.98, top=1 - 0.35 / (2.9 * len(pairs) + 0.3),
                        bottom=0.45 / (2.9 * len(pairs) + 0.3), hspace=0.5, wspace=0.32)
    for k, (demo, robot) in enumerate(pairs):
        draw_motion(fig.add_subplot(len(pairs), 2, 2 * k + 1), _thin(demo),
                    f"#{demo.index} demonstration: {demo.moved} → {demo.frame_name}")
        ax = fig.add_subplot(len(pairs), 2, 2 * k + 2)
        if robot is None or robot.moved is None:
            ax.text(0.5, 0.5, "no aligned robot sub-action", ha="center", va="center", fontsize=8)
            ax.set_axis_off()
        else:
            draw_motion(ax, _thin(robot), f"#{robot.index} robot: {robot.moved} → {robot.frame_name}")
    return save_figure(fig, out)
