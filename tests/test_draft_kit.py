"""``oacc draft`` on the KIT development clips (skipped without ``../shared/mocap``): the draft
compiles alone and with ``library/``, and ``oacc compose --library DRAFT --library library``
reaches matching and says what is missing. Never the evaluation clips."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from tests._draft_helpers import LIBRARY, check_draft, dims, run

KIT_DEV = ("Pour", "Stir", "Mix", "Wipe", "Scoop", "Cut")  # development clips only (not the evaluation ones)


def kit_clip(name: str) -> Path:
    from tests._mocap import MOCAP, mocap_file

    folder = mocap_file("kit_bimanual")
    assert MOCAP is not None
    (clip,) = sorted(folder.glob(f"{name}_files_*.mmm.xml"))
    return clip


@pytest.mark.parametrize("name", KIT_DEV)
def test_draft_of_a_kit_clip_compiles_and_reaches_matching(capsys, tmp_path, name):
    from oacdsl.segmentation.grouping import group_recording
    from oacdsl.segmentation.readers import read_recording

    clip = kit_clip(name)
    groups = set(group_recording(read_recording(clip), None)[0].instances)
    alone = tmp_path / "alone.oac"
    code, _, err = run(capsys, "draft", str(clip), "-o", str(alone))
    assert code == 0, err
    assert "marker set 'kit' recognised" in err  # hands found unasked, as oacc segment does
    classes, scene = check_draft(alone.read_text(encoding="utf-8"))
    assert {i.name for i in scene.instances} == groups | {"table"}
    assert {"left_hand", "right_hand"} <= groups
    for inst in scene.instances:
        if inst.name not in ("left_hand", "right_hand", "table"):  # 4 markers each: a shape
            size = dims(classes[inst.classes[0]])
            assert all(0.01 <= v <= 0.5 for v in size.values()), (inst.name, size)
    library = tmp_path / "library"
    shutil.copytree(LIBRARY, library, ignore=shutil.ignore_patterns("learned", "drafts"))
    code, _, err = run(capsys, "match", str(clip), "--library", str(library))  # no scene yet: says what to do
    assert code == 1 and "no scene of the library has exactly" in err and "oacc draft RECORDING" in err
    draft = tmp_path / f"{name.lower()}.oac"
    code, _, err = run(capsys, "draft", str(clip), "--library", str(library), "-o", str(draft))
    assert code == 0, err
    text = draft.read_text(encoding="utf-8")
    classes, _ = check_draft(text, library)
    assert not {"Hand", "Table", "Graspable"} & set(classes)  # the library's
    assert f"oacc compose {clip} --library {draft} --library {library} --name NAME --propose" in text
    # the draft is the scene compose needs: matching starts, and says what is missing
    code, out, err = run(capsys, "compose", str(clip), "--library", str(draft), "--library", str(library),
                         "--name", f"kit_{name.lower()}")
    assert code == 1 and out == ""
    assert re.search(r"error: sub-action \d+ \(frames \d+–\d+\) matches no OAC", err), err
    assert "pass --propose for a draft" in err
    assert not (library / "learned").exists() and not (library / "drafts").exists()


def test_compose_propose_writes_drafts_over_a_drafted_scene(capsys, tmp_path):
    clip = kit_clip("Pour")
    library = tmp_path / "library"
    shutil.copytree(LIBRARY, library, ignore=shutil.ignore_patterns("learned", "drafts"))
    draft = tmp_path / "pour_scene.oac"
    assert run(capsys, "draft", str(clip), "--library", str(library), "-o", str(draft))[0] == 0
    code, out, err = run(capsys, "compose", str(clip), "--library", str(draft), "--library", str(library),
                         "--name", "kit_pour", "--propose")
    assert code == 0, err
    written = sorted(p.name for p in (library / "drafts").iterdir())
    assert "kit_pour.oac" in written and len(written) >= 2  # the OAC and the drafts of what it lacked
    composed = (library / "drafts" / "kit_pour.oac").read_text(encoding="utf-8")
    assert "cup: Cup = cup_small" in composed  # the library's Cup: its name's word is the group's
