"""scripts/convert-hitl-scenes.py: MuJoCo scenes in the layout of Papallas & Dogar's code
become reach problems that cluttertamp validates, with the target where the paper's
green cylinder stands relative to the shelf's back wall; bad input exits with 2."""

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
