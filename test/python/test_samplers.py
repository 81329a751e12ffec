"""Samplers written in Python, named in problem files: used by the retrieval planner,
their proposals checked as the framework's own, their exceptions failures with
tracebacks, their parameters read with locations; the collision world from Python."""

import math
import os
import subprocess
import sys

import numpy as np
import pytest

import cluttertamp

SOURCE = os.environ["CLUTTERTAMP_SOURCE_DIR"]
CLI = os.environ["CLUTTERTAMP_CLI"]
DEFAULT = os.path.join(SOURCE, "problems", "default.yaml")
UR10 = os.path.join(SOURCE, "domains", "robots", "ur10_ag95.yaml")


def side_tool(position, yaw, height):
    """A side grasp's tool pose: z along the approach (yaw in the plane), x down."""
    approach = np.array([math.cos(yaw), math.sin(yaw), 0.0])
    x = np.array([0.0, 0.0, -1.0])
    pose = np.eye(4)
    pose[:3, 0] = x
    pose[:3, 1] = np.cross(approach, x)
    pose[:3, 2] = approach
    pose[:3, 3] = position + np.array([0.0, 0.0, height])
    return pose


class FrontGrasps(cluttertamp.GraspSampler):
    """Side grasps facing the robot, a fan of directions at one height."""

    calls = 0

    def configure(self, parameters):
        self.spread = parameters.number("spread", 45.0, "degrees either side of facing the robot", low=0, high=90)
        self.directions = parameters.integer("directions", 7, "approach directions", low=1, high=31)

    def sample(self, query):
        type(self).calls += 1
        assert query.shape["type"] in ("cylinder", "box")
        centre = query.world_T_object[:3, 3]
        base = query.world_T_robot_base[:3, 3]
        facing = math.atan2(centre[1] - base[1], centre[0] - base[0])
        offsets = np.linspace(-self.spread, self.spread, self.directions) if self.directions > 1 else [0.0]
        for offset in sorted(offsets, key=abs):
            yield side_tool(centre, facing + math.radians(offset), 0.0)


def problem_file(tmp_path, grasp="front_grasps", placement="placement_region", motion="motion_ompl",
                 grasp_parameters="", name="py.yaml", scene="scenes/shelf12.yaml", extra_plugins=""):
    file = tmp_path / name
    parameters = f", parameters: {{{grasp_parameters}}}" if grasp_parameters else ""
    file.write_text(
        "version: 1\n"
        "name: python-samplers\n"
        f"scene: {SOURCE}/problems/{scene}\n"
        f"robot: {{description: {UR10}}}\n"
        "task: {retrieve: target}\n"
        "planner: {plugin: retrieval_graph, time_limit: 60, seed: 0}\n"
        "plugins:\n"
        f"  grasp_sampler: {{plugin: {grasp}{parameters}}}\n"
        f"  motion_sampler: {motion}\n"
        f"  placement_sampler: {placement}\n" + extra_plugins)
    return file


@pytest.fixture(autouse=True)
def registered():
    FrontGrasps.calls = 0
    cluttertamp.register_sampler("front_grasps", FrontGrasps)
    yield
    for kind in cluttertamp._cluttertamp.sampler_kinds():
        for name in ("front_grasps", "raising", "fan_placements", "through_the_floor", "python_push", "wall_push"):
            cluttertamp.withdraw_sampler(kind, name)


def check_plan(problem_file, result):
    """A solved retrieval: each object moved once, the target last, the steps' trajectories
    joining up; the first step (nothing moved yet) re-checked against the scene at every
    point and between points, the object it picks ignored."""
    problem = cluttertamp.load_problem(problem_file)
    assert result.moved_objects[-1] == problem.target
    assert len(set(result.moved_objects)) == len(result.moved_objects)
    trajectories = [s.trajectory for s in result.steps if s.trajectory is not None]
    for a, b in zip(trajectories, trajectories[1:]):
        assert np.abs(a.positions[-1] - b.positions[0]).max() < 1e-9
    first = result.steps[0]
    world = problem.world()
    points = first.trajectory.positions
    for a, b in zip(points, points[1:]):
        for t in np.linspace(0.0, 1.0, max(2, int(np.ceil(np.abs(b - a).max() / 0.01)) + 1)):
            contacts = world.contacts(a + t * (b - a), ignored=first.objects)
            assert not contacts["fixed"] and not contacts["self"], contacts
            assert contacts["objects"] == [], contacts


def test_a_python_grasp_sampler_is_used_by_the_retrieval_planner(tmp_path):
    problem = problem_file(tmp_path)
    result = cluttertamp.plan(problem)
    assert result.solved, result.reason
    assert FrontGrasps.calls > 0
    assert result.moved_objects[-1] == "target"
    assert result.counters["samples"] > 0
    check_plan(problem, result)
    # Same seed, same plan.
    again = cluttertamp.plan(problem)
    assert [s.objects for s in again.steps] == [s.objects for s in result.steps]
    assert np.array_equal(again.steps[0].trajectory.positions, result.steps[0].trajectory.positions)


def test_proposals_are_checked_a_grasp_through_the_back_wall_is_blocked(tmp_path):
    class FromBehind(cluttertamp.GraspSampler):
        def sample(self, query):
            centre = query.world_T_object[:3, 3]
            base = query.world_T_robot_base[:3, 3]
            facing = math.atan2(centre[1] - base[1], centre[0] - base[0])
            yield side_tool(centre, facing + math.pi, 0.0)  # from the far side: the shelf's back

    cluttertamp.register_sampler("front_grasps", FromBehind)
    result = cluttertamp.plan(problem_file(tmp_path))
    assert not result.solved
    reasons = " ".join(f.reason for f in result.failures)
    assert "no usable grasp of 'target'" in reasons
    assert "unreachable" in reasons or "fixed geometry" in reasons


def test_an_exception_in_a_sampler_is_a_failure_with_its_traceback(tmp_path):
    class Raising(cluttertamp.GraspSampler):
        def sample(self, query):
            return [1 / 0]

    cluttertamp.register_sampler("raising", Raising)
    result = cluttertamp.plan(problem_file(tmp_path, grasp="raising"))
    assert not result.solved and result.exit_code == 1
    grasp_failures = [f for f in result.failures if f.stage == "grasp"]
    assert grasp_failures
    reason = grasp_failures[0].reason
    assert "the Python grasp_sampler 'raising' raised" in reason
    assert "ZeroDivisionError" in reason
    assert "test_samplers.py" in reason and "in sample" in reason  # where: the traceback's frame


def test_proposals_of_the_wrong_shape_are_failures_not_crashes(tmp_path):
    class Wrong(cluttertamp.GraspSampler):
        def sample(self, query):
            yield np.eye(3)

    cluttertamp.register_sampler("raising", Wrong)
    result = cluttertamp.plan(problem_file(tmp_path, grasp="raising"))
    assert not result.solved
    assert any("grasp_sampler 'raising'" in f.reason for f in result.failures)

    class NotRigid(cluttertamp.GraspSampler):
        def sample(self, query):
            yield 2 * np.eye(4)

    cluttertamp.register_sampler("raising", NotRigid)
    result = cluttertamp.plan(problem_file(tmp_path, grasp="raising"))
    assert any("not a rigid transform" in f.reason for f in result.failures)


def test_python_parameters_are_checked_with_their_locations(tmp_path):
    solved = cluttertamp.plan(problem_file(tmp_path, grasp_parameters="spread: 30, directions: 5"))
    assert solved.solved
    bad = problem_file(tmp_path, grasp_parameters="spread: 120, colour: red", name="bad.yaml")
    with pytest.raises(cluttertamp.InputError) as raised:
        cluttertamp.plan(bad)
    messages = [(os.path.basename(f), line, message) for f, line, column, message in raised.value.errors]
    assert any(f == "bad.yaml" and line == 8 and "spread" in m for f, line, m in messages), messages
    assert any(f == "bad.yaml" and line == 8 and "unknown parameter 'colour'" in m for f, line, m in messages), messages


def test_a_python_placement_sampler_places_the_moved_objects(tmp_path):
    class FanPlacements(cluttertamp.PlacementSampler):
        proposed = 0

        def sample(self, query):
            rng = np.random.default_rng(query.seed)
            size = query.region_size
            height = query.shape["height"] if "height" in query.shape else query.shape["size"][2]
            for _ in range(100):
                local = np.eye(4)
                local[:3, 3] = [rng.uniform(-0.4, 0.4) * size[0], rng.uniform(-0.4, 0.4) * size[1],
                                -size[2] / 2 + height / 2]
                type(self).proposed += 1
                yield query.world_T_region @ local

    cluttertamp.register_sampler("fan_placements", FanPlacements)
    problem = problem_file(tmp_path, placement="fan_placements")
    result = cluttertamp.plan(problem)
    assert result.solved, result.reason
    assert FanPlacements.proposed > 0
    assert [s.action for s in result.steps].count("place") >= 1
    check_plan(problem, result)


def test_a_python_motion_through_the_floor_is_refused_with_what_it_touches(tmp_path):
    class ThroughTheFloor(cluttertamp.MotionSampler):
        def plan(self, query):
            down = query.start.copy()
            down[1] = query.upper_limits[1]  # the shoulder lifted as far as it goes: the arm into the table
            down[2] = 0.0
            return [query.start, down, query.goal]

    cluttertamp.register_sampler("through_the_floor", ThroughTheFloor)
    result = cluttertamp.plan(problem_file(tmp_path, motion="through_the_floor"))
    assert not result.solved
    motion = [f.reason for f in result.failures if "motion_sampler 'through_the_floor'" in f.reason]
    assert motion and all("touches" in r or "joint limits" in r for r in motion), motion


def test_the_world_answers_collision_and_kinematics_queries():
    problem = cluttertamp.load_problem(DEFAULT)
    world = problem.world()
    home = problem.robot.home
    assert world.is_valid(home)
    assert world.contacts(home) == {"self": False, "fixed": False, "objects": [], "valid": True}
    poses = world.object_poses
    assert set(poses) == set(problem.objects)
    # The tool at the target: that configuration touches the target and nothing fixed.
    target = poses["target"]
    tool = side_tool(target[:3, 3], 0.0, 0.0)
    solutions = world.ik(tool)
    assert solutions, "the target is in reach"
    for q in solutions:
        assert np.allclose(world.tool_pose(q), tool, atol=1e-6)
        touched = world.contacts(q)
        assert not touched["valid"]
        assert "target" in touched["objects"] or touched["fixed"]
        assert world.contacts(q, ignored=["target"])["objects"] == [o for o in touched["objects"] if o != "target"]
    # An object where another stands touches it.
    neighbour = next(o for o in problem.objects if o != "target")
    assert neighbour in world.object_contacts("target", poses[neighbour])["objects"]
    lifted = poses["target"].copy()
    lifted[2, 3] += 0.001  # standing on its board it touches the board
    assert world.object_contacts("target", lifted)["valid"]
    assert world.object_contacts("target", poses["target"])["fixed"]
    with pytest.raises(ValueError):
        world.is_valid(home[:-1])
    with pytest.raises(ValueError):
        world.object_contacts("no-such-object", target)


def test_a_query_kept_after_its_call_refuses_to_answer(tmp_path):
    kept = []

    class Keeping(FrontGrasps):
        def sample(self, query):
            kept.append(query)
            return super().sample(query)

    cluttertamp.register_sampler("front_grasps", Keeping)
    assert cluttertamp.plan(problem_file(tmp_path)).solved
    with pytest.raises(RuntimeError, match="call that is over"):
        kept[0].world_T_object
    with pytest.raises(RuntimeError, match="call that is over"):
        kept[0].world.is_valid(kept[0].configuration)


def test_registration_errors_and_withdrawal(tmp_path):
    with pytest.raises(ValueError, match="kind"):
        cluttertamp.register_sampler("x", object, kind="gripper")
    with pytest.raises(ValueError, match="C identifier"):
        cluttertamp.register_sampler("front-grasps", FrontGrasps)
    with pytest.raises(ValueError, match="say which kind"):
        cluttertamp.register_sampler("plain", object)

    @cluttertamp.register_sampler("raising")
    class Decorated(FrontGrasps):
        pass

    assert Decorated.kind == "grasp_sampler"
    assert cluttertamp.withdraw_sampler("grasp_sampler", "raising")
    assert not cluttertamp.withdraw_sampler("grasp_sampler", "raising")
    with pytest.raises(cluttertamp.InputError, match="no usable grasp_sampler plugin named 'raising'"):
        cluttertamp.plan(problem_file(tmp_path, grasp="raising"))


class LineUpAndPush(cluttertamp.PushSampler):
    """Out to the front of the shelf, across, in behind the object, then straight through it."""

    def push(self, query):
        here = query.object_poses[query.object][:2, 3]
        direction = (query.goal_xy - here) / np.linalg.norm(query.goal_xy - here)
        yaw = math.atan2(direction[1], direction[0])
        ahead = query.palm_size[0] / 2 + query.finger_length  # the fingertips, from the gripper's centre
        behind = here - (query.footprint_radius + ahead + 0.02) * direction
        end = query.goal_xy - (query.footprint_radius + query.palm_size[0] / 2) * direction  # palm face at it
        front = query.support[0][0] - 0.1
        return [(front, query.gripper[1], yaw), (front, behind[1], yaw), (behind[0], behind[1], yaw),
                (end[0], end[1], yaw)]


def push_problem(tmp_path, sampler):
    text = open(os.path.join(SOURCE, "problems", "push", "retrieve-push.yaml"), encoding="utf-8").read()
    text = text.replace("push_sampler: push_ompl", f"push_sampler: {sampler}")
    text = text.replace("scene: retrieve-push-scene.yaml", f"scene: {SOURCE}/problems/push/retrieve-push-scene.yaml")
    text = text.replace("../../domains", f"{SOURCE}/domains")
    file = tmp_path / "push.yaml"
    file.write_text(text)
    return file


def test_a_python_push_sampler_pushes_what_blocks_the_target(tmp_path):
    cluttertamp.register_sampler("python_push", LineUpAndPush)
    result = cluttertamp.plan(push_problem(tmp_path, "python_push"))
    assert result.solved, result.reason
    assert [s.action for s in result.steps] == ["push", "retrieve"]
    push = result.steps[0]
    assert push.objects == ["o3"] and push.values["controls"]
    assert result.counters["propagations"] > 0
    # The pushed object's end pose, as simulated: clear of the target's way out.
    end = np.array(push.values["o3"][:2])
    assert np.linalg.norm(end - result.planned_problem.world().object_poses["o3"][:2, 3]) > 0.05


def test_a_python_push_into_a_wall_is_not_used(tmp_path):
    class IntoTheWall(LineUpAndPush):
        def push(self, query):
            return [(0.9, -0.6, query.gripper[2])]  # across the shelf's right side wall

    cluttertamp.register_sampler("wall_push", IntoTheWall)
    result = cluttertamp.plan(push_problem(tmp_path, "wall_push"))
    assert result.solved, result.reason  # by picking and placing instead
    assert "push" not in [s.action for s in result.steps]


def test_generate_shelf_writes_the_scene_of_the_command_line(tmp_path):
    run = subprocess.run([CLI, "generate", "--objects", "12", "--seed", "0", "--output", str(tmp_path / "cli.yaml")],
                         capture_output=True, text=True)
    assert run.returncode == 0 and "(seed 0)" in run.stdout, run.stdout + run.stderr
    problem = cluttertamp.generate_shelf(tmp_path / "py.yaml", objects=12, seed=0,
                                         problem_file=tmp_path / "problem.yaml", robot=UR10)
    assert (tmp_path / "py.yaml").read_bytes() == (tmp_path / "cli.yaml").read_bytes()
    assert len(problem.objects) == 12 and problem.target == "target"
    assert cluttertamp.plan(problem).solved
    with pytest.raises(ValueError, match="robot"):
        cluttertamp.generate_shelf(tmp_path / "x.yaml", problem_file=tmp_path / "x-problem.yaml")
    with pytest.raises(ValueError):
        cluttertamp.generate_shelf(tmp_path / "x.yaml", objects=0)
    with pytest.raises(ValueError, match="finite"):
        cluttertamp.generate_shelf(tmp_path / "x.yaml", min_gap=float("nan"))


def run_example(name, *arguments):
    example = os.path.join(SOURCE, "examples", "python", name)
    run = subprocess.run([sys.executable, example, *arguments], capture_output=True, text=True, env=dict(os.environ))
    assert run.returncode == 0, run.stdout + run.stderr
    return run.stdout


def test_the_grasp_sampler_example_solves_the_default_problem():
    out = run_example("front_grasps.py", "--spread", "30")
    assert "front_grasps (Python)  solved" in out and "grasp_side (C++)       solved" in out


def test_the_plotting_example_draws_removals_against_objects(tmp_path):
    plot = tmp_path / "removals.svg"
    out = run_example("removals_vs_objects.py", "--objects", "6", "10", "--scenes", "2", "--output", str(plot))
    rows = [line.split() for line in out.splitlines() if line.split() and line.split()[0] in ("6", "10")]
    assert len(rows) == 4 and all(r[2] == "True" for r in rows)
    assert plot.read_text().lstrip().startswith("<?xml") and "objects on the shelf" in plot.read_text()


def test_grasps_round_trip_and_refuse_what_is_not_rigid(tmp_path):
    grasp = cluttertamp.Grasp()
    assert np.array_equal(grasp.world_T_gripper, np.eye(4))
    pose = side_tool(np.array([0.9, 0.1, 0.5]), 0.3, 0.02)
    for field in ("world_T_gripper", "world_T_pregrasp", "world_T_lift", "gripper_T_object"):
        setattr(grasp, field, pose)
        assert np.allclose(getattr(grasp, field), pose, atol=1e-15)
        with pytest.raises(ValueError, match="not a rigid transform"):
            setattr(grasp, field, pose * 1.5)
    grasp.finger_open, grasp.finger_closed = 0.05, 0.04
    assert (grasp.finger_open, grasp.finger_closed) == (0.05, 0.04)

    class Handmade(FrontGrasps):
        def sample(self, query):
            for pose in super().sample(query):  # the Grasp query.grasp makes, copied field by field
                made = query.grasp(pose)
                own = cluttertamp.Grasp()
                for field in ("world_T_gripper", "world_T_pregrasp", "world_T_lift", "gripper_T_object",
                              "finger_open", "finger_closed"):
                    setattr(own, field, getattr(made, field))
                yield own

    cluttertamp.register_sampler("front_grasps", Handmade)
    handmade = cluttertamp.plan(problem_file(tmp_path))
    cluttertamp.register_sampler("front_grasps", FrontGrasps)
    assert handmade.json["plan"] == cluttertamp.plan(problem_file(tmp_path)).json["plan"]
