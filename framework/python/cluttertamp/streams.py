"""Streams written in Python, as PDDLStream writes them, solved by cluttertamp's
adaptive (focused) or incremental stream search.

    from cluttertamp.streams import PDDLProblem, from_gen_fn, from_test, solve

    stream_map = {"sample-pose": from_gen_fn(sample_pose), "collision-free": from_test(free)}
    problem = PDDLProblem(domain_pddl, {}, stream_pddl, stream_map, init, goal)
    solution = solve(problem, algorithm="adaptive")
    plan, cost, _ = solution          # as PDDLStream's solve() returns them

Semantics are PDDLStream's: a generator function yields output tuples (or None for
"nothing this time"); a function returns one tuple or None; a test returns a bool; a
predicate or cost function in the stream map may be a plain callable. Values are any
Python objects: the ones in `init` become problem objects, the ones streams make are
handed back to streams and appear in the plan as themselves.
"""

import collections
import os
import re

from . import _cluttertamp

__all__ = ["PDDLProblem", "Solution", "StreamFn", "from_gen_fn", "from_list_gen_fn", "from_fn", "from_test", "solve"]


class StreamFn:
    """A callable with how the search calls it: "gen" (a generator of output tuples),
    "list_gen" (a generator of lists of output tuples), "fn" (one tuple or None) or
    "test" (a bool)."""

    def __init__(self, kind, fn):
        if not callable(fn):
            raise TypeError(f"a stream needs a callable, not {fn!r}")
        self.kind = kind
        self.fn = fn

    def __repr__(self):
        return f"StreamFn({self.kind!r}, {getattr(self.fn, '__name__', self.fn)!r})"


def from_gen_fn(fn):
    """fn(*inputs) returns an iterator of output tuples."""
    return StreamFn("gen", fn)


def from_list_gen_fn(fn):
    """fn(*inputs) returns an iterator of lists of output tuples."""
    return StreamFn("list_gen", fn)


def from_fn(fn):
    """fn(*inputs) returns one output tuple, or None when there is none."""
    return StreamFn("fn", fn)


def from_test(fn):
    """fn(*inputs) returns whether the certified facts hold."""
    return StreamFn("test", fn)


PDDLProblem = collections.namedtuple("PDDLProblem", ["domain_pddl", "constant_map", "stream_pddl", "stream_map",
                                                     "init", "goal"])


class Solution:
    """`solved`, `reason`, `plan` (a list of (action, arguments) with the arguments as
    Python values), `cost`, `failures` ((stage, reason) of streams that produced
    nothing) and `statistics`. Unpacks as (plan or None, cost, statistics)."""

    def __init__(self, data):
        self.solved = data["solved"]
        self.reason = data["reason"]
        self.plan = [(action, tuple(arguments)) for action, arguments in data["plan"]]
        self.cost = data["cost"]
        self.failures = list(data["failures"])
        self.statistics = dict(data["statistics"])

    def __iter__(self):
        return iter((self.plan if self.solved else None, self.cost if self.solved else float("inf"), self.statistics))

    def __repr__(self):
        if self.solved:
            return f"Solution({len(self.plan)} steps, cost {self.cost})"
        return f"Solution(not solved: {self.reason})"


_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_\-]*$")


def _text(source, what):
    """PDDL text and a name for messages: `source` is the text itself or a file."""
    if isinstance(source, os.PathLike) or (isinstance(source, str) and "(" not in source):
        path = os.fspath(source)
        with open(path, encoding="utf-8") as f:
            return f.read(), path
    return source, f"<{what}>"


class _Objects:
    """Python values as PDDL objects: strings that are PDDL names stand for themselves,
    constants for their constant_map values, anything else gets a fresh name."""

    def __init__(self, constant_map):
        self.values = {}        # name -> value
        self.by_value = {}      # hashable value -> name
        self.by_id = {}         # id(unhashable value) -> name
        self.constants = set()
        for name, value in constant_map.items():
            self.constants.add(name.lower())
            self._remember(name.lower(), value)

    def _remember(self, name, value):
        self.values[name] = value
        try:
            self.by_value.setdefault(value, name)
        except TypeError:
            self.by_id[id(value)] = name

    def name(self, value):
        try:
            if value in self.by_value:
                return self.by_value[value]
        except TypeError:
            if id(value) in self.by_id:
                return self.by_id[id(value)]
        if isinstance(value, str) and _NAME.match(value) and value.lower() not in self.values:
            name = value.lower()
        else:
            name = f"v{len(self.values)}"
            while name in self.values:
                name += "_"
        self._remember(name, value)
        return name


def _atom(fact, objects):
    if not isinstance(fact, (tuple, list)) or not fact or not isinstance(fact[0], str):
        raise ValueError(f"a fact is a tuple (predicate, argument...), not {fact!r}")
    return "(" + " ".join([fact[0]] + [objects.name(a) for a in fact[1:]]) + ")"


def _formula(goal, objects):
    if isinstance(goal, (tuple, list)) and goal and isinstance(goal[0], str):
        head = goal[0].lower()
        if head in ("and", "or", "not", "imply"):
            return f"({head} " + " ".join(_formula(g, objects) for g in goal[1:]) + ")"
        return _atom(goal, objects)
    if isinstance(goal, (tuple, list)):  # a list of facts: their conjunction
        return "(and " + " ".join(_formula(g, objects) for g in goal) + ")"
    raise ValueError(f"a goal is a fact or ('and' | 'or' | 'not', ...), not {goal!r}")


def solve(problem, algorithm="adaptive", search="lazy-gbfs-ff", seed=0, time_limit=60.0):
    """Solves a PDDLProblem with the adaptive (focused) or incremental stream search.

    domain_pddl and stream_pddl are PDDL text or files. Raises cluttertamp.InputError
    (file, line, column) for bad PDDL or a stream the stream map leaves out; a stream
    that raises is a failure of that stream (with its traceback in `failures`), not
    an error of the run."""
    domain_text, domain_name = _text(problem.domain_pddl, "domain")
    stream_text, stream_name = _text(problem.stream_pddl, "stream")
    match = re.search(r"\(\s*domain\s+([^\s()]+)", domain_text, re.IGNORECASE)
    if not match:
        raise ValueError(f"{domain_name}: no (domain NAME) in the domain")
    objects = _Objects(dict(problem.constant_map or {}))
    init = " ".join(_atom(fact, objects) for fact in problem.init)
    goal = _formula(problem.goal, objects)
    declared = " ".join(n for n in objects.values if n not in objects.constants)
    # Action costs count as PDDLStream counts them (unit_costs=False): the domain's
    # (total-cost), minimized.
    metric = "\n  (:metric minimize (total-cost))" if "total-cost" in domain_text.lower() else ""
    problem_text = (f"(define (problem python) (:domain {match.group(1)})\n  (:objects {declared})\n"
                    f"  (:init {init})\n  (:goal {goal}){metric})\n")
    stream_map = {}
    for name, entry in problem.stream_map.items():
        if isinstance(entry, StreamFn):
            stream_map[name.lower()] = (entry.kind, entry.fn)
        elif callable(entry):
            stream_map[name.lower()] = ("auto", entry)
        else:
            raise TypeError(f"stream map entry {name!r}: {entry!r} is not callable (PDDLStream's debug "
                            "entries are not supported)")
    values = {name: value for name, value in objects.values.items()}
    data = _cluttertamp.solve_python_streams(domain_text, domain_name, stream_text, stream_name, problem_text, values,
                                             stream_map, algorithm, search, seed, time_limit)
    return Solution(data)
