"""Streams written in Python behind the adaptive and incremental searches: the 2-D
blocks problem of examples/python/blocks_2d solved and replayed, PDDLStream's call
kinds, errors located, a raising stream a failure with its traceback."""

import importlib.util
import subprocess
import sys
import os

import pytest

import cluttertamp
from cluttertamp.streams import PDDLProblem, from_fn, from_gen_fn, from_list_gen_fn, from_test, solve

SOURCE = os.environ["CLUTTERTAMP_SOURCE_DIR"]
EXAMPLE = os.path.join(SOURCE, "examples", "python", "blocks_2d")


def example():
    spec = importlib.util.spec_from_file_location("blocks_2d_problem", os.path.join(EXAMPLE, "problem.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("algorithm", ["adaptive", "incremental"])
def test_the_blocker_is_moved_out_of_the_way_first(algorithm):
    blocks = example()
    for seed in range(5):
        solution = solve(blocks.blocks_problem(seed), algorithm=algorithm, time_limit=60)
        assert solution.solved, solution.reason
        final = blocks.check(solution.plan)  # b0 in the goal, no overlap on the way
        assert [a for a, _ in solution.plan] == ["pick", "place", "pick", "place"]
        assert solution.plan[0][1][0] == "b1"
        assert final["b1"] != 1.25
        plan, cost, statistics = solution
        assert plan == solution.plan and cost == 4 and statistics["stream_calls"] > 0


def test_values_are_the_python_objects_the_streams_made():
    made = []

    class Pose:
        def __init__(self, x):
            self.x = x
            made.append(self)

    def sample(block, region):
        for k in range(100):
            yield (Pose(region[0] + 0.25 + 0.01 * k),)

    def cfree(block, pose, other, other_pose):
        assert isinstance(pose, (Pose, float)) and isinstance(other_pose, (Pose, float))
        x = pose.x if isinstance(pose, Pose) else pose
        y = other_pose.x if isinstance(other_pose, Pose) else other_pose
        return abs(x - y) >= 0.4

    blocks = example()
    problem = blocks.blocks_problem()._replace(stream_map={"sample-pose": from_gen_fn(sample), "test-cfree": from_test(cfree)})
    solution = solve(problem)
    assert solution.solved, solution.reason
    placed = [arguments[1] for action, arguments in solution.plan if action == "place"]
    assert all(any(p is m for m in made) for p in placed)


def test_a_stream_that_raises_is_a_failure_with_its_traceback():
    def cfree(block, pose, other, other_pose):
        return 1 / 0

    blocks = example()
    problem = blocks.blocks_problem()._replace(stream_map={**blocks.blocks_problem().stream_map, "test-cfree": from_test(cfree)})
    solution = solve(problem, time_limit=5)
    assert not solution.solved and solution.reason
    stage, reason = next(f for f in solution.failures if f[0] == "stream test-cfree")
    assert "Traceback" in reason and "ZeroDivisionError" in reason and "return 1 / 0" in reason


def test_every_call_kind_of_pddlstream():
    domain = """(define (domain kinds) (:requirements :strips)
      (:predicates (Number ?n) (Double ?n ?d) (Even ?n) (Big ?n) (Done ?n))
      (:functions (Cost ?n))
      (:action finish :parameters (?n ?d) :precondition (and (Double ?n ?d) (Even ?d) (Big ?d))
        :effect (and (Done ?n) (increase (total-cost) (Cost ?d)))))"""
    streams = """(define (stream kinds)
      (:stream double :inputs (?n) :domain (Number ?n) :outputs (?d) :certified (and (Number ?d) (Double ?n ?d)))
      (:stream nothing :inputs (?n) :domain (Number ?n) :outputs (?m) :certified (Number ?m))
      (:stream pairs :inputs (?n) :domain (Number ?n) :outputs (?m) :certified (Number ?m))
      (:stream even :inputs (?n) :domain (Number ?n) :certified (Even ?n))
      (:predicate (Big ?n) (Number ?n))
      (:function (Cost ?n) (Number ?n)))"""
    calls = {"nothing": 0}

    def nothing(n):
        calls["nothing"] += 1
        return None

    def pairs(n):
        yield [(n + 100,), (n + 200,)]

    stream_map = {"double": from_fn(lambda n: (2 * n,)), "nothing": from_fn(nothing), "pairs": from_list_gen_fn(pairs),
                  "even": from_test(lambda n: n % 2 == 0), "Big": lambda n: n > 5, "Cost": lambda n: float(n)}
    problem = PDDLProblem(domain, {}, streams, stream_map, [("Number", 3)], ("Done", 3))
    for algorithm in ("adaptive", "incremental"):
        solution = solve(problem, algorithm=algorithm)
        assert solution.solved, solution.reason
        assert solution.plan == [("finish", (3, 6))]
    assert calls["nothing"] >= 1


def test_errors_name_what_is_wrong_and_where():
    blocks = example()
    problem = blocks.blocks_problem()
    with pytest.raises(cluttertamp.InputError) as caught:
        solve(problem._replace(stream_map={"sample-pose": problem.stream_map["sample-pose"]}))
    file, line, column, message = caught.value.errors[0]
    assert file.endswith("streams.pddl") and (line, column) == (8, 3) and "test-cfree" in message
    with pytest.raises(TypeError, match="from_gen_fn"):
        solve(problem._replace(stream_map={**problem.stream_map, "sample-pose": lambda b, r: None}))
    with pytest.raises(ValueError, match="does not declare"):
        solve(problem._replace(stream_map={**problem.stream_map, "sample-grasp": from_fn(lambda: None)}))
    with pytest.raises(cluttertamp.InputError) as caught:
        solve(problem._replace(domain_pddl="(define (domain blocks-2d) (:predicates (Block ?b)) (:action pick))"))
    assert caught.value.errors[0][0] == "<domain>"
    with pytest.raises(ValueError, match="algorithm"):
        solve(problem, algorithm="sideways")


def test_a_search_ended_by_its_time_limit_lets_the_interpreter_exit_cleanly(tmp_path):
    # The search is freed on a background thread after its time limit; the Python values
    # it holds are released under the GIL later, never by that thread at exit.
    script = tmp_path / "ends_at_limit.py"
    script.write_text(
        "import importlib.util\n"
        f"spec = importlib.util.spec_from_file_location('p', {os.path.join(EXAMPLE, 'problem.py')!r})\n"
        "m = importlib.util.module_from_spec(spec); spec.loader.exec_module(m)\n"
        "from cluttertamp.streams import from_test, solve\n"
        "problem = m.blocks_problem()\n"
        "problem = problem._replace(stream_map={**problem.stream_map, 'test-cfree': from_test(lambda *a: 1 / 0)})\n"
        "print(solve(problem, time_limit=1).reason)\n")
    run = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120, env=dict(os.environ))
    assert run.returncode == 0, run.stdout + run.stderr
    assert "time limit" in run.stdout


def test_a_stream_answering_the_wrong_shape_is_a_failure_not_an_error():
    blocks = example()
    problem = blocks.blocks_problem()
    wrong = problem._replace(stream_map={**problem.stream_map, "sample-pose": from_gen_fn(lambda b, r: iter([0.5]))})
    solution = solve(wrong, time_limit=5)
    assert not solution.solved
    assert any(stage == "stream sample-pose" and "not a tuple of outputs" in reason for stage, reason in solution.failures)
    arity = problem._replace(stream_map={**problem.stream_map, "test-cfree": from_test(lambda b: True)})
    solution = solve(arity, time_limit=5)
    assert any(stage == "stream test-cfree" and "TypeError" in reason for stage, reason in solution.failures)


def test_a_function_wrapped_with_from_fn_gives_its_number():
    domain = """(define (domain costs) (:requirements :strips)
      (:predicates (Number ?n) (Done ?n)) (:functions (Cost ?n))
      (:action finish :parameters (?n) :precondition (Number ?n) :effect (and (Done ?n) (increase (total-cost) (Cost ?n)))))"""
    streams = "(define (stream costs) (:function (Cost ?n) (Number ?n)))"
    problem = PDDLProblem(domain, {}, streams, {"Cost": from_fn(lambda n: (2.5 * n,))}, [("Number", 2)], ("Done", 2))
    solution = solve(problem)
    assert solution.solved and solution.cost == 5.0


def test_a_stream_with_fluents_gets_the_state_it_is_evaluated_in():
    domain = """(define (domain fluents) (:requirements :strips)
      (:predicates (Block ?b) (Pose ?p) (AtPose ?b ?p) (Free ?b ?p) (Moved ?b))
      (:action move :parameters (?b ?from ?to) :precondition (and (AtPose ?b ?from) (Free ?b ?to))
        :effect (and (AtPose ?b ?to) (not (AtPose ?b ?from)) (Moved ?b))))"""
    streams = """(define (stream fluents)
      (:stream free-pose :inputs (?b) :domain (Block ?b) :fluents (AtPose) :outputs (?p)
        :certified (and (Pose ?p) (Free ?b ?p))))"""
    seen = []

    def free_pose(block, fluents=()):
        facts = [tuple(f) for f in fluents]
        seen.append(facts)
        occupied = {f[2] for f in facts if f[0].lower() == "atpose"}
        yield (next(p for p in range(10) if p not in occupied),)

    init = [("Block", "a"), ("Block", "c"), ("Pose", 0), ("Pose", 1), ("AtPose", "a", 0), ("AtPose", "c", 1)]
    problem = PDDLProblem(domain, {}, streams, {"free-pose": from_gen_fn(free_pose)}, init, ("Moved", "a"))
    solution = solve(problem, algorithm="adaptive")
    assert solution.solved, solution.reason
    assert solution.plan == [("move", ("a", 0, 2))]
    assert seen and all(sorted((f[0].lower(),) + f[1:] for f in facts) == [("atpose", "a", 0), ("atpose", "c", 1)]
                        for facts in seen), seen
    with pytest.raises(cluttertamp.InputError, match="fluents"):
        solve(problem, algorithm="incremental")
