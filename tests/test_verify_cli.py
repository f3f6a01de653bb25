"""``oacc verify`` on files: exit status, output, JSON; the simulated contacts file and its
keyframes; the runtime's ContactRecorder."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import _verify_takes as corrupt
import numpy as np
import pytest

from oacdsl.cli import main
from oacdsl.errors import InputError
from oacdsl.segmentation.readers import read_recording
from oacdsl.segmentation.readers.c3d import write_c3d
from oacdsl.verify_contacts import SimContacts, contacts_path, read_contacts, write_contacts
from oacdsl.verify_tolerances import VerifyTolerances
from oacdsl.world import WorldState

ROOT = Path(__file__).resolve().parents[1]
DOUGH = ROOT / "data" / "dough.c3d"
LIBRARY = ROOT / "library"


def verify(capsys: pytest.CaptureFixture[str], *args: object) -> tuple[int, str, str]:
    code = main(["verify", *(str(a) for a in args)])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_the_demonstration_verifies_against_itself(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = verify(capsys, DOUGH, DOUGH, "--library", LIBRARY, "--json")
    assert code == 0
    doc = json.loads(out)
    assert doc["verified"] is True and doc["faithful"] is True
    assert {"relations", "end_state", "motion"} == {c["kind"] for c in doc["checks"]}
    for c in doc["checks"]:
        assert set(c) >= {"name", "passed", "demonstration", "execution", "tolerance", "detail"}
    assert doc["relations_source"] == "aas" and doc["contacts"] is None
    assert doc["tolerances"]["tilt_rad"] == pytest.approx(VerifyTolerances().tilt_rad, abs=1e-6)


def test_a_cup_left_on_its_side_fails_with_one_line_per_failed_check(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    rec = read_recording(DOUGH)
    bad = tmp_path / "tipped.c3d"
    last = rec.n_frames - 1
    write_c3d(corrupt.turned_on_side(rec, "red_cup", last - 50), bad)
    code, out, _ = verify(capsys, DOUGH, bad, "--library", LIBRARY)
    lines = out.splitlines()
    assert code == 1
    assert lines[0].startswith("not verified: end state failed")
    failed = [x for x in lines if x.startswith("FAILED ")]
    assert failed and failed[0].startswith("FAILED end_state.red_cup.orientation: red_cup ends on its side")
    assert "tolerance: same class" in failed[0]


def test_bad_input_is_one_line_and_exit_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = verify(capsys, DOUGH, tmp_path / "none.c3d", "--library", LIBRARY)
    assert (code, out) == (2, "") and err.strip().count("\n") == 0 and "no such recording file" in err
    copy = tmp_path / "run.c3d"
    copy.write_bytes(DOUGH.read_bytes())
    contacts_path(copy).write_text("{not json")
    code, _, err = verify(capsys, DOUGH, copy, "--library", LIBRARY)
    assert code == 2 and "run.contacts.json: not a JSON document" in err and err.count("\n") == 1


def _as_contacts(rec_path: Path) -> SimContacts:
    """The demonstration's own AAS keyframes as a simulation's contacts (at its frame rate)."""
    from oacdsl.pipeline import load_inputs
    from oacdsl.segmentation import AasParams, segment

    inputs = load_inputs(rec_path, LIBRARY, None, AasParams())
    seg = segment(inputs.motion_capture(), inputs.params)
    changes = tuple((k.frame, k.state.relations) for k in seg.keyframes)
    return SimContacts(seg.rate_hz, seg.frames, tuple(seg.instances), changes, {})


def test_a_contacts_file_beside_the_execution_gives_the_relations(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    copy = tmp_path / "execution.c3d"
    copy.write_bytes(DOUGH.read_bytes())
    sim = _as_contacts(DOUGH)
    write_contacts(sim, contacts_path(copy))
    assert read_contacts(contacts_path(copy)) == sim
    code, out, _ = verify(capsys, DOUGH, copy, "--library", LIBRARY, "--json")
    doc = json.loads(out)
    assert code == 0 and doc["relations_source"] == "simulation contacts"
    assert doc["contacts"] == str(contacts_path(copy))
    # a contact the simulation never made: the relations fail, whatever the markers show
    first = next(i for i, (_, rels) in enumerate(sim.changes) if rels)
    made = sorted(sim.changes[first][1] - sim.changes[first - 1][1])[0]
    cut = tuple((f, rels - {made}) for f, rels in sim.changes)
    write_contacts(SimContacts(sim.rate_hz, sim.frames, sim.instances, cut, {}), contacts_path(copy))
    code, out, _ = verify(capsys, DOUGH, copy, "--library", LIBRARY)
    assert code == 1 and any(x.startswith("FAILED relations:") for x in out.splitlines())
    assert any(x.startswith("finding: the AAS sees") for x in out.splitlines())


def test_contact_keyframes_drop_flicker_bridge_short_lifts_and_merge() -> None:
    rate = 100.0
    ab, cd = ("a", "b"), ("c", "d")
    changes = (
        (0, frozenset()),
        (100, frozenset({ab})),  # a touches b at 1 s
        (150, frozenset()),  # lifts off for 0.2 s: bridged
        (170, frozenset({ab})),
        (300, frozenset({ab, cd})),  # c touches d for 2 frames: flicker, dropped
        (302, frozenset({ab})),
        (400, frozenset()),  # a leaves b at 4 s ...
        (480, frozenset({cd})),  # ... and c touches d 0.8 s later: two keyframes
        (500, frozenset()),  # 0.2 s later c leaves d: merged with its start into one keyframe
    )
    sim = SimContacts(rate, 700, ("a", "b", "c", "d"), changes, {})
    seg = sim.segmentation(("a", "b", "c", "d"), VerifyTolerances())
    rels = [sorted(k.state.relations) for k in seg.keyframes]
    assert [k.frame for k in seg.keyframes] == [0, 100, 400, 500]
    assert rels == [[], [ab], [], []]
    longer = sim.segmentation(("a", "b", "c", "d"), VerifyTolerances(contact_gap_s=0.1, contact_merge_s=0.0))
    assert [k.frame for k in longer.keyframes] == [0, 100, 150, 170, 400, 480, 500]


def test_the_runtime_records_contacts_only_when_they_change() -> None:
    pytest.importorskip("mujoco")
    from oacdsl.runtime.recorder import ContactRecorder

    states = [set(), set(), {("a", "b")}, {("a", "b")}, set()]
    rec = ContactRecorder(100.0)
    for k, rels in enumerate(states):
        world = SimpleNamespace(time_s=2.0 + k / 100, relations=lambda r=rels: WorldState.of(("a", "b"), r))
        rec(world)  # type: ignore[arg-type]
    doc = rec.to_json()
    assert doc["frames"] == 5 and doc["instances"] == ["a", "b"]
    assert [(c["frame"], c["relations"]) for c in doc["changes"]] == [(0, []), (2, [["a", "b"]]), (4, [])]
    assert np.isclose(doc["changes"][1]["time_s"], 0.02)


def test_a_regrasp_within_a_step_is_no_change_of_the_task(tmp_path: Path) -> None:
    # the hand lets go of the lid for 1.2 s to take it again and turn it further (twist): the
    # runtime lists that window as internal; the relation holds through it, and only through it
    hand_lid = ("hand", "lid")
    changes = ((0, frozenset()), (100, frozenset({hand_lid})), (300, frozenset()),
               (420, frozenset({hand_lid})), (800, frozenset()))
    plain = SimContacts(100.0, 900, ("hand", "lid"), changes, {})
    assert len(plain.segmentation(("hand", "lid")).keyframes) == 5  # + − + −: a let-go and a retake
    sim = SimContacts(100.0, 900, ("hand", "lid"), changes, {}, ((hand_lid, 295, 425),))
    seg = sim.segmentation(("hand", "lid"))
    assert [(k.frame, sorted(k.state.relations)) for k in seg.keyframes] == [
        (0, []), (100, [hand_lid]), (800, [])]
    path = write_contacts(sim, tmp_path / "run.contacts.json")
    assert read_contacts(path) == sim  # the windows are part of the file
    doc = json.loads(path.read_text())
    doc["internal"] = [{"relation": ["hand", "lid"], "from_frame": 400, "to_frame": 300}]
    path.write_text(json.dumps(doc))
    with pytest.raises(InputError, match="ends .* before it starts"):
        read_contacts(path)


def test_the_contacts_recorder_lists_the_controllers_regrasps_as_frames() -> None:
    pytest.importorskip("mujoco")
    from oacdsl.runtime.recorder import ContactRecorder

    regrasps: list[tuple[float, float, str, str]] = []
    rec = ContactRecorder(100.0, regrasps=regrasps)
    layout = SimpleNamespace(hands={"left_hand": "l", "right_hand": "r"})
    for k in range(5):
        rec(SimpleNamespace(time_s=2.0 + k / 100, layout=layout,  # type: ignore[arg-type]
                            relations=lambda: WorldState.of(("lid", "left_hand"), [])))
    regrasps.append((2.013, 2.031, "l", "lid"))  # appended by the controller during the run
    assert rec.to_json()["internal"] == [{"relation": ["left_hand", "lid"], "from_frame": 1, "to_frame": 5}]


def test_a_contacts_file_nested_too_deeply_is_an_input_error_naming_it(tmp_path: Path) -> None:
    path = tmp_path / "run.contacts.json"
    path.write_text("[" * 100_000 + "]" * 100_000)  # deeper than the JSON reader recurses
    with pytest.raises(InputError, match="nested too deeply") as caught:
        read_contacts(path)
    assert str(path) in str(caught.value)
