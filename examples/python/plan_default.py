"""Plans the bundled default problem from Python and prints what moved and how far the
arm travelled in each step; writes result.json and the replay page beside it.

    PYTHONPATH=build/python python3 examples/python/plan_default.py [OUTPUT_DIR]
"""

import os
import sys

import numpy as np

import cluttertamp

source = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
output = sys.argv[1] if len(sys.argv) > 1 else "cluttertamp-out-python"

problem = cluttertamp.load_problem(os.path.join(source, "problems", "default.yaml"))
result = cluttertamp.plan(problem, seed=0)
print(result)
if not result.solved:
    for failure in result.failures:
        print(f"  {failure.stage}: {failure.reason} (blocked by {', '.join(failure.blocking_objects) or 'nothing'})")
    sys.exit(1)
for step in result.steps:
    q = step.trajectory.positions
    travel = np.abs(np.diff(q, axis=0)).sum()  # summed joint travel, rad (and m of the fingers)
    print(f"  {step.index}. {step.action:9s} {' '.join(step.objects):10s} {len(q):3d} waypoints, "
          f"{step.trajectory.times[-1]:5.2f} s, joint travel {travel:5.2f}")
print(f"collision checks {result.counters['collision_checks']}, planning {result.time['total']:.3f} s")
print("wrote", result.write(output))
result.write_page(os.path.join(output, "plan.html"))
print("wrote", os.path.join(output, "plan.html"))
