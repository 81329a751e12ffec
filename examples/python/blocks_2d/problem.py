"""The blocks-2d problem with its streams in Python, as PDDLStream writes them.

    PYTHONPATH=build/python python3 examples/python/blocks_2d/problem.py [--incremental]

Block b0 must go into the goal region, where b1 stands and leaves no room: b1 has to be
moved out of the way first. Blocks are intervals along x (centre, width); a region is
an interval (low, high).
"""

import os
import random
import sys

from cluttertamp.streams import PDDLProblem, from_gen_fn, from_test, solve

HERE = os.path.dirname(os.path.abspath(__file__))
WIDTHS = {"b0": 0.4, "b1": 0.4}
TABLE = (-3.0, 3.0)
GOAL = (1.0, 1.5)


def blocks_problem(seed=0):
    rng = random.Random(seed)

    def sample_pose(block, region):
        low, high = region[0] + WIDTHS[block] / 2, region[1] - WIDTHS[block] / 2
        while True:
            yield (round(rng.uniform(low, high), 6),)

    def cfree(block, pose, other, other_pose):
        return abs(pose - other_pose) >= (WIDTHS[block] + WIDTHS[other]) / 2

    init = [("HandEmpty",), ("Region", TABLE), ("Region", GOAL)]
    for block, x in (("b0", -2.0), ("b1", 1.25)):
        init += [("Block", block), ("Pose", block, x), ("AtPose", block, x)]
    init += [("Contained", "b1", 1.25, GOAL)]
    stream_map = {"sample-pose": from_gen_fn(sample_pose), "test-cfree": from_test(cfree)}
    return PDDLProblem(os.path.join(HERE, "domain.pddl"), {}, os.path.join(HERE, "streams.pddl"), stream_map,
                       init, ("In", "b0", GOAL))


def check(plan):
    """Replays the plan: b0 ends inside the goal and no two blocks overlap."""
    at, held = {"b0": -2.0, "b1": 1.25}, None
    for action, (block, x) in plan:
        if action == "pick":
            assert held is None and at[block] == x
            held = block
            del at[block]
        else:
            assert held == block
            for other, y in at.items():
                assert abs(x - y) >= (WIDTHS[block] + WIDTHS[other]) / 2, (block, x, other, y)
            at[block], held = x, None
    assert held is None and GOAL[0] <= at["b0"] - WIDTHS["b0"] / 2 and at["b0"] + WIDTHS["b0"] / 2 <= GOAL[1]
    return at


if __name__ == "__main__":
    algorithm = "incremental" if "--incremental" in sys.argv else "adaptive"
    solution = solve(blocks_problem(), algorithm=algorithm, time_limit=10)
    print(solution, solution.statistics["stream_calls"], "stream calls")
    if not solution.solved:
        sys.exit(1)
    for action, arguments in solution.plan:
        print(f"  ({action} {' '.join(map(str, arguments))})")
    print("final poses:", check(solution.plan))
