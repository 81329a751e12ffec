#!/usr/bin/env python3
"""Converts the ten pushing scenes of Papallas & Dogar's public code into reach problems.

The paper's code (github.com/rpapallas/hitl_clutter) keeps its scenes as MuJoCo models,
models/s1.xml ... s10.xml: ten cylinders (radius 0.03 m, 0.10 m tall, 10 kg, friction
0.4; the green one is the target) in a shelf whose walls its include/shelf_1.xml places.
This script reads the objects' positions and yaws from such a checkout (fetch it
yourself; nothing of it is bundled) and writes, into OUT_DIR, for N = 01 ... 10:

  pNN-scene.yaml     our cabinet of problems/push/paper10 with the scene's objects, its
                     back wall's face and its middle where the paper's are
  pNN.yaml           problems/push/paper10/p01.yaml's robot, physics and planner
  pNN-guidance.yaml  the automatic guidance (cluttertamp guide --auto)

so that `cluttertamp bench push --push-scenes OUT_DIR` runs the paper's own scenes.

With --ur5 FILE the problems push with the paper's own arm instead of our UR10: FILE
describes a UR5 in the joint frames of ROS-Industrial's ur_description (the maker's
ur5_robot.urdf, a gripper whose tool centre point is 0.13 m past tool0), held in the
posture the paper's robot model (models/robot/include/full_planar_robot.xml) sets, on
its base 0.28 m ahead of the mobile base's centre, the hand starting where the paper's
reach point stands, 7 cm inside the shelf.

Usage: scripts/convert-hitl-scenes.py MODELS_DIR OUT_DIR [--ur5 FILE] [--cluttertamp BIN]
Exit codes: 0 written, 2 bad input (a missing or unreadable scene, no target).
"""

import argparse
import math
import pathlib
import re
import subprocess
import sys
import xml.etree.ElementTree as ET

REPO = pathlib.Path(__file__).resolve().parent.parent
TEMPLATE_SCENE = REPO / "problems/push/paper10/p01-scene.yaml"
TEMPLATE_PROBLEM = REPO / "problems/push/paper10/p01.yaml"

# The paper's shelf (include/shelf_1.xml): the body at (1.49, 0.25) turned -90 degrees
# about z; its back wall's inner face at x = 1.792 - 0.005, its side walls' inner faces
# at y = 0.25 - 0.005 and 0.25 - 0.594 + 0.005.
PAPER_BACK_FACE_X = 1.787
PAPER_MIDDLE_Y = (0.245 + -0.339) / 2
# Ours (problems/push/paper10): the back wall's inner face, the shelf's middle.
OUR_BACK_FACE_X = 1.19
OUR_MIDDLE_Y = 0.0
OUR_CENTRE_Z = 0.45  # a 10 cm cylinder standing on our floor board (top 0.40)


def fail(message):
    print("convert-hitl-scenes: " + message, file=sys.stderr)
    sys.exit(2)


def yaw_of(quat):
    w, x, y, z = quat
    return math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


def read_objects(path):
    """The scene's cylinders as (is_target, x, y, yaw) in the paper's world frame."""
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as e:
        fail(f"{path}: {e}")
    objects = []
    for body in root.iter("body"):
        name = body.get("name", "")
        geom = body.find("geom")
        if not re.fullmatch(r"object_\d+", name) or geom is None or geom.get("type") != "cylinder":
            continue
        try:
            x, y, _ = (float(v) for v in body.get("pos").split())
            quat = [float(v) for v in body.get("quat", "1 0 0 0").split()]
            rgba = [float(v) for v in geom.get("rgba").split()]
        except (AttributeError, ValueError) as e:
            fail(f"{path}: body '{name}': {e}")
        is_target = rgba[1] > 0.5 and rgba[0] < 0.5  # the paper draws its target green
        objects.append((is_target, x, y, yaw_of(quat)))
    if sum(1 for o in objects if o[0]) != 1:
        fail(f"{path}: needs exactly one green (target) cylinder among {len(objects)}")
    return objects


def scene_text(name, objects):
    header = TEMPLATE_SCENE.read_text().split("\nobjects:")[0]
    header = re.sub(r"(?m)^name: .*$", f"name: {name}", header)
    lines = []
    obstacle = 0
    for is_target, x, y, yaw in sorted(objects, key=lambda o: not o[0]):
        ours_x = OUR_BACK_FACE_X - (PAPER_BACK_FACE_X - x)
        ours_y = OUR_MIDDLE_Y + (y - PAPER_MIDDLE_Y)
        if is_target:
            ident, extra = "target", ", target: true"
        else:
            obstacle += 1
            ident, extra = f"o{obstacle}", ""
        lines.append(f"  - {{id: {ident}, cylinder: {{radius: 0.03, height: 0.1}}, "
                     f"pose: {{xyz: [{ours_x:.6f}, {ours_y:.6f}, {OUR_CENTRE_Z}], rpy: [0, 0, {yaw:.6f}]}}, "
                     f"mass: 10, friction: 0.4{extra}}}")
    return (f"# Converted by scripts/convert-hitl-scenes.py from Papallas & Dogar's scene {name}.\n"
            + header + "\nobjects:\n" + "\n".join(lines) + "\n")


# The paper's UR5 (full_planar_robot.xml): its bodies' turns are the joint angles in
# ROS-Industrial's frames (shoulder_link's quaternion, a turn of -85 degrees about y, is
# the joint origin's +90 and a shoulder lift of -175), the fingers open; the arm's
# base_link 0.28 m ahead of the mobile base's centre. Its reach point, 0.1 m past the
# gripper's base, stands at (1.2679, -0.1785) heading -0.0698 rad in the paper's frame.
UR5_POSTURE = [3.0718, -3.0543, -0.0873, -3.1416, -1.5708, 1.5708, 0.0475]
UR5_BASE_OFFSET = [0.28, 0]
PAPER_REACH_POINT = (1.2679, -0.1785, -0.0698)
OUR_TCP_BEYOND_REACH_POINT = 0.03  # m: our hand's centre point is 0.13 m past the flange


def ur5_start():
    """The hand's start [x, y, yaw] in our frame: where the paper's reach point is."""
    x, y, yaw = PAPER_REACH_POINT
    ours_x = OUR_BACK_FACE_X - (PAPER_BACK_FACE_X - x) + OUR_TCP_BEYOND_REACH_POINT * math.cos(yaw)
    ours_y = OUR_MIDDLE_Y + (y - PAPER_MIDDLE_Y) + OUR_TCP_BEYOND_REACH_POINT * math.sin(yaw)
    return [round(ours_x, 3), round(ours_y, 3), yaw]


def problem_text(name, scene_file, ur5=None):
    text = TEMPLATE_PROBLEM.read_text()
    text = re.sub(r"(?m)^name: .*$", f"name: {name}", text)
    text = re.sub(r"(?m)^scene: .*$", f"scene: {scene_file}", text)
    robot = ur5.resolve().as_posix() if ur5 else (REPO / "domains/robots/ur10_ag95.yaml").as_posix()
    text = re.sub(r"description: [^}]*}", f"description: {robot}}}", text)
    if ur5:
        def numbers(values):
            return "[" + ", ".join(f"{v:g}" for v in values) + "]"
        arm = (f"base_offset: {numbers(UR5_BASE_OFFSET)}, posture: {numbers(UR5_POSTURE)},\n"
               f"          start: {numbers(ur5_start())},")
        text, replaced = re.subn(r"base_offset: \[[^]]*\],", arm, text)
        if replaced != 1:
            fail(f"{TEMPLATE_PROBLEM}: no base_offset in its physics block to replace")
        text = text.replace("\nversion: 1\n", "\n# Pushed by the paper's UR5 in its posture (scripts/convert-hitl-scenes.py --ur5).\nversion: 1\n", 1)
    return text


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("models", type=pathlib.Path, help="the paper code's models/ directory (s1.xml ... s10.xml)")
    parser.add_argument("out", type=pathlib.Path, help="where to write pNN-scene.yaml, pNN.yaml, pNN-guidance.yaml")
    parser.add_argument("--cluttertamp", default=str(REPO / "build/bin/cluttertamp"), help="the program that writes the guidance")
    parser.add_argument("--ur5", type=pathlib.Path, help="a UR5 robot description in ROS-Industrial's joint frames: push with it as the paper did")
    args = parser.parse_args()
    if args.ur5 and not args.ur5.is_file():
        fail(f"{args.ur5}: no such robot description")
    args.out.mkdir(parents=True, exist_ok=True)
    for n in range(1, 11):
        source = args.models / f"s{n}.xml"
        if not source.is_file():
            fail(f"{source}: no such scene (expected s1.xml ... s10.xml in {args.models})")
        stem = f"p{n:02d}"
        name = f"hitl-s{n}"
        (args.out / f"{stem}-scene.yaml").write_text(scene_text(name, read_objects(source)))
        problem = args.out / f"{stem}.yaml"
        problem.write_text(problem_text(name, f"{stem}-scene.yaml", args.ur5))
        guide = [args.cluttertamp, "guide", str(problem), "--auto", "--output", str(args.out / f"{stem}-guidance.yaml"), "--quiet"]
        if subprocess.run(guide).returncode != 0:
            fail(f"{problem}: cluttertamp guide --auto failed")
    print(f"wrote {args.out}: ten problems from {args.models}; run cluttertamp bench push --push-scenes {args.out}")


if __name__ == "__main__":
    main()
