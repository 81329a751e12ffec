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

Usage: scripts/convert-hitl-scenes.py MODELS_DIR OUT_DIR [--cluttertamp BIN]
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


def problem_text(name, scene_file):
    text = TEMPLATE_PROBLEM.read_text()
    text = re.sub(r"(?m)^name: .*$", f"name: {name}", text)
    text = re.sub(r"(?m)^scene: .*$", f"scene: {scene_file}", text)
    robot = (REPO / "domains/robots/ur10_ag95.yaml").as_posix()
    return re.sub(r"description: [^}]*}", f"description: {robot}}}", text)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("models", type=pathlib.Path, help="the paper code's models/ directory (s1.xml ... s10.xml)")
    parser.add_argument("out", type=pathlib.Path, help="where to write pNN-scene.yaml, pNN.yaml, pNN-guidance.yaml")
    parser.add_argument("--cluttertamp", default=str(REPO / "build/bin/cluttertamp"), help="the program that writes the guidance")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for n in range(1, 11):
        source = args.models / f"s{n}.xml"
        if not source.is_file():
            fail(f"{source}: no such scene (expected s1.xml ... s10.xml in {args.models})")
        stem = f"p{n:02d}"
        name = f"hitl-s{n}"
        (args.out / f"{stem}-scene.yaml").write_text(scene_text(name, read_objects(source)))
        problem = args.out / f"{stem}.yaml"
        problem.write_text(problem_text(name, f"{stem}-scene.yaml"))
        guide = [args.cluttertamp, "guide", str(problem), "--auto", "--output", str(args.out / f"{stem}-guidance.yaml"), "--quiet"]
        if subprocess.run(guide).returncode != 0:
            fail(f"{problem}: cluttertamp guide --auto failed")
    print(f"wrote {args.out}: ten problems from {args.models}; run cluttertamp bench push --push-scenes {args.out}")


if __name__ == "__main__":
    main()
