"""Object poses by a rigid fit of markers, and the MMM ``ModelPose`` reader (synthetic and KIT clips)."""

import numpy as np
import pytest
from _mocap import mocap_file

from oacdsl.errors import RecordingError
from oacdsl.segmentation.poses import (
    agreement,
    fit_constellation,
    fit_instance,
    fit_poses,
    invert,
    relative,
    rotation_angle,
)
from oacdsl.segmentation.readers import read_recording
from oacdsl.segmentation.readers.mmm_pose import read_model_poses, rpy_matrix
from oacdsl.segmentation.recording import Recording

RATE_HZ = 100.0


def rot_z(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def rot_x(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])


def moving_body(frames=300, noise_m=0.0005, seed=0):
    """A 4-marker body (metres) turning about z, tilting about x, travelling; and its T_world_object."""
    rng = np.random.default_rng(seed)
    body = np.array([[0.04, 0.0, 0.0], [-0.03, 0.03, 0.01], [0.0, -0.05, 0.02], [-0.01, 0.02, -0.03]])
    body -= body.mean(axis=0)  # the fit's origin is the centroid at the reference frame
    t = np.arange(frames) / RATE_HZ
    T = np.tile(np.eye(4), (frames, 1, 1))
    T[:, :3, :3] = np.stack([rot_z(1.5 * s) @ rot_x(0.8 * np.sin(2 * s)) for s in t])
    T[:, :3, 3] = np.stack([0.3 * t, 0.1 * np.sin(t), 0.8 + 0.05 * t], axis=1)
    T[0] = np.eye(4)  # the reference frame: the object as it stood
    T[0, :3, 3] = (0.0, 0.0, 0.8)
    pts = np.einsum("fij,kj->fki", T[:, :3, :3], body) + T[:, None, :3, 3]
    pts += rng.normal(0.0, noise_m, pts.shape)
    return t, pts, T


def make_recording(pts, extra=None):
    names = [f"m{i}" for i in range(pts.shape[1])]
    groups = {"thing": tuple(range(pts.shape[1]))}
    positions = pts
    if extra is not None:
        groups["dot"] = (pts.shape[1],)
        names.append("dot")
        positions = np.concatenate([pts, extra[:, None, :]], axis=1)
    t = np.arange(len(pts)) / RATE_HZ
    return Recording("synthetic", RATE_HZ, t, tuple(names), positions, groups)


def test_known_rigid_motion_recovered_through_noise_and_gaps():
    t, pts, truth = moving_body()
    pts = pts.copy()
    pts[50:60, 0] = np.nan  # one marker occluded: 3 remain, still posed
    pts[100:110, :2] = np.nan  # two occluded: a gap
    pts[200, :] = np.nan  # all occluded
    poses = fit_instance(make_recording(pts), "thing")
    gap = np.zeros(len(t), bool)
    gap[100:110] = gap[200] = True
    assert np.array_equal(~poses.valid, gap)
    assert np.isnan(poses.residual_m[gap]).all()
    assert poses.reference_frame == 0 and poses.visible[55] == 3
    ok = ~gap
    pos_err = np.linalg.norm(poses.positions_m[ok] - truth[ok, :3, 3], axis=1)
    ang_err = rotation_angle(np.swapaxes(poses.T_world_object[ok, :3, :3], 1, 2) @ truth[ok, :3, :3])
    assert pos_err.max() < 0.002  # metres: 0.5 mm of marker noise on a 5 cm body
    assert np.degrees(ang_err).max() < 4.0  # worst where only 3 markers are seen
    assert np.degrees(np.median(ang_err)) < 1.0
    assert 0.0002 < np.nanmedian(poses.residual_m) < 0.001  # the residual reports the noise


def test_exact_markers_give_exact_poses_and_a_vectorised_batch():
    _, pts, truth = moving_body(frames=50, noise_m=0.0)
    constellation = pts[0] - pts[0].mean(axis=0)
    T, residual = fit_constellation(constellation, pts)
    assert np.allclose(T, truth, atol=1e-9) and np.allclose(residual, 0.0, atol=1e-9)


def test_a_mirrored_constellation_is_never_fitted_by_a_reflection():
    _, pts, _ = moving_body(frames=5, noise_m=0.0)
    mirrored = pts[0] * np.array([-1.0, 1.0, 1.0])
    T, residual = fit_constellation(pts[0] - pts[0].mean(axis=0), mirrored[None])
    assert np.isclose(np.linalg.det(T[0, :3, :3]), 1.0)
    assert residual[0] > 0.005  # the fit says it does not fit


def test_instances_with_fewer_than_three_markers_get_no_pose():
    _, pts, _ = moving_body(frames=20)
    rec = make_recording(pts, extra=np.zeros((20, 3)))
    assert list(fit_poses(rec)) == ["thing"]
    with pytest.raises(RecordingError, match="'dot' has 1 marker"):
        fit_instance(rec, "dot")
    with pytest.raises(RecordingError, match="did you mean 'thing'"):
        fit_instance(rec, "thin")


def test_relative_and_invert():
    _, _, truth = moving_body(frames=30, noise_m=0.0)
    assert np.allclose(invert(truth) @ truth, np.eye(4), atol=1e-12)
    rel = relative(truth, truth[::-1])
    assert np.allclose(truth @ rel, truth[::-1], atol=1e-12)


MMM = """<?xml version='1.0'?>
<MMM version="2.0">
 <Motion name="true_box" type="object" synchronized="true"><Sensors>
  <Sensor type="ModelPose" version="1.0"><Configuration/><Data>
   <Measurement timestep="0"><RootPosition>100 200 900</RootPosition>
    <RootRotation>0 0 0</RootRotation></Measurement>
   <Measurement timestep="0.1"><RootPosition>110 200 900</RootPosition>
    <RootRotation>0.3 -0.2 1.5</RootRotation></Measurement>
  </Data></Sensor></Sensors></Motion>
 <Motion name="true_1723" type="object"><Sensors>
  <Sensor type="Kinematic" version="1.0"><Data/></Sensor>
  <Sensor type="ModelPose" version="1.0"><Data>
   <Measurement timestep="0"><RootPosition>0 0 0</RootPosition>
    <RootRotation>0 0 0</RootRotation></Measurement>
  </Data></Sensor></Sensors></Motion>
</MMM>
"""


def test_model_pose_reader(tmp_path):
    path = tmp_path / "two.mmm.xml"
    path.write_text(MMM)
    poses = read_model_poses(path)
    assert sorted(poses) == ["box", "subject_1723"]  # named like read_mmm's groups
    box = poses["box"]
    assert np.allclose(box.times_s, [0.0, 0.1])
    assert np.allclose(box.T_world_model[1, :3, 3], [0.11, 0.2, 0.9])  # mm → m
    expected = rot_z(1.5) @ np.array([[np.cos(-0.2), 0, np.sin(-0.2)], [0, 1, 0],
                                      [-np.sin(-0.2), 0, np.cos(-0.2)]]) @ rot_x(0.3)
    assert np.allclose(box.T_world_model[1, :3, :3], expected)
    assert np.allclose(rpy_matrix(np.zeros(3)), np.eye(3))


def test_model_pose_reader_errors(tmp_path):
    bad = tmp_path / "bad.mmm.xml"
    bad.write_text(MMM.replace("110 200 900", "110 200"))
    where = r"bad.mmm.xml: line 8: motion 'true_box', timestep 0.1: RootPosition"
    with pytest.raises(RecordingError, match=where):
        read_model_poses(bad)
    nan = tmp_path / "nan.mmm.xml"
    nan.write_text(MMM.replace("0.3 -0.2 1.5", "0.3 nan 1.5"))
    with pytest.raises(RecordingError, match="RootRotation is '0.3 nan 1.5', expected three finite numbers"):
        read_model_poses(nan)
    bomb = tmp_path / "bomb.mmm.xml"
    bomb.write_text(MMM.replace("<MMM", '<!DOCTYPE MMM [<!ENTITY a "aaaa">]>\n<MMM', 1))
    with pytest.raises(RecordingError, match="document type declaration"):
        read_model_poses(bomb)
    broken = tmp_path / "broken.mmm.xml"
    broken.write_text(MMM[:300])
    with pytest.raises(RecordingError, match="not well-formed XML at line"):
        read_model_poses(broken)


@pytest.mark.parametrize("clip", ["Pour_files_motions_2967_Pour1_cs_ms_0_20l_04",
                                  "Wipe_files_motions_3091_Wipe1_pl_sp_front_angle_03"])
def test_rigid_fit_agrees_with_the_mmm_model_pose_on_bulky_objects(clip):
    path = mocap_file(f"kit_bimanual/{clip}.mmm.xml")
    recording, model = read_recording(path), read_model_poses(path)
    fitted = {name: p for name, p in fit_poses(recording).items() if name in model}
    assert len(fitted) >= 2
    for name, poses in fitted.items():
        if name.startswith("subject_"):
            continue
        position, angle = agreement(poses, model[name].T_world_model)
        assert np.nanmax(position) < 0.001, name  # metres
        assert np.degrees(np.nanmax(angle)) < 3.0, name
        assert np.nanmedian(poses.residual_m) < 0.001, name


def test_model_pose_of_the_thin_tablespoon_flips_where_the_rigid_fit_stays_smooth():
    path = mocap_file("kit_bimanual/Stir_files_motions_2941_Stir1_bc_s_right_03.mmm.xml")
    fit = fit_poses(read_recording(path))["tablespoon"].T_world_object
    model = read_model_poses(path)["tablespoon"].T_world_model
    step = {name: np.degrees(rotation_angle(np.swapaxes(T[:-1, :3, :3], 1, 2) @ T[1:, :3, :3]))
            for name, T in (("fit", fit), ("model", model))}
    assert step["model"][4] > 90  # frame 4 → 5: ModelPose turns ~150° about the handle ...
    assert step["fit"][:20].max() < 5  # ... while the spoon lies still on the table


@pytest.mark.parametrize("shuffled", [False, True])
def test_chunk_coordinates_fill_rigid_gaps_as_the_filled_recording_has_them(shuffled):
    """The segmenter fills rigid gaps straight into a chunk's float32 coordinates
    (:meth:`RigidFill.cells`), not into a copy of its positions: the same numbers, bit for bit,
    as the coordinates of the recording filled beforehand (markers in any order)."""
    from oacdsl.segmentation.geometry import ChunkGeometry
    from oacdsl.segmentation.pairs import PairTable
    from oacdsl.segmentation.poses import RigidFill, fill_rigid_gaps

    rng = np.random.default_rng(3)
    n = 700
    t = np.arange(n) / RATE_HZ
    tracks, names, groups = [], [], {}
    for i, name in enumerate(("box", "cup", "hand")):
        body = rng.normal(scale=0.04, size=(4 + (name == "hand"), 3))
        turn = np.stack([rot_z(a) for a in 0.5 * t + i])
        pts = np.einsum("fij,kj->fki", turn, body) + np.array([0.3 * i, 0.1, 0.8])
        pts[:, :, 0] += 0.05 * np.sin(t + i)[:, None]
        pts[rng.random(pts.shape[:2]) < 0.02] = np.nan  # single markers hidden
        groups[name] = tuple(range(len(names), len(names) + pts.shape[1]))
        names += [f"{name}.{k}" for k in range(pts.shape[1])]
        tracks.append(pts)
    positions = np.concatenate(tracks, axis=1)
    if shuffled:  # instances' markers interleaved in the file: the pair table reorders them
        order = rng.permutation(positions.shape[1])
        inverse = np.argsort(order)
        positions = positions[:, order]
        names = [names[j] for j in order]
        groups = {g: tuple(int(inverse[j]) for j in idx) for g, idx in groups.items()}
    rec = Recording("test", RATE_HZ, t, tuple(names), positions, groups)
    rigid = ["box", "cup"]
    filler = RigidFill(rec, rigid)
    filled = fill_rigid_gaps(rec, rigid)
    assert np.isnan(filled.positions_m).sum() < np.isnan(rec.positions_m).sum()  # something filled
    table = PairTable.of(rec)
    direct, copied = ChunkGeometry(rec, table, filler), ChunkGeometry(filled, table)
    copied.centre = direct.centre  # the centre comes from the first frame as recorded
    for lo, hi in ((0, n), (0, 1), (33, 301), (650, n)):
        assert np.array_equal(direct.coordinates(lo, hi), copied.coordinates(lo, hi), equal_nan=True)
