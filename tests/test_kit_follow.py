"""KIT development clips with a named skill replaced by the generic ``follow``, reproduced and
verified end to end (`oacc reproduce CLIP.mmm.xml --library tests/data/kit_follow`): the
sub-action runs from its demonstrated path alone (docs/runtime.md, "follow"). Slow; each case
skips when ../shared/mocap is absent.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from _mocap import mocap_file

ROOT = Path(__file__).resolve().parents[1]
FOLLOW_KIT = ROOT / "tests" / "data" / "kit_follow"

#: clip → (recording under shared/mocap, the composed steps, the step that follows a path)
CLIPS = {
    "Cut": ("kit_bimanual/Cut_files_motions_3021_Cut1_c_0_05cm_03.mmm.xml",
            ["grasp", "grasp", "hold_on_board", "work_on", "finish_cut", "place", "place"], "work_on"),
    "Stir": ("kit_bimanual/Stir_files_motions_2941_Stir1_bc_s_right_03.mmm.xml",
             ["grasp_both", "work_in", "take_out", "place_both"], "work_in"),
}
# Cut: saw replaced by follow (tests/data/kit_follow/cut.oac: work_on), the knife's path fitted
# onto the cucumber's top. Pour (bring_to's touch replaced by follow, tests/data/kit_follow/pour.oac)
# was verified on seeds 0 and 1 by the closed loop of virtual markers; the verifier of issue 18
# (relations from the simulation's contacts) sees the tilted carton touch the hand that holds the
# cup: not verified yet, so not kept here (docs/runtime.md, "follow").


def test_each_follow_step_gets_the_path_of_its_own_two_objects(capsys: pytest.CaptureFixture[str]) -> None:
    """Pour: the demonstrator lifted the cup to the carton (the carton's path relative to the cup
    is that motion inverted); Scoop: the ladle leaves the cup for the bowl (its path relative to the
    bowl, not the cup it leaves). Composing only, no simulation."""
    from oacdsl.cli import main

    for relative, wanted in (
        ("kit_bimanual/Pour_files_motions_2967_Pour1_cs_ms_0_20l_04.mmm.xml",
         ["milk_small relative to cup_small"]),
        ("kit_bimanual/Scoop_files_motions_2989_Scoop1_mbg_l_CS_225_30o_04.mmm.xml",
         ["ladle relative to cup_small", "ladle relative to mixing_bowl_green"]),
    ):
        recording = mocap_file(relative)
        args = ["compose", str(recording), "--library", str(FOLLOW_KIT), "--name", "t", "--dry-run"]
        assert main(args) == 0
        text = capsys.readouterr().out
        assert "no demonstrated path" not in text
        assert [line.split("(", 1)[1].split(",")[0] for line in text.splitlines()
                if "# demonstrated (" in line and "path of" in line] == wanted


@pytest.mark.slow
@pytest.mark.parametrize(("clip", "seed"), [("Cut", None), ("Cut", 1), ("Stir", None), ("Stir", 2)])
def test_a_named_skill_replaced_by_follow_is_reproduced_and_verified(clip: str, seed: int | None,
                                                                      tmp_path: Path) -> None:
    """Cut seed 1: the cucumber carried to its place from under the knife the other hand holds
    up, round it (runtime/motion/detour.py; before, the hand carrying it touched the blade).
    Stir: faithful, its circles judged (motion.4.cycles): the spoon, whose floor is out of reach
    with its hand clear of the cup's rim, is pushed out to the wall and circles along it, its
    rocking shrunk with its circles (runtime/skills/follow_wall.py; before, it circled in the
    middle touching the cup now and then: no oscillation; seed 2's hand met the rim)."""
    pytest.importorskip("mujoco")
    from oacdsl.pipeline import load_inputs, reproduce
    from oacdsl.pipeline.inputs import default_name
    from oacdsl.segmentation import AasParams

    relative, steps, follows = CLIPS[clip]
    recording = mocap_file(relative)
    library = tmp_path / "kit_follow"
    shutil.copytree(FOLLOW_KIT, library, ignore=shutil.ignore_patterns("learned", "drafts"))
    inputs = load_inputs(recording, library, None, AasParams())
    name = default_name(str(recording))
    outcome = reproduce(inputs, name=name, out=tmp_path / "out", db=None, render=False, quiet=True,
                        seed=seed)
    result = outcome.result
    assert outcome.exit_code == 0, result["verdict"]
    assert [s["oac"] for s in result["compose"]["steps"]] == steps
    assert result["verification"]["verified"] and result["verification"]["distance"] == 0
    if clip == "Stir":
        assert result["verdict"]["faithful"], result["verdict"]["summary"]
    # the step ran the generic skill on the demonstrated path the composer wrote
    text = (library / "learned" / f"{name}.oac").read_text(encoding="utf-8")
    assert f"{follows}(" in text and "path [" in text
    ran = next(s for s in result["run"]["steps"] if s["oac"] == follows)
    assert ran["success"] and ran["params"]["path_keyframes"] >= 10
