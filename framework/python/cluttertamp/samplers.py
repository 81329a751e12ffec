"""Samplers written in Python, named in problem files like the C++ plugins.

    import cluttertamp

    class FrontGrasps(cluttertamp.GraspSampler):
        def configure(self, parameters):
            self.heights = parameters.numbers("heights", [0.5], "fractions of the object's height", low=0, high=1)

        def sample(self, query):
            ...  # yield 4 x 4 tool poses (world frame), or query.grasp(pose, approach=..., lift=...)

    cluttertamp.register_sampler("front_grasps", FrontGrasps)
    result = cluttertamp.plan("problem.yaml")   # its plugins: grasp_sampler: {name: front_grasps}

The sampler proposes; cluttertamp checks every proposal as it checks its own samplers'
(IK, the approach, the grasp and the lift for a grasp; contacts and reach for a
placement; every straight segment of a motion at 0.01 rad; a push in the physics), so a
proposal that collides is rejected with the objects in its way, never planned with. An
exception raised by a sampler is that call's failure, its traceback in the reason
(result.json's `failures`); the run goes on.

Each run makes a new instance (the class is called with no arguments), then calls
`configure(parameters)` with the problem file's parameters for it (a Parameters: number,
integer, boolean, string, numbers and require; keys never read are reported as unknown,
values out of range with their file, line and column), then the sampling method once per
query. Queries, their `world` and the parameters object answer only during the call.

Calls hold the GIL and are not interrupted: a sampler that runs long should look at
`query.remaining_time` (s). Randomness should come from `query.seed` (the same run seed
gives the same seed), so that a run repeats exactly.
"""

from . import _cluttertamp
from ._cluttertamp import GraspQuery, PlacementQuery, MotionQuery, PushQuery, Grasp, Parameters, World  # noqa: F401

__all__ = [
    "GraspSampler", "PlacementSampler", "MotionSampler", "PushSampler",
    "register_sampler", "withdraw_sampler",
]


class GraspSampler:
    """Proposes grasps of an object: `sample(query)` returns or yields tool poses (4 x 4,
    world frame, z the approach direction) or Grasps made with `query.grasp(pose,
    approach=0.10, lift=0.03, clearance=0.008)` (m). Sampling stops after `max_usable`
    usable grasps.

    GraspQuery: object (id), shape (dict: type, radius/height or size), world_T_object,
    world_T_robot_base, gripper_stroke (m), configuration (where IK starts), joint_names,
    seed, remaining_time, world (a World at the query's state, hand empty)."""

    kind = "grasp_sampler"
    max_usable = 3

    def configure(self, parameters):
        """Reads the problem file's parameters (a Parameters); the default reads none."""

    def sample(self, query):
        raise NotImplementedError(f"{type(self).__name__}.sample(query) is not written")


class PlacementSampler:
    """Proposes where to put an object down in a region: `sample(query)` returns or yields
    object poses (4 x 4, world frame); the first `query.max_placements` that touch nothing
    and the robot can hold are kept, after at most `max_attempts` proposals.

    PlacementQuery: object, shape, region (id), world_T_region (its centre), region_size
    (full edges, m), gripper_T_object (how it is held, or None: a side grip facing the
    robot), max_placements, plus configuration, seed, world, ... as GraspQuery."""

    kind = "placement_sampler"
    max_attempts = 200

    def configure(self, parameters):
        """Reads the problem file's parameters (a Parameters); the default reads none."""

    def sample(self, query):
        raise NotImplementedError(f"{type(self).__name__}.sample(query) is not written")


class MotionSampler:
    """Plans robot motions: `plan(query)` returns waypoints (an n x joints array or a list
    of configurations) from query.start to query.goal (added where missing), or None when
    it finds none. Every straight segment between them is checked every 0.01 rad, carrying
    what the hand holds; the first contact fails the motion with the objects in the way.

    MotionQuery: start, goal, lower_limits, upper_limits, joint_names, seed, world (at the
    query's state, the held object in the hand), remaining_time."""

    kind = "motion_sampler"

    def configure(self, parameters):
        """Reads the problem file's parameters (a Parameters); the default reads none."""

    def plan(self, query):
        raise NotImplementedError(f"{type(self).__name__}.plan(query) is not written")


class PushSampler:
    """Pushes an object: `push(query)` returns the gripper's planar waypoints (x, y m, yaw
    rad, world frame) from query.gripper, or None. They are simulated in the push physics
    in straight, speed-bounded controls; the push counts when no object falls or leaves
    the support, the gripper stays clear of fixed geometry, and query.object ends within
    goal_radius of goal_xy.

    PushQuery: object, goal_xy, goal_radius (m), gripper (x, y, yaw), support ((x_min,
    y_min), (x_max, y_max)), object_poses (id -> 4 x 4), seed, remaining_time."""

    kind = "push_sampler"

    def configure(self, parameters):
        """Reads the problem file's parameters (a Parameters); the default reads none."""

    def push(self, query):
        raise NotImplementedError(f"{type(self).__name__}.push(query) is not written")


def register_sampler(name, cls=None, kind=None, description=None):
    """Makes the class `cls` the sampler `name` of its kind (grasp_sampler, placement_sampler,
    motion_sampler or push_sampler: from its base class, or `kind`) for every plan made in
    this process afterwards. It is found before a plugin library's sampler of the same name;
    registering a name again replaces it. Returns `cls`, so it can decorate:

        @cluttertamp.register_sampler("front_grasps")   # no cls: a decorator
        class FrontGrasps(cluttertamp.GraspSampler): ...
    """
    if cls is None:
        return lambda c: register_sampler(name, c, kind, description)
    kind = kind or getattr(cls, "kind", None)
    if kind is None:
        raise ValueError(f"say which kind of sampler {cls!r} is: derive it from GraspSampler, PlacementSampler, "
                         "MotionSampler or PushSampler, or pass kind=")
    doc = (cls.__doc__ or "").strip().splitlines()
    origin = f"python:{cls.__module__}.{cls.__qualname__}"
    _cluttertamp.provide_sampler(kind, name, cls, description if description is not None else (doc[0] if doc else ""),
                                 origin)
    return cls


def withdraw_sampler(kind, name):
    """Forgets the Python sampler `name` of `kind` for plans made afterwards; False when there
    was none."""
    return _cluttertamp.withdraw_sampler(kind, name)
