"""cluttertamp from Python: load problems, plan, and read the results.

    import cluttertamp
    problem = cluttertamp.load_problem("problems/default.yaml")
    result = cluttertamp.plan(problem, seed=0, time_limit=30)
    if result.solved:
        for step in result.steps:
            print(step.action, step.objects, step.trajectory.positions.shape)

A Result holds what `cluttertamp plan` writes to result.json (docs/file-formats.md,
"result.json"), trajectories as numpy arrays. Bad input raises InputError, whose
`errors` list every (file, line, column, message) found.
"""

import json
import os

import numpy as np

from ._cluttertamp import InputError, LoadedProblem, Robot  # noqa: F401  (re-exported)
from . import _cluttertamp
from . import streams  # noqa: F401  (cluttertamp.streams)
from .samplers import (GraspSampler, PlacementSampler, MotionSampler, PushSampler,  # noqa: F401
                       register_sampler, withdraw_sampler, Grasp, World)

__all__ = [
    "InputError", "Problem", "Robot", "Result", "Step", "Trajectory", "Failure",
    "load_problem", "load_robot", "validate", "plan", "generate_shelf", "solve_pddl", "validate_pddl_plan", "search_names",
    "GraspSampler", "PlacementSampler", "MotionSampler", "PushSampler", "register_sampler", "withdraw_sampler",
    "Grasp", "World",
]

Problem = LoadedProblem


def load_problem(file, package_paths=()):
    """The problem file `file` with its scene and robot, validated.

    package_paths: directories searched for a URDF's package:// meshes, before the robot
    description's `package_paths` and ROS_PACKAGE_PATH. Raises InputError listing every
    error with its file, line and column."""
    return _cluttertamp.load_problem(os.fspath(file), [os.fspath(p) for p in package_paths])


def load_robot(file, package_paths=()):
    """A robot description file (URDF plus semantics) with forward and inverse kinematics:
    `tool_pose(q)` the tool's 4 x 4 pose in the frame of the arm's base link (the IK
    chain's base), `link_poses(q)` every link's in the frame of the URDF's root link (the
    same for a fixed arm whose base link is the root), `ik(pose, seed=None, random_seed=0)`
    the solutions for a tool pose in the base link's frame."""
    return _cluttertamp.load_robot(os.fspath(file), [os.fspath(p) for p in package_paths])


def validate(file, package_paths=()):
    """Checks a problem or scene file as `cluttertamp validate --no-plugins` does: returns the
    loaded Problem (for a problem file) or the scene's name; raises InputError."""
    file = os.fspath(file)
    if _cluttertamp.is_problem_file(file):
        problem = load_problem(file, package_paths)
        problem.check_start()
        return problem
    return _cluttertamp.check_scene(file)


class Trajectory:
    """A robot motion: `joint_names`, `times` (s, shape (n,)), `positions` (rad or m, shape
    (n, joints)); for a push also `objects`, id -> planar poses (x, y, yaw), shape (n, 3)."""

    def __init__(self, data):
        self.joint_names = list(data.get("joint_names", []))
        self.times = np.asarray(data.get("times", []), dtype=float)
        self.positions = np.asarray(data.get("positions", []), dtype=float).reshape(len(self.times),
                                                                                      len(self.joint_names))
        self.objects = {k: np.asarray(v, dtype=float) for k, v in data.get("objects", {}).items()}

    def __repr__(self):
        return f"Trajectory({len(self.times)} points, {len(self.joint_names)} joints)"


class Step:
    """One plan step: `index`, `action`, `arguments`, `objects`, `values` (name -> list of
    numbers) and `trajectory` (a Trajectory or None)."""

    def __init__(self, data):
        self.index = data.get("index")
        self.action = data.get("action")
        self.arguments = list(data.get("arguments", []))
        self.objects = list(data.get("objects", []))
        self.values = {k: list(v) for k, v in data.get("values", {}).items()}
        trajectory = data.get("trajectory")
        self.trajectory = Trajectory(trajectory) if trajectory else None

    def __repr__(self):
        return f"Step({self.index}, {self.action!r}, objects={self.objects})"


class Failure:
    """Why one attempt failed: `stage` (grasp, motion, ...), `reason` and the
    `blocking_objects` in the way; `data` holds every field result.json gives it."""

    def __init__(self, data):
        self.data = data
        self.stage = data.get("stage")
        self.reason = data.get("reason")
        self.blocking_objects = list(data.get("blocking_objects", []))

    def __repr__(self):
        return f"Failure({self.stage!r}, {self.reason!r})"


class Result:
    """A planning run: every field of result.json as an attribute (`solved`, `reason`,
    `exit_code`, `moved_objects`, `counters`, `time`, `phases`, ...), with `steps` and
    `failures` as objects. `json` is the dict of result.json, `text` its exact text;
    `write(directory)` writes result.json (and drawings.json) as `cluttertamp plan` does.
    `problem` is the problem file's path, as in result.json; `planned_problem` the
    Problem it was planned from."""

    def __init__(self, text, drawings_text="", planned_problem=None, run=None):
        self.text = text
        self._drawings_text = drawings_text
        self._run = run
        self.planned_problem = planned_problem
        self.json = json.loads(text)
        for key, value in self.json.items():
            if key not in ("plan", "failures"):
                setattr(self, key, value)
        self.steps = [Step(s) for s in self.json.get("plan", [])]
        self.failures = [Failure(f) for f in self.json.get("failures", [])]

    @property
    def drawings_text(self):
        """drawings.json's text (the planner's roadmaps and graphs), made when first asked for."""
        if self._drawings_text is None:
            self._drawings_text = self._run.drawings_json() if self._run is not None else ""
        return self._drawings_text

    def write(self, directory):
        """Writes result.json (and drawings.json when the planner drew anything) into
        `directory`, creating it; returns the path of result.json."""
        os.makedirs(directory, exist_ok=True)
        path = os.path.join(directory, "result.json")
        _write_whole(path, self.text)
        drawings = os.path.join(directory, "drawings.json")
        if json.loads(self.drawings_text or "{}").get("drawings"):
            _write_whole(drawings, self.drawings_text)
        elif os.path.exists(drawings):
            os.remove(drawings)
        return path

    def write_page(self, file):
        """The replay page of this run (as `cluttertamp plan --html`): one HTML file that
        opens from disk."""
        if self.planned_problem is None:
            raise ValueError("this Result was not planned here: load its problem and plan it to draw it")
        _cluttertamp.write_page(self.planned_problem, os.fspath(file), self.text, self.drawings_text, "result")

    def __repr__(self):
        state = "solved" if self.solved else f"not solved: {self.reason}"
        return f"Result({state}, {len(self.steps)} steps, moved {self.moved_objects})"


def _write_whole(path, text):
    # As the command line writes: a complete copy renamed over the old file.
    partial = path + ".partial"
    with open(partial, "w", encoding="utf-8") as out:
        out.write(text)
    os.replace(partial, path)


def plan(problem, seed=None, time_limit=None, planner=None, plugin_paths=(), package_paths=()):
    """Plans a problem (a Problem or a problem file) as `cluttertamp plan` does and returns
    its Result. seed, time_limit (s) and planner override the problem file's; plugin_paths
    are searched for plugins first. Planning failure is a Result with a reason; bad input
    (a missing plugin, a robot that starts in collision) raises InputError."""
    if not isinstance(problem, LoadedProblem):
        problem = load_problem(problem, package_paths)
    run = _cluttertamp.plan(problem, seed, time_limit, planner, [os.fspath(p) for p in plugin_paths])
    return Result(run.result_json(), None, problem, run)


def generate_shelf(scene_file, objects=12, seed=0, min_gap=0.0, problem_file=None, robot=None,
                   planner="retrieval_graph", time_limit=60.0):
    """Writes a generated shelf scene (Tian et al., Section VI-B: `objects` cylinders placed at
    random in a cabinet sized for their number, the target nearest the middle of the back
    wall; min_gap m between neighbours, 0 the paper's): the scene of `cluttertamp generate
    --seed SEED`, same seed, same file. Unlike generate it keeps scenes whose target comes
    straight out (|O_r| = 1) instead of going on to the next seed.

    With `problem_file`, also writes a problem that retrieves the target with `planner`,
    the shipped samplers and the robot `robot` (a robot description file, e.g.
    domains/robots/ur10_ag95.yaml), and returns that Problem; else returns the target's
    id. Raises ValueError when the objects do not fit or a length is not finite."""
    scene_file = os.fspath(scene_file)
    target = _cluttertamp.generate_shelf(scene_file, objects, seed, min_gap)
    if problem_file is None:
        return target
    problem_file = os.fspath(problem_file)
    if robot is None:
        raise ValueError("a problem file needs a robot description: pass robot=")
    robot = os.path.abspath(os.fspath(robot))
    here = os.path.dirname(os.path.abspath(problem_file))
    _write_whole(problem_file,
                 f"# Generated by cluttertamp.generate_shelf (seed {seed}). Format: docs/file-formats.md.\n"
                 "version: 1\n"
                 f"scene: {os.path.relpath(os.path.abspath(scene_file), here)}\n"
                 f"robot: {{description: {os.path.relpath(robot, here)}}}\n"
                 f"task: {{retrieve: {target}}}\n"
                 f"planner: {{plugin: {planner}, time_limit: {time_limit}, seed: 0}}\n"
                 "plugins: {grasp_sampler: grasp_side, motion_sampler: motion_ompl, placement_sampler: placement_region}\n")
    return load_problem(problem_file)


def solve_pddl(domain, problem, search="lama-first", time_limit=60.0, max_expansions=None, landmarks="rhw",
               anytime=False):
    """Grounds and searches a PDDL domain and problem as `cluttertamp pddl` does (the time
    limit, in seconds, counts parsing and grounding too; landmarks and anytime as the
    command's --landmarks and --anytime): a dict with solved, reason, plan (steps in IPC
    format, "(action arg ...)"), cost, the search's counts and plans_found."""
    return _cluttertamp.solve_pddl(os.fspath(domain), os.fspath(problem), search, time_limit, max_expansions, landmarks,
                                   bool(anytime))


def validate_pddl_plan(domain, problem, plan):
    """Checks a plan (IPC text, a list of steps, or a plan file) against a domain and
    problem as `cluttertamp validate-plan` does: a dict with valid, reason, step, cost."""
    name = "plan"
    if isinstance(plan, (list, tuple)):
        plan = "\n".join(plan)
    elif isinstance(plan, os.PathLike) or (isinstance(plan, str) and "(" not in plan and os.path.exists(plan)):
        name = os.fspath(plan)
        with open(name, encoding="utf-8") as f:
            plan = f.read()
    return _cluttertamp.validate_pddl_plan(os.fspath(domain), os.fspath(problem), plan, name)


def search_names():
    """The searches solve_pddl takes."""
    return _cluttertamp.search_names()
