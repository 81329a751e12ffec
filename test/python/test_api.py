"""The Python module against the command line: the same results, errors with their
locations, kinematics that round-trip, PDDL plans the validator accepts, no leaks."""

import json
import sys
import os
import resource
import subprocess

import numpy as np
import pytest

import cluttertamp

SOURCE = os.environ["CLUTTERTAMP_SOURCE_DIR"]
CLI = os.environ["CLUTTERTAMP_CLI"]
DEFAULT = os.path.join(SOURCE, "problems", "default.yaml")
UR10 = os.path.join(SOURCE, "domains", "robots", "ur10_ag95.yaml")


def small_problem(tmp_path, planner="retrieval_graph", extra=""):
    """Three cylinders and a lid on a floor (test/data/scenes/good.yaml), target 'a'."""
    file = tmp_path / "small.yaml"
    file.write_text(
        "version: 1\n"
        f"scene: {SOURCE}/test/data/scenes/good.yaml\n"
        f"robot: {{description: {UR10}{extra}}}\n"
        "task: {retrieve: a}\n"
        f"planner: {{plugin: {planner}, time_limit: 30, seed: 0}}\n"
        "plugins: {grasp_sampler: grasp_side, motion_sampler: motion_ompl, placement_sampler: placement_region}\n")
    return file


def without_times(value):
    """A result.json without the fields that measure time (as plan --expect compares)."""
    if isinstance(value, dict):
        return {k: without_times(v) for k, v in value.items() if k not in ("time", "seconds")}
    if isinstance(value, list):
        return [without_times(v) for v in value]
    return value


def test_plan_gives_what_the_command_line_writes(tmp_path):
    result = cluttertamp.plan(DEFAULT, seed=0)
    out = tmp_path / "cli"
    run = subprocess.run([CLI, "plan", DEFAULT, "--seed", "0", "--output", str(out), "-q"], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    with open(out / "result.json", encoding="utf-8") as f:
        written = json.load(f)
    assert without_times(result.json) == without_times(written)
    assert result.solved and result.exit_code == 0 and result.reason is None
    assert result.moved_objects[-1] == "target"
    assert result.counters["collision_checks"] > 0


def test_trajectories_are_numpy_arrays_that_join_up():
    problem = cluttertamp.load_problem(DEFAULT)
    result = cluttertamp.plan(problem, seed=1)
    assert result.solved
    joints = problem.robot.joint_names
    previous_end = problem.robot.home
    for step in result.steps:
        trajectory = step.trajectory
        assert trajectory.joint_names == joints
        assert trajectory.positions.shape == (len(trajectory.times), len(joints))
        assert np.all(np.diff(trajectory.times) > 0)
        np.testing.assert_allclose(trajectory.positions[0], previous_end, atol=1e-9)
        previous_end = trajectory.positions[-1]
    assert result.steps[-1].action == "retrieve"


def test_a_result_writes_the_same_result_json_and_a_replay_page(tmp_path):
    result = cluttertamp.plan(DEFAULT, seed=0)
    path = result.write(tmp_path / "out")
    assert open(path, encoding="utf-8").read() == result.text
    page = tmp_path / "plan.html"
    result.write_page(page)
    text = page.read_text(encoding="utf-8")
    assert text.lower().startswith("<!doctype html>") and "target" in text
    # A file that cannot be written is Python's OSError, naming it; nothing is left half written.
    (tmp_path / "a-file").write_text("x")
    with pytest.raises(OSError):
        result.write(tmp_path / "a-file" / "out")
    with pytest.raises(OSError, match="a-file/plan.html: error: cannot write the page"):
        result.write_page(tmp_path / "a-file" / "plan.html")


def test_planning_failure_is_a_result_with_a_reason(tmp_path):
    # The robot stands 3 m behind the target: out of its reach, said before planning.
    scene = tmp_path / "far.yaml"
    with open(os.path.join(SOURCE, "test", "data", "scenes", "good.yaml"), encoding="utf-8") as f:
        scene.write_text(f.read().replace("robot_base: {xyz: [0.0, 0.0, 0.0]}", "robot_base: {xyz: [-2.0, 0.0, 0.0]}"))
    problem = small_problem(tmp_path)
    problem.write_text(problem.read_text().replace(f"{SOURCE}/test/data/scenes/good.yaml", str(scene)))
    failed = cluttertamp.plan(problem)
    assert not failed.solved
    assert failed.exit_code == 1
    assert "out of the robot's reach" in failed.reason
    assert failed.steps == []


def test_bad_input_raises_input_error_with_every_location():
    bad = os.path.join(SOURCE, "test", "data", "problems", "bad_problem.yaml")
    with pytest.raises(cluttertamp.InputError) as caught:
        cluttertamp.load_problem(bad)
    error = caught.value
    assert isinstance(error, ValueError)
    assert (bad, 3, 22) in [e[:3] for e in error.errors]
    assert (bad, 7, 15) in [e[:3] for e in error.errors]
    assert "bad_problem.yaml:3:22: error:" in str(error)
    with pytest.raises(cluttertamp.InputError, match="no such file"):
        cluttertamp.load_problem(os.path.join(SOURCE, "no", "such.yaml"))


def test_a_missing_plugin_and_a_robot_starting_in_collision_are_input_errors(tmp_path):
    with pytest.raises(cluttertamp.InputError, match="no_such_planner"):
        cluttertamp.plan(small_problem(tmp_path), planner="no_such_planner")
    # The arm stretched out towards +x at shoulder height, through the cylinders.
    inside = small_problem(tmp_path, extra=", configuration: [3.14159, 0, 0, 0, 0, 0, 0.0475]")
    with pytest.raises(cluttertamp.InputError, match="overlaps the robot's start configuration") as caught:
        cluttertamp.validate(inside)
    assert any(file.endswith("good.yaml") for file, *_ in caught.value.errors)
    with pytest.raises(cluttertamp.InputError):
        cluttertamp.plan(inside)


def test_forward_and_inverse_kinematics_round_trip():
    robot = cluttertamp.load_robot(UR10)
    rng = np.random.default_rng(5)
    for _ in range(200):
        q = robot.home.copy()
        q[:6] = rng.uniform(-np.pi, np.pi, 6)
        pose = robot.tool_pose(q)
        assert pose.shape == (4, 4)
        solutions = robot.ik(pose, seed=q)
        assert 1 <= len(solutions) <= 8
        for s in solutions:
            np.testing.assert_allclose(robot.tool_pose(s), pose, atol=1e-6)
        assert min(np.abs(np.remainder(s[:6] - q[:6] + np.pi, 2 * np.pi) - np.pi).max() for s in solutions) < 1e-6
    links = robot.link_poses(robot.home)
    np.testing.assert_allclose(links["gripper_tcp"], robot.tool_pose(robot.home), atol=1e-12)
    with pytest.raises(ValueError, match="7 values, not 3"):
        robot.tool_pose(np.zeros(3))
    with pytest.raises(ValueError, match="not a rotation"):
        robot.ik(np.diag([2.0, 1.0, 1.0, 1.0]))


BLOCKS = os.path.join(SOURCE, "test", "data", "pddl", "blocks")


def test_pddl_plans_are_accepted_by_the_validator_and_broken_ones_are_not():
    domain, problem = os.path.join(BLOCKS, "domain.pddl"), os.path.join(BLOCKS, "p5-2.pddl")
    found = cluttertamp.solve_pddl(domain, problem)
    assert found["solved"] and found["plan"]
    assert cluttertamp.validate_pddl_plan(domain, problem, found["plan"]) == {
        "valid": True, "reason": None, "step": 0, "cost": found["cost"]}
    broken = cluttertamp.validate_pddl_plan(domain, problem, found["plan"][1:])
    assert not broken["valid"] and broken["reason"]
    with pytest.raises(cluttertamp.InputError) as caught:
        cluttertamp.validate_pddl_plan(domain, problem, "(no-such-action a b)\n")
    assert caught.value.errors[0][0] == "plan" and caught.value.errors[0][1] == 1
    assert "lama-first" in cluttertamp.search_names()


def test_pddl_searches_take_the_landmarks_and_the_anytime_mode_of_the_command():
    domain, problem = os.path.join(BLOCKS, "domain.pddl"), os.path.join(BLOCKS, "p5-2.pddl")
    first = cluttertamp.solve_pddl(domain, problem)
    assert first["solved"] and first["plans_found"] == 1
    other = cluttertamp.solve_pddl(domain, problem, landmarks="zhu-givan")
    assert other["solved"] and cluttertamp.validate_pddl_plan(domain, problem, other["plan"])["valid"]
    # Bounded by expansions, not by the clock: the same improvements on any machine.
    better = cluttertamp.solve_pddl(domain, problem, anytime=True, max_expansions=20000)
    assert better["solved"] and better["plans_found"] >= 1 and better["cost"] <= first["cost"]
    assert cluttertamp.validate_pddl_plan(domain, problem, better["plan"])["valid"]
    with pytest.raises(ValueError, match="unknown landmarks 'hm'; known: rhw, zhu-givan"):
        cluttertamp.solve_pddl(domain, problem, landmarks="hm")


@pytest.mark.skipif(os.environ.get("CLUTTERTAMP_SANITIZED") == "1",
                    reason="AddressSanitizer holds freed memory in quarantine: the process grows by design")
def test_a_thousand_plans_do_not_grow_the_process(tmp_path):
    problem = cluttertamp.load_problem(small_problem(tmp_path))

    def rss_kib():
        with open("/proc/self/statm", encoding="ascii") as f:
            return int(f.read().split()[1]) * resource.getpagesize() // 1024

    for seed in range(50):  # warm up: plugin libraries, allocator pools
        assert cluttertamp.plan(problem, seed=seed).solved
    before = rss_kib()
    for seed in range(1000):
        result = cluttertamp.plan(problem, seed=seed % 50)
        assert result.solved
    grown = rss_kib() - before
    assert grown < 4096, f"RSS grew by {grown} KiB over 1000 plans"


def test_the_example_plans_the_default_problem_and_writes_its_files(tmp_path):
    example = os.path.join(SOURCE, "examples", "python", "plan_default.py")
    run = subprocess.run([sys.executable, example, str(tmp_path)], capture_output=True, text=True,
                         env=dict(os.environ), timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "retrieve" in run.stdout
    assert (tmp_path / "result.json").exists() and (tmp_path / "plan.html").exists()
