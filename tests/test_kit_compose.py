"""Mix, Wipe, Scoop and Cut (KIT development clips) compose into one OAC of library/kit (no robot)."""

from __future__ import annotations

from pathlib import Path

import pytest
from _mocap import mocap_file

from oacdsl.cli import main
from oacdsl.compiler import load_library

ROOT = Path(__file__).resolve().parents[1]
KIT = ROOT / "library" / "kit"

#: clip → the OAC each sub-action matches, in order (the keyframes: tests/test_toolroles.py).
STEPS = {
    "Mix": ["grasp_both", "mix_both", "leave_both_in"],
    "Wipe": ["take_plate", "grasp", "wipe_held", "lift_sponge", "set_into_rack", "leave_in_rack", "place"],
    "Scoop": ["grasp", "take_and_dip", "scoop_into", "back_into", "put_down_and_leave"],
    "Cut": ["grasp", "grasp", "hold_on_board", "cut", "finish_cut", "place", "place"],
}
#: clip → what the composed OAC leaves behind (its positive effects).
LEFT = {
    "Mix": {("mixing_bowl_green", "salad_fork"), ("mixing_bowl_green", "salad_spoon")},
    "Wipe": {("draining_rack", "plate_dish")},
    "Scoop": {("ladle", "mixing_bowl_green")},
    "Cut": set(),
}


@pytest.mark.parametrize("clip", sorted(STEPS))
def test_clip_composes_into_the_oacs_of_its_sub_actions(clip, tmp_path, capsys):
    xml = next(mocap_file("kit_bimanual").glob(f"{clip}_*.mmm.xml"))
    name = f"kit_{clip.lower()}_demo"
    out = tmp_path / f"{name}.oac"
    code = main(["compose", str(xml), "--library", str(KIT), "--name", name, "-o", str(out)])
    _, err = capsys.readouterr()
    assert code == 0, err
    library = load_library([KIT, out])
    composed = library.oacs[name]
    assert [step.oac for step in composed.steps] == STEPS[clip]
    defaults = {p.name: p.default for p in composed.params}
    made = {tuple(sorted((defaults.get(a.left, a.left), defaults.get(a.right, a.right))))
            for a in composed.effect if not a.negated and a.right != "nothing"}
    assert made == LEFT[clip]


def test_a_clip_scene_without_its_oacs_says_what_is_missing(tmp_path, capsys):
    """Without mix.oac's OACs, nor stir.oac's or the generic touch (two stirs or touches at once
    would do: docs/matching.md, split keyframes), the mixing sub-action matches nothing: exit 1,
    the change named."""
    lib = tmp_path / "kit"
    lib.mkdir()
    for f in KIT.glob("*.oac"):
        text = f.read_text()
        if f.name == "mix.oac":
            text = text[: text.index("# The sub-actions of Mix")]
        if f.name == "stir.oac":
            text = text[: text.index("oac stir(")]
        if f.name == "actions.oac":
            text = text[: text.index("# Bring the held object into contact")]
        (lib / f.name).write_text(text)
    xml = next(mocap_file("kit_bimanual").glob("Mix_*.mmm.xml"))
    code = main(["compose", str(xml), "--library", str(lib), "--name", "m", "-o", str(tmp_path / "m.oac")])
    _, err = capsys.readouterr()
    assert code == 1 and "mixing_bowl_green <-> salad_fork" in err


def test_mix_both_takes_the_demonstrated_mixing(tmp_path, capsys):
    """Fork and spoon go into the bowl together (the fork moved most); the spoon's circles
    that follow set the bimanual step's period, radius and turns."""
    xml = next(mocap_file("kit_bimanual").glob("Mix_*.mmm.xml"))
    out = tmp_path / "kit_mix_demo.oac"
    assert main(["compose", str(xml), "--library", str(KIT), "--name", "kit_mix_demo", "-o", str(out)]) == 0
    capsys.readouterr()
    step = load_library([KIT, out]).oacs["kit_mix_demo"].steps[1]
    params = {p.name: p.value for p in step.skill_params}
    assert step.oac == "mix_both" and set(params) == {"period", "radius", "turns"}
    assert 0.7 < params["period"].value < 1.1 and params["period"].unit == "s"
    assert params["turns"].value >= 2
    assert "salad_spoon relative to mixing_bowl_green" in out.read_text()


def test_the_wipe_plate_is_to_end_on_edge_in_the_rack_as_the_person_left_it(tmp_path, capsys):
    """The composer writes the demonstrated end tilt (the plate's axis from the rack's at the end
    of its rigid fit, about 97°) on the step that sets it into the rack (touch's ``tilt``); the
    runtime sets it on edge into a slot from that (tests/test_rack.py, test_kit_reproduce.py)."""
    import math

    xml = mocap_file("kit_bimanual/Wipe_files_motions_3091_Wipe1_pl_sp_front_angle_03.mmm.xml")
    out = tmp_path / "wipe_demo.oac"
    code = main(["compose", str(xml), "--library", str(KIT), "--name", "wipe_demo", "-o", str(out)])
    assert code == 0, capsys.readouterr().err
    step = next(s for s in load_library([KIT, out]).oacs["wipe_demo"].steps if s.oac == "set_into_rack")
    tilt = {p.name: p.value for p in step.skill_params}["tilt"]
    assert tilt.unit == "deg" and 80 <= tilt.value <= 110, tilt
    assert math.radians(tilt.value) > math.pi / 4  # on edge, not lying as it lay
