"""Executing OACs: the paper's dough sequence, pose invariance, clean failures, `oacc run`."""

import json
import os
import sqlite3
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")

from runtime_lib import STANDARD, task_library  # noqa: E402

from oacdsl.errors import RuntimeFailure  # noqa: E402
from oacdsl.runtime import MarkerRecorder, execute  # noqa: E402
from oacdsl.runtime.binding import bind, flatten  # noqa: E402
from oacdsl.runtime.layout import BALLS_PER_LIQUID  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
TESTS = Path(__file__).resolve().parent
PAPER_EFFECTS = [
    ["mixer", "right_hand"],
    ["liquid_one", "orange_bowl"],
    ["liquid_two", "orange_bowl"],
    ["mixer", "orange_bowl"],
]


@pytest.mark.slow
def test_the_papers_dough_sequence_end_to_end():
    recorder = MarkerRecorder()
    result = execute(task_library(), "dough", recorder=recorder)
    assert result.success, result.error
    assert [s.oac for s in result.steps] == [
        "grasp",
        "pour",
        "place",
        "grasp",
        "pour",
        "place",
        "grasp",
        "mix",
    ]
    final = result.steps[-1].observed
    for pair in PAPER_EFFECTS:
        assert sorted(pair) in [sorted(p) for p in final], pair
    assert result.metrics["balls_total"] == 2 * BALLS_PER_LIQUID
    assert result.metrics["balls_in_bowl"] >= 0.9 * result.metrics["balls_total"]
    # the recorder sampled the run at 100 Hz of simulated time, one marker group per instance
    rec = recorder.to_recording()
    assert abs(rec.n_frames - result.metrics["sim_time_s"] * 100) < 5
    assert set(rec.instances) == {
        "left_hand",
        "right_hand",
        "red_cup",
        "green_cup",
        "orange_bowl",
        "mixer",
        "liquid_one",
        "liquid_two",
    }
    cup = rec.group_positions("red_cup")
    assert np.nanmax(cup[:, :, 2]) - np.nanmin(cup[:, :, 2]) > 0.1  # the cup was lifted


@pytest.mark.slow
def test_pose_invariance_same_oac_succeeds_on_four_of_five_seeds():
    results = [execute(task_library(), "left_pour", scene="kitchen", seed=seed) for seed in range(1, 6)]
    moved = [r.success for r in results]
    assert sum(moved) >= 4, [r.error for r in results]


def test_a_violated_precondition_fails_cleanly_before_anything_moves():
    result = execute(task_library(), "place", {"h": "left_hand", "o": "red_cup"}, "kitchen")
    assert not result.success
    assert result.steps[0].error.startswith("precondition of place not met: left_hand <-> red_cup")
    assert result.metrics["sim_time_s"] == 0.0


def test_an_unreachable_object_fails_cleanly_with_a_reason():
    result = execute(
        task_library(),
        "grasp",
        {"h": "left_hand", "o": "red_cup"},
        "kitchen",
        places={"red_cup": (1.35, 0.3)},
    )
    assert not result.success
    assert "out of reach of left_hand" in result.steps[0].error


def test_binding_errors_name_what_is_wrong():
    lib = task_library()
    grasp, kitchen = lib.oacs["grasp"], lib.scenes["kitchen"]
    with pytest.raises(RuntimeFailure, match="needs a binding.*left_hand, right_hand"):
        bind(lib, grasp, kitchen, {"o": "red_cup"})
    with pytest.raises(RuntimeFailure, match="not a Graspable"):
        bind(lib, grasp, kitchen, {"h": "left_hand", "o": "orange_bowl"})
    with pytest.raises(RuntimeFailure, match="did you mean 'red_cup'"):
        bind(lib, grasp, kitchen, {"h": "left_hand", "o": "red_cpu"})
    with pytest.raises(RuntimeFailure, match="no parameter 'x'"):
        bind(lib, grasp, kitchen, {"x": "left_hand"})
    steps = flatten(lib, lib.oacs["dough"], bind(lib, lib.oacs["dough"], kitchen))
    assert [s.args for s in steps][:2] == [
        ("left_hand", "red_cup"),
        ("left_hand", "red_cup", "liquid_one", "orange_bowl"),
    ]


def oacc_run(tmp_path, *args, env=None):
    """``oacc run`` in a subprocess on the standard library plus the test tasks."""
    cmd = [
        sys.executable,
        "-m",
        "oacdsl",
        "run",
        *args,
        *(arg for p in (*STANDARD, TESTS / "data" / "runtime_tasks.oac") for arg in ("--library", str(p))),
    ]
    return subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=300, cwd=ROOT)


def test_oacc_run_json_document_and_clean_failure(tmp_path):
    db = tmp_path / "runs.sqlite3"
    out = oacc_run(
        tmp_path, "place", "--scene", "kitchen", "--bind", "h=left_hand", "--bind", "o=red_cup", "--json",
        env={**os.environ, "OACDSL_DB": str(db)},
    )
    assert out.returncode == 1 and "Traceback" not in out.stderr
    last = out.stderr.strip().splitlines()[-1]
    assert last.startswith("oacc: error: step 1 place(left_hand, red_cup): precondition of place not met")
    doc = json.loads(out.stdout)
    assert set(doc) == {"oac", "success", "failed_step", "steps", "composed", "metrics"}
    assert doc["success"] is False and doc["failed_step"] == "step 1 place(left_hand, red_cup)"
    assert set(doc["metrics"]) == {"balls_total", "balls_in_bowl", "sim_time_s", "wall_time_s", "regrasps",
                                   "reseats"}
    step = doc["steps"][0]
    assert set(step) == {"oac", "binding", "success", "duration_s", "predicted", "observed", "error"}
    assert step["binding"] == {"h": "left_hand", "o": "red_cup"} and step["predicted"] == [
        ["left_hand", "nothing"]
    ]
    # the failed run is in the run store ($OACDSL_DB), as oacc stats shows
    stats = subprocess.run([sys.executable, "-m", "oacdsl", "stats", "--json"], capture_output=True,
                           text=True, env={**os.environ, "OACDSL_DB": str(db)}, cwd=ROOT)
    assert stats.returncode == 0, stats.stderr
    summary = json.loads(stats.stdout)
    assert summary["runs"] == 1 and [(o["oac"], o["runs"], o["successes"]) for o in summary["oacs"]] == [
        ("place", 1, 0)
    ]
    assert "precondition of place not met" in summary["oacs"][0]["last_failure"]
    again = oacc_run(tmp_path, "place", "--scene", "kitchen", "--bind", "h=left_hand", "--bind", "o=red_cup",
                     "--db", str(db), "--no-record")
    assert again.returncode == 1
    with sqlite3.connect(db) as conn:
        assert conn.execute("SELECT oac, success, command FROM runs").fetchall() == [("place", 0, "run")]


def test_oacc_run_succeeds_in_a_scene_file_and_renders_step_frames(tmp_path):
    scene = tmp_path / "bench.oac"
    scene.write_text(
        "scene bench {\n    left_hand, right_hand : Hand\n    blue_cup : Cup\n"
        "    table : Table environment\n}\n"
    )
    out = oacc_run(
        tmp_path,
        "grasp",
        "--scene",
        str(scene),
        "--seed",
        "2",
        "--bind",
        "h=right_hand",
        "--bind",
        "o=blue_cup",
        "--frames",
        str(tmp_path / "frames"),
    )
    assert out.returncode == 0, out.stderr
    assert "step 1/1 grasp(right_hand, blue_cup): ok" in out.stdout and "success" in out.stdout
    if "no offscreen rendering" not in out.stderr:  # a machine without EGL/OSMesa warns instead
        assert (tmp_path / "frames" / "step_01_grasp.png").stat().st_size > 10_000


def test_oacc_run_without_a_rendering_backend_still_completes(tmp_path):
    env = {**__import__("os").environ, "MUJOCO_GL": "disable"}
    out = oacc_run(
        tmp_path,
        "place",
        "--scene",
        "kitchen",
        "--bind",
        "h=left_hand",
        "--bind",
        "o=red_cup",
        "--video",
        str(tmp_path / "v.mp4"),
        env=env,
    )
    assert "no offscreen rendering" in out.stderr and "Traceback" not in out.stderr
    assert out.returncode == 1 and "precondition of place not met" in out.stderr  # the run itself went on


def test_oacc_run_usage_errors(tmp_path):
    out = oacc_run(tmp_path, "grasp", "--bind", "h")
    assert out.returncode == 2 and "expected NAME=INSTANCE" in out.stderr
    a_file = tmp_path / "file"
    a_file.write_text("x")
    (tmp_path / "clip.mp4").mkdir()
    for args, message in [
        (["--seed", "-1"], "a seed is a whole number from 0 to 2^63-1"),
        (["--seed", str(2**63)], "a seed is a whole number"),
        (["--frames", a_file], "exists and is not a folder"),
        (["--frames", a_file / "sub"], "a parent is a file"),
        (["--video", a_file / "v.mp4"], "exists and is not a folder"),
        (["--video", tmp_path / "clip.mp4"], "is a folder; give a file name ending in .mp4"),
        (["--video", a_file], "exists and is not a folder"),
        (["--db", a_file / "runs.sqlite3"], "cannot record runs here"),
        (["--db", tmp_path], "is a directory"),
    ]:
        bound = ["--scene", "kitchen", "--bind", "h=right_hand", "--bind", "o=green_cup"]
        out = oacc_run(tmp_path, "grasp", *bound, *map(str, args))
        assert out.returncode == 2 and "Traceback" not in out.stderr, (args, out.stderr)
        lines = out.stderr.strip().splitlines()
        assert message in lines[-1], (args, out.stderr)
        assert len(lines) == 1 or lines[0].startswith("usage:"), out.stderr
        assert "step 1" not in out.stdout  # refused before the simulation
    assert sorted(p.name for p in tmp_path.iterdir()) == ["clip.mp4", "file"]
    out = oacc_run(tmp_path, "grsap", "--scene", "kitchen")
    assert out.returncode == 2 and "did you mean 'grasp'" in out.stderr


@pytest.mark.parametrize(("bind", "message"), [
    ("h=nobody", "--bind h=nobody: no instance 'nobody' in scene kitchen (valid: green_cup, left_hand,"),
    ("h=red_cpu", "--bind h=red_cpu: no instance 'red_cpu' in scene kitchen (did you mean 'red_cup'?)"),
    ("x=left_hand", "--bind x=left_hand: oac pour has no parameter 'x' (valid: b, c, h, l)"),
    ("h=red_cup", "--bind h=red_cup: red_cup is not a Hand (it is Container, Cup, Graspable)"),
])
def test_a_wrong_binding_is_one_line_before_anything_heavy(tmp_path, capsys, monkeypatch, bind, message):
    """Checked right after the library: before the demonstration is read (this one is not a
    recording), the run store is opened or MuJoCo is started."""
    import oacdsl.cli.run_cmd as run_cmd
    from oacdsl.cli import main

    def started(*_: object) -> None:
        raise AssertionError("the simulation was being prepared")

    monkeypatch.setattr(run_cmd, "prepare_backend", started)
    demo = tmp_path / "demo.c3d"
    demo.write_text("not a recording")
    code = main(["run", "pour", "--scene", "kitchen", "--bind", bind, "--demonstration", str(demo),
                 "--execution", str(tmp_path / "out" / "run.c3d"), "--db", str(tmp_path / "runs.sqlite3")])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith(f"oacc: error: {message}") and len(err.strip().splitlines()) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["demo.c3d"]


def test_a_composed_step_whose_effect_is_not_observed_fails_the_run_and_is_named(tmp_path):
    # grasp_into_bowl (composed of one grasp) predicts `green_cup <-> orange_bowl`, which no
    # grasp makes true: the run stops after it (the place never runs), exit 1, step named
    named = "composed step grasp_into_bowl(right_hand, green_cup, orange_bowl) (steps 1-1)"
    out = oacc_run(tmp_path, "grasp_into_bowl_and_place", "--scene", "pouring", "--strict")
    assert out.returncode == 1 and "Traceback" not in out.stderr
    last = out.stderr.strip().splitlines()[-1]
    assert last.startswith(f"oacc: error: {named}: grasp_into_bowl: predicted effect not observed")
    assert f"failed at {named}" in out.stdout  # the one-line summary
    assert "composed grasp_into_bowl(right_hand, green_cup, orange_bowl) of steps 1-1: FAILED" in out.stdout
    # the JSON document (the same run in-process)
    doc = execute(task_library(), "grasp_into_bowl_and_place", scene="pouring").to_json()
    assert doc["success"] is False and doc["failed_step"] == named
    assert [(s["oac"], s["success"]) for s in doc["steps"]] == [("grasp", True)]
    (inner,) = doc["composed"]
    assert inner["oac"] == "grasp_into_bowl" and inner["steps"] == [1, 1] and inner["success"] is False
    assert inner["predicted"] == [["green_cup", "orange_bowl"], ["green_cup", "right_hand"]]


def test_oacc_run_pinches_the_flat_tray_of_the_wiping_scene():
    # the command of issue 10, on the standard library alone
    cmd = [sys.executable, "-m", "oacdsl", "run", "grasp", "--library", "library", "--scene", "wiping"]
    out = subprocess.run(
        [*cmd, "--bind", "h=right_hand", "--bind", "o=tray", "--json"],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=ROOT,
    )
    assert out.returncode == 0, out.stderr
    (step,) = json.loads(out.stdout)["steps"]
    assert step["success"] and ["right_hand", "tray"] in step["observed"]
