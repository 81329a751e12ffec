"""How many objects the retrieval planner moves (|O_r|, the target included) as shelves
fill up: generated Table I shelves (Tian et al., Section VI-B), planned from Python,
plotted with matplotlib.

    PYTHONPATH=build/python python3 examples/python/removals_vs_objects.py \
        [--objects 6 8 ... 20] [--scenes 5] [--output removals.svg]

Each point is one scene (seed 0, 1, ... per size); the line joins the medians of the
solved ones. Unsolved scenes are drawn as crosses at the top. Prints a table as it goes.
"""

import argparse
import os
import statistics
import tempfile

import matplotlib

matplotlib.use("Agg")  # files only: no display needed
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402,F401

import cluttertamp  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", type=int, nargs="+", default=[6, 8, 10, 12, 14, 16, 18, 20])
    parser.add_argument("--scenes", type=int, default=5, help="scenes (seeds 0..N-1) per size")
    parser.add_argument("--planner", default="retrieval_graph")
    parser.add_argument("--time-limit", type=float, default=60.0, help="s per run (the outer limit)")
    parser.add_argument("--output", default="removals.svg", help="the plot (.svg, .png or .pdf)")
    args = parser.parse_args()

    source = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    robot = os.path.join(source, "domains", "robots", "ur10_ag95.yaml")
    runs = {}  # objects -> [(seed, solved, |O_r|)]
    print(f"{'objects':>7s} {'seed':>4s} {'solved':>6s} {'|O_r|':>5s} {'time (s)':>8s}")
    with tempfile.TemporaryDirectory() as tmp:
        for n in args.objects:
            for seed in range(args.scenes):
                scene = os.path.join(tmp, f"shelf{n}-{seed}.yaml")
                problem = cluttertamp.generate_shelf(scene, objects=n, seed=seed, problem_file=scene + ".problem.yaml",
                                                     robot=robot, planner=args.planner, time_limit=args.time_limit)
                result = cluttertamp.plan(problem, seed=0)
                removed = len(result.moved_objects)
                runs.setdefault(n, []).append((seed, result.solved, removed))
                print(f"{n:7d} {seed:4d} {str(result.solved):>6s} {removed:5d} {result.time['total']:8.2f}", flush=True)

    figure, axes = plt.subplots(figsize=(6, 4))
    solved = [(n, r) for n, rs in runs.items() for _, ok, r in rs if ok]
    unsolved = [n for n, rs in runs.items() for _, ok, _ in rs if not ok]
    counts = {}  # scenes with the same size and |O_r| drawn as one point, its area their number
    for point in solved:
        counts[point] = counts.get(point, 0) + 1
    axes.scatter([n for n, _ in counts], [r for _, r in counts], s=[40 * c for c in counts.values()], alpha=0.6,
                 label="solved scenes (area: how many)")
    medians = [(n, statistics.median(r for _, ok, r in rs if ok)) for n, rs in sorted(runs.items())
               if any(ok for _, ok, _ in rs)]
    axes.plot([n for n, _ in medians], [m for _, m in medians], "-o", color="black", label="median")
    if unsolved:
        top = max([r for _, r in solved] + [1]) + 1
        axes.scatter(unsolved, [top] * len(unsolved), marker="x", color="red", label="not solved")
    axes.set_xlabel("objects on the shelf")
    axes.set_ylabel("|O_r|: objects moved, target included")
    axes.set_title(f"{args.planner}, {args.scenes} scene(s) per size")
    axes.yaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))
    axes.set_xticks(sorted(runs))
    axes.grid(True, alpha=0.3)
    axes.legend()
    figure.tight_layout()
    figure.savefig(args.output)
    print("wrote", args.output)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
