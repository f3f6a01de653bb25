"""Either hand for every skill (issue 19): the bundled dough demonstration mirrored, left-handed
(``oacc take data/dough.c3d --standard mirrored``), reproduced in the dough's own scene, whose
cups stand where the right-handed demonstration had them; a cup poured across the body; and KIT
Pour left-handed, poured into the cup the other hand holds."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

#: ARMAR-III in the simulator.
pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[1]


def test_the_mirrored_dough_is_reproduced_verified_and_faithful(tmp_path: Path) -> None:
    pytest.importorskip("mujoco")
    pytest.importorskip("unified_planning")
    from oacdsl.pipeline import load_inputs, reproduce
    from oacdsl.segmentation import AasParams
    from oacdsl.segmentation.readers import read_recording, write_recording
    from oacdsl.segmentation.takes import STANDARD_TAKES

    take, hands = STANDARD_TAKES["mirrored"](read_recording(ROOT / "data" / "dough.c3d"))
    assert hands == {"left_hand": "right_hand", "right_hand": "left_hand"}
    path = Path(write_recording(take, tmp_path / "dough_mirrored.c3d"))
    library = tmp_path / "library"
    shutil.copytree(ROOT / "library", library, ignore=shutil.ignore_patterns("learned", "drafts"))
    inputs = load_inputs(path, library, None, AasParams())
    outcome = reproduce(inputs, name="dough_mirrored", out=tmp_path / "out", db=None, render=False,
                        quiet=True)
    result = outcome.result
    # composed left-handed: the right hand takes the red cup (on the robot's left) first
    assert result["compose"]["steps"][0]["binding"]["h"] == "right_hand"
    run = result["run"]
    # the scene is laid out for the right hand: the whole task is done with the hands exchanged,
    # every ball poured, and judged with the hands free to be exchanged consistently
    [exchanged] = [a for a in run["adaptations"] if a["kind"] == "exchanged"]
    assert run["steps"][0]["binding"] == {"h": "left_hand", "o": "red_cup"}, exchanged
    assert run["metrics"]["balls_in_bowl"] == run["metrics"]["balls_total"] == 20
    assert outcome.exit_code == 0, result["verdict"]
    assert result["verdict"]["verified"] and result["verdict"]["faithful"], result["verdict"]


def test_a_cup_poured_across_the_body_keeps_the_arm_off_the_bowl() -> None:
    """The left hand pours the green cup, which stands on the robot's right, into the bowl
    between them: the first side the whole-body IK reaches there laid the forearm on the bowl
    and the elbow on the table at full tilt, the arm lagged its command by 15 cm and no ball
    reached the bowl. The side taken keeps the arm's links clear (runtime/armroom.py)."""
    pytest.importorskip("mujoco")
    from runtime_lib import task_library

    from oacdsl.runtime.executor import prepare, run_prepared

    run = prepare(task_library(), "pour_task", {"h": "left_hand"}, scene="pouring")
    assert run.world.layout.placement("green_cup").y < 0  # on the right: across the left arm's body
    result = run_prepared(run)
    assert result.success, result.error
    assert result.metrics["balls_in_bowl"] == result.metrics["balls_total"]
    assert run.world.warnings() == {}


@pytest.mark.parametrize("variation", ["mirrored", "mirror_x1.5_rot135"])
def test_the_mirrored_kit_pour_pours_every_ball_past_the_hand_holding_the_cup(
        tmp_path: Path, variation: str) -> None:
    """KIT Pour done left-handed (``oacc take --standard mirrored``; and mirrored, 1.5 times as slow
    and turned 135°): the left hand pours the carton into the cup the right hand holds. The carton
    and the pouring hand keep their clearance from the holding hand's boxes as they are
    (``runtime/boxlift.py``), and the round carton is turned in the pouring hand's grasp so that
    the hand is beside its lip, not over the cup: held as it was taken, the lip rolled the balls
    out 9-11 cm above the rim, and 1 of 8 bounced out of the cup in the second take (seed 0; the
    first kept its 8 by a hair)."""
    pytest.importorskip("mujoco")
    import takesweep
    from _mocap import mocap_file

    from oacdsl.pipeline import load_inputs, reproduce
    from oacdsl.segmentation import AasParams
    from oacdsl.segmentation.readers import read_recording, write_recording
    from oacdsl.segmentation.takes import STANDARD_TAKES

    clip = mocap_file("kit_bimanual/Pour_files_motions_2967_Pour1_cs_ms_0_20l_04.mmm.xml")
    make = STANDARD_TAKES.get(variation) or takesweep.SWEEP[variation]
    take, hands = make(read_recording(clip))
    assert hands["left_hand"] == "right_hand"
    path = Path(write_recording(take, tmp_path / "pour_mirrored.mmm.xml"))
    library = tmp_path / "kit"
    shutil.copytree(ROOT / "library" / "kit", library, ignore=shutil.ignore_patterns("learned", "drafts"))
    inputs = load_inputs(path, library, None, AasParams())
    outcome = reproduce(inputs, name="pour_mirrored", out=tmp_path / "out", db=None, render=False,
                        quiet=True)
    result = outcome.result
    pour = [s for s in result["run"]["steps"] if s["oac"] == "pour"]
    assert pour and pour[0]["binding"]["h"] == "left_hand", result["run"]["steps"]
    assert result["run"]["metrics"]["balls_in_bowl"] == result["run"]["metrics"]["balls_total"] == 8
    assert outcome.exit_code == 0, result["verdict"]
    assert result["verdict"]["verified"] and result["verdict"]["faithful"], result["verdict"]
