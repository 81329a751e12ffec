"""What a Python stream costs beyond the Python function itself, per call.

    PYTHONPATH=build/python python3 examples/python/bench_stream_overhead.py [N]

N x N instances of a stream whose generator is empty are evaluated once each by the
incremental search (the goal needs a fact none certifies). The search's stream time
(measured around each call in C++) less the same generators run in plain Python,
divided by the calls, is the binding's overhead per call; the goal is 5 us at most.
"""

import statistics
import sys
import time

from cluttertamp.streams import PDDLProblem, from_gen_fn, solve

N = int(sys.argv[1]) if len(sys.argv) > 1 else 100
DOMAIN = """(define (domain empty) (:requirements :strips)
  (:predicates (N ?a) (Ok ?a ?b) (Done))
  (:action finish :parameters (?a ?b) :precondition (Ok ?a ?b) :effect (Done)))"""
STREAMS = """(define (stream empty)
  (:stream ok :inputs (?a ?b) :domain (and (N ?a) (N ?b)) :outputs (?c) :certified (Ok ?a ?c)))"""


def empty(a, b):
    return iter(())


def plain_python_seconds(calls):
    start = time.perf_counter()
    for _ in range(calls):
        for _ in empty(0, 0):
            pass
    return time.perf_counter() - start


problem = PDDLProblem(DOMAIN, {}, STREAMS, {"ok": from_gen_fn(empty)}, [("N", k) for k in range(N)], ("Done",))
overheads = []
for run in range(5):
    solution = solve(problem, algorithm="incremental", time_limit=120)
    calls = solution.statistics["stream_calls"]
    python = plain_python_seconds(calls)
    overheads.append((solution.statistics["stream_seconds"] - python) / calls * 1e6)
    print(f"run {run}: {calls} calls, stream time {solution.statistics['stream_seconds'] * 1e3:.1f} ms, "
          f"plain Python {python * 1e3:.1f} ms, overhead {overheads[-1]:.2f} us per call ({solution.reason})")
median = statistics.median(overheads)
print(f"median overhead per call: {median:.2f} us (goal <= 5 us): {'met' if median <= 5 else 'MISSED'}")
sys.exit(0 if median <= 5 else 1)
