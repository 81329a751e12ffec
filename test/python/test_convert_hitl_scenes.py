"""scripts/convert-hitl-scenes.py: MuJoCo scenes in the layout of Papallas & Dogar's code
become reach problems that cluttertamp validates, with the target where the paper's
green cylinder stands relative to the shelf's back wall; bad input exits with 2."""

import math
import os
import pathlib
import re
import subprocess
import sys

SOURCE = pathlib.Path(os.environ.get("CLUTTERTAMP_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
SCRIPT = SOURCE / "scripts/convert-hitl-scenes.py"
CLI = os.environ.get("CLUTTERTAMP_CLI", str(SOURCE / "build/bin/cluttertamp"))

# Two cylinders of our own placing, in the paper's frame: the back wall's face at
# x = 1.787, the shelf's middle at y = -0.047.
SCENE = """<?xml version="1.0" ?>
<mujoco model="ours">
  <worldbody>
    <body name="object_1" pos="1.70 0.10 0.479" quat="0.7071068 0 0 0.7071068">
      <geom name="object_1" rgba="0 1 0. 1" size="0.03 0.05" type="cylinder"/>
    </body>
    <body name="object_2" pos="1.50 -0.047 0.479" quat="1 0 0 0">
      <geom name="object_2" rgba="1 0 0. 1" size="0.03 0.05" type="cylinder"/>
    </body>
    <body name="shelf" pos="1.49 0.25 0.5582"><geom type="box" size="0.005 0.297 0.13"/></body>
  </worldbody>
</mujoco>
"""


def run(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args), "--cluttertamp", CLI],
                          capture_output=True, text=True, timeout=300)


def test_scenes_become_problems_with_the_target_as_far_from_the_back_wall(tmp_path):
    models = tmp_path / "models"
    models.mkdir()
    for n in range(1, 11):
        (models / f"s{n}.xml").write_text(SCENE)
    out = tmp_path / "out"
    r = run(models, out)
    assert r.returncode == 0, r.stderr
    objects = re.findall(r"\{id: (\w+), cylinder: .*xyz: \[([-\d.]+), ([-\d.]+), [-\d.]+\], rpy: \[0, 0, ([-\d.]+)\]\}(.*)\}",
                         (out / "p01-scene.yaml").read_text())
    assert [o[0] for o in objects] == ["target", "o1"]
    (_, x, y, yaw, rest), obstacle = objects
    assert "target: true" in rest
    assert abs(float(x) - (1.19 - 0.087)) < 1e-6  # 8.7 cm before the back wall, as in the source
    assert abs(float(y) - 0.147) < 1e-6
    assert abs(float(yaw) - 1.5707963) < 1e-6
    assert abs(float(obstacle[2])) < 1e-9  # the shelf's middle
    for n in (1, 10):
        problem = out / f"p{n:02d}.yaml"
        assert (out / f"p{n:02d}-guidance.yaml").is_file()
        v = subprocess.run([CLI, "validate", str(problem), "-q"], capture_output=True, text=True, timeout=120)
        assert v.returncode == 0, v.stdout + v.stderr


def test_a_missing_scene_or_one_without_a_target_exits_with_2(tmp_path):
    r = run(tmp_path / "nowhere", tmp_path / "out")
    assert r.returncode == 2
    assert "s1.xml" in r.stderr
    models = tmp_path / "models"
    models.mkdir()
    for n in range(1, 11):
        (models / f"s{n}.xml").write_text(SCENE.replace('rgba="0 1 0. 1"', 'rgba="1 0 0. 1"'))
    r = run(models, tmp_path / "out")
    assert r.returncode == 2
    assert "s1.xml" in r.stderr and "target" in r.stderr


def joint(name, parent, child, xyz, rpy="0 0 0", axis="0 0 1", limit=6.2831853):
    return (f'<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="{axis}"/>'
            f'<limit lower="-{limit}" upper="{limit}" velocity="3" effort="100"/></joint>')


def link(name, radius=0.0, length=0.0, xyz="0 0 0"):
    if not radius:
        return f'<link name="{name}"/>'
    return (f'<link name="{name}"><collision><origin xyz="{xyz}"/>'
            f'<geometry><cylinder radius="{radius}" length="{length}"/></geometry></collision></link>')


# A UR5 of our own in ROS-Industrial's joint frames (the published kinematics: axes along
# y but for the first and fifth), cylinders for links, a box of a hand at tool0 with one
# finger joint and its centre point 0.13 m past the flange.
UR5 = ("""<?xml version="1.0"?>\n<robot name="ur5_ours">"""
       + link("base_link", 0.075, 0.08, "0 0 0.04") + link("shoulder_link", 0.06, 0.15)
       + link("upper_arm_link", 0.05, 0.4, "0 0 0.2125") + link("forearm_link", 0.04, 0.37, "0 0 0.196")
       + link("wrist_1_link", 0.04, 0.1) + link("wrist_2_link", 0.04, 0.1) + link("wrist_3_link", 0.04, 0.05)
       + link("tool0") + link("hand", 0.04, 0.1, "0 0 0.05") + link("finger") + link("tcp")
       + joint("shoulder_pan_joint", "base_link", "shoulder_link", "0 0 0.089159")
       + joint("shoulder_lift_joint", "shoulder_link", "upper_arm_link", "0 0.13585 0", "0 1.5707963 0", "0 1 0")
       + joint("elbow_joint", "upper_arm_link", "forearm_link", "0 -0.1197 0.425", axis="0 1 0", limit=3.1415926)
       + joint("wrist_1_joint", "forearm_link", "wrist_1_link", "0 0 0.39225", "0 1.5707963 0", "0 1 0")
       + joint("wrist_2_joint", "wrist_1_link", "wrist_2_link", "0 0.093 0")
       + joint("wrist_3_joint", "wrist_2_link", "wrist_3_link", "0 0 0.09465", axis="0 1 0")
       + '<joint name="flange" type="fixed"><parent link="wrist_3_link"/><child link="tool0"/>'
         '<origin xyz="0 0.0823 0" rpy="-1.5707963 0 0"/></joint>'
       + '<joint name="mount" type="fixed"><parent link="tool0"/><child link="hand"/></joint>'
       + '<joint name="finger_joint" type="prismatic"><parent link="hand"/><child link="finger"/><axis xyz="0 1 0"/>'
         '<limit lower="0" upper="0.0475" velocity="0.1" effort="10"/></joint>'
       + '<joint name="tcp_joint" type="fixed"><parent link="hand"/><child link="tcp"/><origin xyz="0 0 0.13"/></joint>'
       + "</robot>\n")


def test_with_the_paper_ur5_the_problems_hold_its_posture_and_start_where_its_hand_did(tmp_path):
    (tmp_path / "ur5.urdf").write_text(UR5)
    (tmp_path / "ur5.yaml").write_text(
        "version: 1\nurdf: ur5.urdf\nbase_link: base_link\ntip_link: tcp\nik: numeric\n"
        "gripper: {finger_thickness: 0.012, base_half_length: 0.045, stroke: 0.095}\n")
    models = tmp_path / "models"
    models.mkdir()
    for n in range(1, 11):
        (models / f"s{n}.xml").write_text(SCENE)
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, str(SCRIPT), str(models), str(out), "--ur5", str(tmp_path / "ur5.yaml"),
                        "--cluttertamp", CLI], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    text = (out / "p01.yaml").read_text()
    assert f"description: {(tmp_path / 'ur5.yaml').as_posix()}" in text
    assert "base_offset: [0.28, 0], posture: [3.0718, -3.0543, -0.0873, -3.1416, -1.5708, 1.5708, 0.0475]" in text
    # The paper's reach point 0.519 m before its back wall's face, ours 0.03 m past it.
    x, y, yaw = (float(v) for v in re.search(r"start: \[([-\d.]+), ([-\d.]+), ([-\d.]+)\]", text).groups())
    assert abs(x - (1.19 - 0.5191 + 0.03 * math.cos(-0.0698))) < 1e-3
    assert abs(y - (-0.1785 + 0.047 + 0.03 * math.sin(-0.0698))) < 1e-3
    assert yaw == -0.0698
    v = subprocess.run([CLI, "validate", str(out / "p01.yaml"), "-q"], capture_output=True, text=True, timeout=120)
    assert v.returncode == 0, v.stdout + v.stderr
    r = subprocess.run([sys.executable, str(SCRIPT), str(models), str(out), "--ur5", str(tmp_path / "none.yaml"),
                        "--cluttertamp", CLI], capture_output=True, text=True, timeout=300)
    assert r.returncode == 2 and "none.yaml" in r.stderr
