"""``oacc segment --motion`` / ``--plot-motion``: table, JSON records, picture, errors."""

import json

import pytest
from _mocap import mocap_file
from _motion_helpers import synthetic_stir

from oacdsl.cli import main
from oacdsl.segmentation.readers import write_c3d

STIR = "kit_bimanual/Stir_files_motions_2941_Stir1_bc_s_right_03.mmm.xml"


@pytest.fixture(scope="module")
def stir_c3d(tmp_path_factory):
    rec, _ = synthetic_stir()
    return write_c3d(rec, tmp_path_factory.mktemp("rec") / "stir.c3d")


def run(capsys, *argv):
    code = main(["segment", *map(str, argv)])
    out, err = capsys.readouterr()
    return code, out, err


def test_motion_table_on_a_synthetic_stir(stir_c3d, capsys):
    code, out, err = run(capsys, stir_c3d, "--motion")
    assert code == 0, err
    table = out.split("demonstrated motion per sub-action")[1]
    rows = [line for line in table.splitlines() if " spoon " in line and "cup (" in line]
    assert rows, out
    assert any("0.60s x" in row for row in rows), rows  # the synthetic stir's period, 0.6 s
    assert "right_hand" in rows[0]


def test_motion_json_records(stir_c3d, capsys):
    code, out, err = run(capsys, stir_c3d, "--motion", "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert len(doc["motions"]) == len(doc["keyframes"]) - 1
    stir = [m for m in doc["motions"] if (m["moved"], m["target"]) == ("spoon", "cup")
            and m["features"]["period_s"] is not None]
    assert stir and stir[0]["features"]["period_s"] == pytest.approx(0.6, rel=0.05)
    first = stir[0]
    n = first["end_frame"] - first["start_frame"] + 1
    assert len(first["T_target_object"]) == n == len(first["times_s"])
    assert first["T_target_object"][0][3] == [0.0, 0.0, 0.0, 1.0]
    code, out, _ = run(capsys, stir_c3d, "--json")
    assert "motions" not in json.loads(out)  # only when asked


def test_plot_motion_is_written(stir_c3d, capsys, tmp_path):
    picture = tmp_path / "motion.png"
    code, out, err = run(capsys, stir_c3d, "--plot-motion", picture)
    assert code == 0, err
    assert picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and picture.stat().st_size > 20_000
    assert f"wrote {picture}" in err and "demonstrated motion" not in out  # the table only with --motion
    assert [p.name for p in tmp_path.iterdir()] == ["motion.png"]  # no temporary file left


def test_plot_motion_bad_suffix_is_one_line_exit_2(stir_c3d, capsys, tmp_path):
    code, out, err = run(capsys, stir_c3d, "--plot-motion", tmp_path / "motion.txt")
    assert code == 2
    assert err.strip().count("\n") == 0 and "error" in err and ".png, .pdf or .svg" in err
    assert not (tmp_path / "motion.txt").exists()


def test_kit_stir_motion_table(capsys, tmp_path):
    code, out, err = run(capsys, mocap_file(STIR), "--motion", "--plot-motion", tmp_path / "stir.png")
    assert code == 0, err
    rows = [line for line in out.splitlines() if "tablespoon" in line and "cup_large (" in line]
    assert any(" 0.50s x3.5 " in row for row in rows), out  # measured: 0.50 s, 3.5 circles
    # numbered as oacc match and the verifier number sub-actions: the stir ends at keyframe 4
    assert [row.split()[:2] for row in rows if "(broken)" in row] == [["4", "27-48"]], rows
    assert (tmp_path / "stir.png").stat().st_size > 20_000
