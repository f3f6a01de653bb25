"""The ARMAR-III model against the published kinematic facts, in MuJoCo and in placo.

The expected values are written here from ``shared/reference/armar3-kinematics.md``
(world positions and axes at q = 0, mm), independently of ``oacdsl.runtime.armar3``:
a product-of-exponentials chain built from these rows is the reference kinematics.
"""

import math

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
placo = pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")

from oacdsl.runtime import urdf  # noqa: E402

S, C = math.sin(math.radians(15)), math.cos(math.radians(15))

# joint: (world position at q=0 in mm, world axis at q=0, limits in rad) — the facts' tables
FACTS = {
    "hip_pitch": ((158.0, 0.0, 890.0), (0, -1, 0), (-0.7854, 0.7854)),
    "hip_roll": ((158.0, 0.0, 890.0), (1, 0, 0), (-0.7854, 0.7854)),
    "hip_yaw": ((158.0, 0.0, 890.0), (0, 0, 1), (-0.7854, 0.7854)),
    "shoulder_1_r": ((123.0, -232.0, 1375.0), (0, 1, 0), (-1.8665, 1.3963)),
    "shoulder_2_r": ((123.0, -232.0, 1375.0), (-1, 0, 0), (-0.2417, 1.6514)),
    "upperarm_r": ((123.0, -232.0, 1375.0), (0, S, C), (-1.8869, 1.2905)),
    "elbow_r": ((143.0, -312.2, 1075.6), (0, -C, S), (-1.9998, 0.9599)),
    "underarm_r": ((143.0, -319.5, 1077.5), (-1, 0, 0), (-1.2156, 1.8893)),
    "wrist_1_r": ((383.0, -319.5, 1077.5), (0, -S, -C), (-0.5093, 0.5215)),
    "wrist_2_r": ((383.0, -319.5, 1077.5), (0, C, -S), (-0.5393, 0.8878)),
    "shoulder_1_l": ((123.0, 232.0, 1375.0), (0, 1, 0), (-1.8659, 1.3963)),
    "shoulder_2_l": ((123.0, 232.0, 1375.0), (-1, 0, 0), (-1.6514, 0.2417)),
    "upperarm_l": ((123.0, 232.0, 1375.0), (0, -S, C), (-1.2156, 1.8893)),
    "elbow_l": ((143.0, 312.2, 1075.6), (0, -C, -S), (-2.1461, 0.9599)),
    "underarm_l": ((143.0, 319.5, 1077.5), (-1, 0, 0), (-1.8893, 1.2156)),
    "wrist_1_l": ((383.0, 319.5, 1077.5), (0, S, -C), (-0.5124, 0.4208)),
    "wrist_2_l": ((383.0, 319.5, 1077.5), (0, C, S), (-0.6702, 0.7735)),
}
TCP0 = {"r": (513.0, -319.5, 1077.5), "l": (513.0, 319.5, 1077.5)}
TORSO = ["hip_pitch", "hip_roll", "hip_yaw"]
ARM = {
    s: [
        f"shoulder_1_{s}",
        f"shoulder_2_{s}",
        f"upperarm_{s}",
        f"elbow_{s}",
        f"underarm_{s}",
        f"wrist_1_{s}",
        f"wrist_2_{s}",
    ]
    for s in "rl"
}


def rot(axis, angle):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def reference_tcp(side, q):
    """TCP position (m) by the product of exponentials of the facts' rows (base: x, y, yaw)."""
    x = np.array(TCP0[side]) * 1e-3
    for name in reversed(TORSO + ARM[side]):
        p = np.array(FACTS[name][0]) * 1e-3
        x = rot(FACTS[name][1], q.get(name, 0.0)) @ (x - p) + p
    x = rot((0, 0, 1), q.get("base_yaw", 0.0)) @ x
    return x + np.array([q.get("base_x", 0.0), q.get("base_y", 0.0), 0.0])


def poses():
    rng = np.random.default_rng(7)
    out = [
        {},
        {"elbow_r": math.radians(-86), "elbow_l": math.radians(-86)},
        {"shoulder_1_r": -0.8, "shoulder_2_l": -0.5, "hip_pitch": 0.3},
    ]
    for _ in range(5):
        q = {n: float(rng.uniform(*FACTS[n][2])) for n in FACTS}
        q.update(
            base_x=float(rng.uniform(-0.3, 0.3)),
            base_y=float(rng.uniform(-0.3, 0.3)),
            base_yaw=float(rng.uniform(-1, 1)),
        )
        out.append(q)
    return out


def test_zero_pose_tcps_match_the_facts():
    for side in "rl":
        assert np.linalg.norm(reference_tcp(side, {}) - np.array(TCP0[side]) * 1e-3) < 1e-9


def test_reach_fact_elbow_straight():
    # facts: maximum shoulder-to-TCP distance ≈ 681 mm with the elbow at -86°
    tcp = reference_tcp("r", {"elbow_r": math.radians(-86)})
    assert abs(np.linalg.norm(tcp - np.array(FACTS["shoulder_1_r"][0]) * 1e-3) - 0.681) < 0.002


@pytest.mark.parametrize("index", range(8))
def test_mujoco_forward_kinematics_matches_the_facts(index):
    model = mujoco.MjModel.from_xml_path(str(urdf.URDF_PATH))
    data = mujoco.MjData(model)
    q = poses()[index]
    for name, value in q.items():
        data.qpos[model.joint(name).qposadr[0]] = value
    mujoco.mj_kinematics(model, data)
    for side in "rl":
        got = data.xpos[model.body(f"tcp_{side}").id]
        assert np.linalg.norm(got - reference_tcp(side, q)) < 1e-3, (side, q)


@pytest.mark.parametrize("index", range(8))
def test_placo_forward_kinematics_matches_the_facts(index):
    robot = placo.RobotWrapper(str(urdf.URDF_PATH), placo.Flags.ignore_collisions)
    q = poses()[index]
    for name, value in q.items():
        robot.set_joint(name, value)
    robot.update_kinematics()
    for side in "rl":
        got = robot.get_T_world_frame(f"tcp_{side}")[:3, 3]
        assert np.linalg.norm(got - reference_tcp(side, q)) < 1e-3, (side, q)


def test_joint_names_are_identical_in_mujoco_and_placo():
    model = mujoco.MjModel.from_xml_path(str(urdf.URDF_PATH))
    robot = placo.RobotWrapper(str(urdf.URDF_PATH), placo.Flags.ignore_collisions)
    mj = {model.joint(i).name for i in range(model.njnt)}
    pl = set(robot.joint_names()) - {"universe", "root_joint"}
    assert mj == pl and len(mj) == 3 + 3 + 7 + 2 * 7 + 2 * 4


def test_tcp_orientation_matches_the_facts():
    # Hand base / TCP axes at q=0: x=(0,-0.26,-0.97) y=(0,0.97,-0.26) z=(1,0,0) (right)
    robot = placo.RobotWrapper(str(urdf.URDF_PATH), placo.Flags.ignore_collisions)
    robot.update_kinematics()
    r = robot.get_T_world_frame("tcp_r")[:3, :3]
    assert np.allclose(r, np.array([[0, 0, 1], [-S, C, 0], [-C, -S, 0]]), atol=1e-6)


def test_shipped_urdf_is_up_to_date():
    assert urdf.URDF_PATH.read_text(encoding="utf-8") == urdf.urdf_text(), (
        "run: python -m oacdsl.runtime.urdf"
    )
    assert urdf.COLLISIONS_PATH.read_text(encoding="utf-8") == urdf.collisions_text()
