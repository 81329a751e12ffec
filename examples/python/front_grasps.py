"""A grasp sampler written in Python, used by the retrieval planner on the default problem.

    PYTHONPATH=build/python python3 examples/python/front_grasps.py [--spread DEG] [--directions N]

FrontGrasps proposes side grasps facing the robot: a fan of approach directions at the
object's mid-height, straight on first. cluttertamp checks each proposal (IK, the
approach, the grasp, the lift) and tells the planner which objects block the rejected
ones, exactly as for its own C++ samplers. The problem file names the sampler like a
plugin (`grasp_sampler: {plugin: front_grasps, parameters: {...}}`); its parameters are
read, range-checked and located as a C++ plugin's are.
"""

import argparse
import math
import os
import tempfile

import numpy as np

import cluttertamp


class FrontGrasps(cluttertamp.GraspSampler):
    """Side grasps facing the robot, a fan of directions at mid-height."""

    max_usable = 3  # stop once three usable grasps are found

    def configure(self, parameters):
        self.spread = parameters.number("spread", 45.0, "degrees either side of facing the robot", low=0, high=90)
        self.directions = parameters.integer("directions", 7, "approach directions", low=1, high=31)

    def sample(self, query):
        centre = query.world_T_object[:3, 3]
        base = query.world_T_robot_base[:3, 3]
        facing = math.atan2(centre[1] - base[1], centre[0] - base[0])
        offsets = np.linspace(-self.spread, self.spread, self.directions) if self.directions > 1 else [0.0]
        for offset in sorted(offsets, key=abs):
            yaw = facing + math.radians(offset)
            approach = np.array([math.cos(yaw), math.sin(yaw), 0.0])  # the tool's z axis
            down = np.array([0.0, 0.0, -1.0])                           # the tool's x axis
            world_T_gripper = np.eye(4)
            world_T_gripper[:3, 0] = down
            world_T_gripper[:3, 1] = np.cross(approach, down)
            world_T_gripper[:3, 2] = approach
            world_T_gripper[:3, 3] = centre
            yield query.grasp(world_T_gripper, approach=0.10, lift=0.03)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spread", type=float, default=45.0)
    parser.add_argument("--directions", type=int, default=7)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()

    cluttertamp.register_sampler("front_grasps", FrontGrasps)
    source = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    with tempfile.TemporaryDirectory() as tmp:
        problem_file = os.path.join(tmp, "front_grasps.yaml")
        with open(problem_file, "w", encoding="utf-8") as out:
            out.write("version: 1\n"
                      "name: shelf12-front-grasps\n"
                      f"scene: {source}/problems/scenes/shelf12.yaml\n"
                      f"robot: {{description: {source}/domains/robots/ur10_ag95.yaml}}\n"
                      "task: {retrieve: target}\n"
                      "planner: {plugin: retrieval_graph, time_limit: 60, seed: 0}\n"
                      "plugins:\n"
                      f"  grasp_sampler: {{plugin: front_grasps, parameters: {{spread: {args.spread}, "
                      f"directions: {args.directions}}}}}\n"
                      "  motion_sampler: motion_ompl\n"
                      "  placement_sampler: placement_region\n")
        mine = cluttertamp.plan(problem_file, seed=args.seed)
    shipped = cluttertamp.plan(os.path.join(source, "problems", "default.yaml"), seed=args.seed)
    for name, result in (("front_grasps (Python)", mine), ("grasp_side (C++)", shipped)):
        print(f"{name:22s} {'solved' if result.solved else 'not solved'}: moved {result.moved_objects}, "
              f"{result.counters['samples']} samples, {result.time['total']:.3f} s")
        for failure in result.failures[:3]:
            print(f"    {failure.stage}: {failure.reason.splitlines()[0]}")
    return 0 if mine.solved else 1


if __name__ == "__main__":
    raise SystemExit(main())
