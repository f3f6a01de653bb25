"""``oacc run``: execute an OAC on the simulated ARMAR-III (MuJoCo + placo).

Exit status 0 when every step — primitive or composed — succeeded and its predicted
effects were observed (adaptive: or a repair made good each step that failed), 1 when the
run failed (the reason is printed on one line, naming the failed step; also when the
composed OAC's effects hold but a step failed that nothing made good), 2 for usage or I/O
errors.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path
from typing import Any

from oacdsl.cli import seed_arg
from oacdsl.cli.backend import NONE_FOUND, prepare_backend
from oacdsl.cli.run_inputs import (
    check_binding,
    check_outputs,
    demonstrated,
    load_inputs,
    run_scene,
    writable_folder,
)
from oacdsl.cli.run_many import add_many_options, check_many_options
from oacdsl.cli.scene_options import add_scene_options, pairs, scene_overrides
from oacdsl.errors import RuntimeFailure, UsageError

__all__ = ["register", "run", "load_inputs", "add_adaptive_options"]


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "run",
        help="execute an OAC on the simulated robot",
        description="Execute a primitive or composed OAC on ARMAR-III in MuJoCo: bind its parameters,"
        " check its preconditions in the simulated world, run each step's skill and judge every step,"
        " primitive or composed, by its predicted effects: the observed touching relations after it."
        " Exit 1 names the first step that failed. The outcome of every run (also a failed one) goes"
        " into the run store (oacc stats).",
    )
    p.add_argument("name", metavar="NAME", help="the OAC to execute")
    p.add_argument(
        "--library",
        action="append",
        metavar="DIR",
        default=None,
        help="OAC library folder or file (repeatable; default: library/)",
    )
    p.add_argument(
        "--scene", metavar="FILE|NAME", help="a .oac file declaring the scene, or a scene name of the library"
    )
    p.add_argument(
        "--seed",
        type=seed_arg,
        metavar="N",
        help="move every object by up to 10 cm at random (default: where the scene puts them)",
    )
    p.add_argument(
        "--bind",
        action="append",
        default=[],
        metavar="VAR=INSTANCE",
        help="bind a parameter to an instance (repeatable; default: the OAC's defaults)",
    )
    p.add_argument(
        "--demonstration",
        metavar="RECORDING",
        help="the demonstration: its first frame lays out a scene with 'layout demonstrated'"
        " (marker groups named after the scene's instances), and the run is judged against it"
        " as `oacc verify` does (verified, faithful; exit 1 when not verified)",
    )
    p.add_argument(
        "--execution",
        metavar="OUT.c3d",
        default="execution.c3d",
        help="with --demonstration: where the robot's virtual-marker recording goes (its contacts"
        " beside it, OUT.contacts.json; default: execution.c3d)",
    )
    p.add_argument(
        "--db",
        metavar="PATH",
        help="run store (default: $OACDSL_DB, else ~/.local/share/oacdsl/runs.sqlite3)",
    )
    p.add_argument("--no-record", action="store_true", help="do not store the run's outcome in the run store")
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")
    p.add_argument(
        "--video", metavar="OUT.mp4", help="record a video (an .mp4 file, or a folder of PNG frames)"
    )
    p.add_argument("--frames", metavar="DIR", help="write one PNG of the scene after every step")
    p.add_argument("--view", action="store_true", help="show the run in MuJoCo's viewer (needs a display)")
    p.add_argument(
        "--no-self-collision",
        action="store_true",
        help="leave self-collision avoidance out of the IK (faster)",
    )
    add_scene_options(p)
    add_adaptive_options(p)
    p.add_argument(
        "--state",
        metavar="ATOMS",
        help='relations at the start, checked against the scene: a liquid in a container ("liquid_one <->'
        ' orange_bowl", as --fill) or a hand holding an object ("mixer <-> right_hand": the hand grasps'
        " it before the run)",
    )
    add_many_options(p)
    p.set_defaults(func=run)


def add_adaptive_options(p: argparse.ArgumentParser) -> None:
    """``--strict`` and ``--max-repairs`` (``oacc run`` and ``oacc reproduce``)."""
    p.add_argument(
        "--strict",
        action="store_true",
        help="run the demonstrated steps as they are and stop at the first one that fails (default:"
        " adaptive: skip a step whose effects hold, replan from the observed state when one fails)",
    )
    p.add_argument(
        "--max-repairs", type=int, default=3, metavar="N", help="adaptive: replan at most N times (default 3)"
    )


def run(args: argparse.Namespace) -> int:
    from oacdsl.cli.run_judge import RunJudge

    bindings = pairs(args.bind, "--bind", "NAME=INSTANCE")
    if args.max_repairs < 0:
        raise UsageError("--max-repairs: a whole number ≥ 0")
    check_many_options(args)
    overrides = scene_overrides(args)
    library, scene = load_inputs(args.library or ["library"], args.scene)
    chosen = run_scene(library, args.name, scene, bindings)
    if args.state:
        import dataclasses

        from oacdsl.planning.state import state_as_setup

        stated_fills, held = state_as_setup(library, chosen, args.state)
        overrides = dataclasses.replace(overrides, fill={**stated_fills, **overrides.fill}, held=held)
    if overrides.places or overrides.fill:
        from oacdsl.cli.scene_check import check_overrides

        check_overrides(library, chosen, overrides)
    check_binding(library, args.name, chosen, bindings)  # a wrong --bind: one line, before any work
    if args.seeds is not None:  # many runs on Dask: the success measure
        from oacdsl.cli.run_many import run_many_cmd

        paths = [*(args.library or ["library"]), *([args.scene] if scene != args.scene else [])]
        return run_many_cmd(args, paths, scene, bindings, overrides)
    db = None
    if not args.no_record:  # an unusable store fails now, before the simulation
        from oacdsl.stats import ensure_writable, resolve_db_path

        db = ensure_writable(resolve_db_path(args.db))
    check_outputs(args)
    if args.demonstration is not None:
        writable_folder(Path(args.execution).parent, "--execution")
    demo_positions, set_downs, headings = (
        demonstrated(args, library, scene, bindings, overrides.layout) or (None, None, None)
    )
    note = prepare_backend(bool(args.video or args.frames))  # before MuJoCo is imported
    if note:
        then = "running without rendering" if note != NONE_FOUND else "trying MuJoCo's default (GLFW)"
        print(f"oacc: warning: {note}; {then}", file=sys.stderr)
    try:
        from oacdsl.runtime.executor import prepare, run_prepared
        from oacdsl.runtime.render import Renderer, RenderUnavailable, VideoRecorder, Viewer, write_png
    except ImportError as error:
        raise UsageError(
            f"the robot runtime needs the 'robot' extra (pip install oacdsl[robot]): {error}"
        ) from None
    except Exception as error:  # MuJoCo refuses to start, e.g. an invalid MUJOCO_GL
        first = (str(error).strip().splitlines() or [type(error).__name__])[0]
        gl = os.environ.get("MUJOCO_GL", "unset")
        raise UsageError(f"MuJoCo could not start (MUJOCO_GL={gl}): {first}") from None
    run_ = prepare(
        library,
        args.name,
        bindings,
        scene,
        args.seed,
        self_collision=not args.no_self_collision,
        demonstrated=demo_positions,
        set_downs=set_downs,
        headings=headings,
        **overrides.kwargs(),
    )
    from oacdsl.runtime.layout import seed_note

    if (moved := seed_note(run_.world.layout)) is not None:
        print(f"oacc: warning: {moved}", file=sys.stderr)
    out = sys.stderr if args.json else sys.stdout
    judge = RunJudge(run_) if args.demonstration is not None else None
    closers: list[Any] = []
    frames: Any = None
    try:
        if args.video:
            try:
                video = VideoRecorder(run_.world.model, args.video)
                closers.append(video)
                run_.controller.add_observer(video)
            except RenderUnavailable as error:
                print(f"oacc: warning: {error}; running without video", file=sys.stderr)
        if args.frames:
            try:
                frames = Renderer(run_.world.model)
                closers.append(frames)
            except RenderUnavailable as error:
                print(f"oacc: warning: {error}; running without frames", file=sys.stderr)
        if args.view:
            viewer = Viewer(run_.world.model, run_.world.data)
            closers.append(viewer)
            run_.controller.add_observer(viewer)
        total = f"/{len(run_.steps)}" if args.strict or not run_.oac.composed else ""

        def on_step(index: int, step: Any, world: Any) -> None:
            args_text = ", ".join(step.binding.values())
            status = "ok" if step.success else "FAILED"
            print(
                f"step {index + 1}{total} {step.oac}({args_text}): {status} ({step.duration_s:.1f} s)",
                file=out,
            )
            if frames is not None:
                write_png(
                    Path(args.frames) / f"step_{index + 1:02d}_{step.oac}.png", frames.render(world.data)
                )

        def on_call(call: Any) -> None:
            status = "ok" if call.success else "FAILED"
            args_text = ", ".join(call.binding.values())
            print(f"composed {call.oac}({args_text}) of steps {call.first}-{call.last}: {status}", file=out)

        if args.strict or not run_.oac.composed:  # a primitive OAC is one step: nothing to adapt
            result = run_prepared(run_, on_step=on_step, on_call=on_call)
        else:
            from oacdsl.runtime.adaptive import describe, run_adaptive

            result = run_adaptive(run_, on_step=on_step, on_call=on_call, max_repairs=args.max_repairs)
            for line in describe(result.adaptations):
                print(f"adapted: {line}", file=out)
    except OSError as error:  # a picture could not be written after all (disk full, folder removed)
        from oacdsl.errors import InputError

        where = getattr(error, "filename", None) or args.frames or args.video
        raise InputError(f"cannot write: {error.strerror or error}", location=str(where)) from None
    finally:
        for c in closers:
            c.close()
    m = result.metrics
    if args.json:
        print(json.dumps(result.to_json(), indent=2))
    else:
        verdict = result.outcome
        poured = f" {m['balls_in_bowl']}/{m['balls_total']} balls in a bowl," if m.get("balls_total") else ""
        timing = f"{m['sim_time_s']:.1f} s simulated in {m['wall_time_s']:.1f} s"
        print(f"{result.oac}: {verdict} —{poured} {timing}")
    if db is not None:
        from oacdsl.stats import RunStore

        with RunStore(db) as store:
            store.record_run_json(result.to_json(), seed=args.seed, command="run")
    if not result.success:
        raise RuntimeFailure(result.error or f"{result.oac} failed")
    if judge is not None:  # judged as oacc reproduce judges: hands the run exchanged may be exchanged
        exchanged = any(a.get("kind") == "exchanged" for a in getattr(result, "adaptations", ()))
        return judge.verdict(args, library, run_.scene, sys.stderr if args.json else sys.stdout, exchanged)
    return 0
