"""``verify_execution`` on the bundled demonstration and the six KIT development clips: the
demonstration against itself and other takes of it (verified and faithful), and corrupted
copies (rejected by the right check). The corruptions are built here from each clip
(tests/_verify_takes.py), the other takes by the take generator
(oacdsl/segmentation/takes.py); which apply depends on what the clip shows (an object moved
elsewhere, an oscillation, a tilt), and every kind occurs on some clip."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import _verify_takes as corrupt
import numpy as np
import pytest
from _mocap import mocap_file

from oacdsl.matching.transient import agents_of, stable_segmentation
from oacdsl.pipeline import load_inputs
from oacdsl.segmentation import AasParams, segment, takes
from oacdsl.segmentation.motion import sub_action_motions
from oacdsl.verify_execution import VerifyOutcome, normalised, verify_execution

ROOT = Path(__file__).resolve().parents[1]
KIT = {
    "Pour": "kit_bimanual/Pour_files_motions_2967_Pour1_cs_ms_0_20l_04.mmm.xml",
    "Stir": "kit_bimanual/Stir_files_motions_2941_Stir1_bc_s_right_03.mmm.xml",
    "Mix": "kit_bimanual/Mix_files_motions_3121_Mix1_salad_gb_parallel_08.mmm.xml",
    "Wipe": "kit_bimanual/Wipe_files_motions_3091_Wipe1_pl_sp_front_angle_03.mmm.xml",
    "Scoop": "kit_bimanual/Scoop_files_motions_2989_Scoop1_mbg_l_CS_225_30o_04.mmm.xml",
    "Cut": "kit_bimanual/Cut_files_motions_3021_Cut1_c_0_05cm_03.mmm.xml",
}


@dataclass
class Case:
    inputs: Any

    @property
    def demo(self) -> Any:
        return self.inputs.recording

    def verify(self, execution: Any, any_hands: bool = False) -> VerifyOutcome:
        i = self.inputs
        return verify_execution(self.demo, execution, scene=i.scene, library=i.library, params=i.params,
                                any_hands=any_hands)


def _case(name: str) -> Case:
    if name == "dough":
        return Case(load_inputs(ROOT / "data" / "dough.c3d", ROOT / "library", None, AasParams()))
    return Case(load_inputs(mocap_file(KIT[name]), ROOT / "library" / "kit", None, AasParams()))


def _failed(o: VerifyOutcome) -> list[str]:
    return [c.name for c in o.failed()]


def _takes(rec: Any) -> dict[str, Any]:
    other_rate = 60.0 if rec.rate_hz != 60.0 else 120.0
    return {
        "rotated 90° and translated 2 m": takes.translated(takes.rotated(rec, math.pi / 2), (2.0, 0.0, 0.0)),
        f"resampled to {other_rate:g} Hz": takes.resampled(rec, other_rate),
        # twice as fast, recorded at twice the rate (a 10 Hz clip played twice as fast at 10 Hz
        # would sample a stirring circle 2.5 times: the motion itself would be lost)
        "stretched x0.5": takes.stretched(takes.resampled(rec, 2 * rec.rate_hz), 0.5),
        "stretched x2": takes.stretched(rec, 2.0),
    }


@pytest.mark.parametrize("clip", ["dough", *KIT])
def test_demonstration_and_its_takes_verify(clip: str) -> None:
    case = _case(clip)
    same = case.verify(case.demo)
    assert same.verified and same.faithful, _failed(same)
    assert any(c.kind == "end_state" for c in same.checks)
    for name, take in _takes(case.demo).items():
        o = case.verify(take)
        assert o.verified and o.faithful, (name, [(c.name, c.detail) for c in o.failed()])


@pytest.mark.parametrize("clip", ["Pour", "Wipe"])
def test_mirrored_take_needs_any_hands(clip: str) -> None:
    case = _case(clip)
    left_handed, hand_map = takes.mirrored(case.demo)
    strict = case.verify(left_handed)
    assert not strict.verified and "relations" in _failed(strict)
    free = case.verify(left_handed, any_hands=True)
    assert free.verified and free.faithful, _failed(free)
    assert free.hand_map == hand_map == {"left_hand": "right_hand", "right_hand": "left_hand"}


def _corruptions(case: Case) -> dict[str, tuple[Any, str, bool]]:
    """name → (corrupted recording, the check that must fail (a prefix), whether only faithfulness
    is at stake: a straightened or unturned path may also take the tool off a contact, so such a
    copy is not required to stay verified, only to fail its motion check)."""
    rec = case.demo
    i = case.inputs
    agents = agents_of(i.library.instance_classes(i.scene))
    seg = stable_segmentation(segment(rec, i.params), agents.__contains__)[0]
    kf = seg.keyframes
    posed = [n for n in rec.instances if n not in agents and len(rec.groups[n]) >= 3]
    released: dict[str, int] = {}  # object → the keyframe where a hand last let go of it
    for a, b in zip(kf, kf[1:], strict=False):
        for r in a.state.relations - b.state.relations:
            for o in posed:
                if o in r and set(r) - {o} <= agents:
                    released[o] = b.frame
    out: dict[str, tuple[Any, str, bool]] = {}
    obj, frame = max(released.items(), key=lambda x: (x[1], x[0]))
    side = corrupt.turned_on_side(rec, obj, min(frame + 2, rec.n_frames - 1))
    out[f"{obj} turned onto its side"] = (side, f"end_state.{obj}.orientation", False)
    # upside down (Mix: the spoon, left leaning in the bowl 48° from how it lay, now 132°)
    flipped = corrupt.turned_upside_down(rec, obj, min(frame + 2, rec.n_frames - 1))
    out[f"{obj} turned upside down"] = (flipped, f"end_state.{obj}.orientation", False)
    same = case.verify(rec)
    for c in same.checks:  # an object the demonstration put elsewhere
        if c.name.endswith(".placed") and c.name.split(".")[1] in released:
            o = c.name.split(".")[1]
            out[f"{o} moved back"] = (corrupt.moved_back(rec, o, released[o]), f"end_state.{o}.", False)
            break
    judged = {int(c.name.split(".")[1]): c.name for c in same.checks if c.kind == "motion"}
    for m in sub_action_motions(rec, seg):
        k = m.index + 1
        if k not in judged or m.moved is None or m.hand is None or m.features is None:
            continue
        if m.target is not None:  # the tool taken off its target while it works on it
            out[f"{m.moved} lifted off {m.target}"] = (
                corrupt.lifted(rec, [m.moved, m.hand], m.start_frame, m.end_frame), "relations", False)
        if judged[k].endswith("cycles"):
            a, b = (int(round(t * rec.rate_hz)) for t in m.features.core_s)
            out[f"{m.moved}'s strokes straightened"] = (
                corrupt.straightened(rec, [m.moved, m.hand], a, b + 1), judged[k], True)
        if judged[k].endswith(("tilt", "turn")):
            out[f"{m.moved}'s turn removed"] = (
                corrupt.unturned(rec, [m.moved], m.start_frame, m.end_frame + 1), judged[k], True)
    return out


@pytest.mark.parametrize("clip", ["dough", *KIT])
def test_corrupted_copies_are_rejected_by_the_right_check(clip: str) -> None:
    case = _case(clip)
    corrupted = _corruptions(case)
    assert len(corrupted) >= 2
    for name, (rec, check, motion_only) in corrupted.items():
        o = case.verify(rec)
        failed = _failed(o)
        assert not o.faithful, name
        assert any(f.startswith(check) for f in failed), (name, check, failed)
        if not motion_only:
            assert not o.verified, name


def test_every_kind_of_corruption_occurs_on_a_clip() -> None:
    words = ("turned onto its side", "turned upside down", "moved back", "lifted off", "straightened",
             "turn removed")
    seen: set[str] = set()
    for clip in KIT:
        for name in _corruptions(_case(clip)):
            seen |= {w for w in words if w in name}
    assert seen == set(words)


def test_normalised_brings_a_take_to_the_pace_and_rate() -> None:
    case = _case("dough")
    slow = takes.stretched(case.demo, 2.0)
    back = normalised(slow, 2.0, case.demo.rate_hz)
    assert back.n_frames == case.demo.n_frames
    assert np.nanmax(np.abs(back.positions_m - case.demo.positions_m)) < 1e-6
