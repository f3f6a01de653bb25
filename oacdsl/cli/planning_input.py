"""The inputs ``oacc pddl`` and ``oacc plan`` share: library, scene, start state, goal."""

from __future__ import annotations

import argparse
from dataclasses import dataclass
from typing import Any

from oacdsl.errors import UsageError, did_you_mean
from oacdsl.world import NOTHING

__all__ = ["PlanningInput", "add_state_options", "read_input"]


@dataclass
class PlanningInput:
    library: Any  # oacdsl.library.Library
    scene: Any  # oacdsl.model.Scene
    state: Any  # oacdsl.world.WorldState
    goal: tuple[Any, ...]  # oacdsl.model.Atom


def add_state_options(p: argparse.ArgumentParser) -> None:
    """``--scene``, ``--goal``, ``--state`` and ``--from``."""
    p.add_argument(
        "--scene", metavar="FILE|NAME", help="a scene name of the library or a .oac file declaring one"
    )
    p.add_argument(
        "--goal",
        metavar="ATOMS",
        help='the goal, atoms as in .oac files separated by commas: "liquid_one <-> orange_bowl, not mixer'
        ' <-> nothing"',
    )
    p.add_argument(
        "--state",
        metavar="ATOMS",
        help='relations that hold at the start beyond the scene\'s ("mixer <-> right_hand"; a "not" atom'
        " or 'x <-> nothing' takes relations away)",
    )
    p.add_argument(
        "--from",
        dest="from_result",
        metavar="RESULT.json",
        help="start where a run ended: the last observed relations of 'oacc run --json' or a result.json",
    )


def _scene(library: Any, name: str | None, named: set[str]) -> Any:
    """The scene called ``name``; else the library's one scene, or the one that holds every
    instance the goal and --state name."""
    if name is None:
        if len(library.scenes) == 1:
            return next(iter(library.scenes.values()))
        fitting = [s for s in library.scenes.values() if named and named <= {i.name for i in s.instances}]
        if len(fitting) == 1:
            return fitting[0]
        names = ", ".join(sorted(library.scenes)) or "none"
        raise UsageError(f"choose a scene with --scene (the library has: {names})")
    if name not in library.scenes:
        raise UsageError(f"--scene: no scene {name!r} in the library{did_you_mean(name, library.scenes)}")
    return library.scenes[name]


def read_input(args: argparse.Namespace, paths: list[str], *, need_goal: bool) -> PlanningInput:
    """Library, scene, start state and goal of the command line (UsageError when wrong)."""
    from oacdsl.cli.run_inputs import load_inputs
    from oacdsl.planning.state import check_atoms, parse_atoms, scene_state, state_from_result, stated

    if need_goal and not args.goal:
        raise UsageError('--goal is required (e.g. --goal "liquid_one <-> orange_bowl")')
    goal = parse_atoms(args.goal, "--goal") if args.goal else ()
    extra = parse_atoms(args.state, "--state") if args.state else ()
    library, scene_name = load_inputs(paths, args.scene)
    named = {n for a in (*goal, *extra) for n in (a.left, a.right)} - {NOTHING}
    scene = _scene(library, scene_name, named)
    state = scene_state(scene)
    if args.from_result:
        state = state_from_result(args.from_result, state.instances)
    if extra:
        state = stated(state, extra, "--state")
    check_atoms(goal, state.instances, "--goal")
    return PlanningInput(library, scene, state, goal)

