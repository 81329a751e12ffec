// grasp_side: side grasps of standing cylinders and boxes (no overhand grasps inside
// shelves: Tian et al.'s assumption 2). A preset ring of approach directions facing
// the robot times a few heights, plus seeded random ones. A grasp is usable when the
// approach (pre-grasp to grasp, fingers open), the grasp and the lift (object held)
// are collision-free; otherwise the answer names the movable objects in the way.
#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <span>
#include <string>

#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/manipulation/base_placement.hpp"
#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"

namespace {

using namespace cluttertamp;
using plugin::BlockedGrasp;
using plugin::Grasp;
using plugin::GraspAnswer;
using plugin::GraspMotion;

constexpr double kPi = M_PI;
// rad between the checks of a usable grasp's approach and lift: pick's dense check.
constexpr double kDenseResolution = 0.01;
// Degrees between the directions of the wide pass at the least.
constexpr double kWideStep = 10.0;

class SideGrasps final : public plugin::GraspSampler {
 public:
  void configure(const Parameters& p) override {
    directions_ = p.get_int("directions", directions_, "approach directions facing the robot", Range::closed(1, 64));
    spread_ = p.get_double("spread", spread_, "degrees either side of facing the robot", Range::closed(0, 180));
    wide_spread_ = p.get_double("wide_spread", wide_spread_,
                                "degrees either side, tried when nothing within spread is usable (0: off)",
                                Range::closed(0, 180));
    heights_ = p.get_vector("heights", heights_, "grasp heights, fractions of the object's height", Range::open(0, 1));
    p.require(!heights_.empty(), "heights", "must list at least one height");
    random_ = p.get_int("random", random_, "seeded random grasps besides the preset ones", Range::closed(0, 1000));
    approach_ = p.get_double("approach", approach_, "m from the pre-grasp to the grasp", Range::open(0, 1));
    lift_ = p.get_double("lift", lift_, "m the object is lifted", Range::closed_open(0, 1));
    clearance_ = p.get_double("clearance", clearance_, "m between each finger and the object", Range::closed_open(0, 0.05));
    tight_clearance_ = p.get_double("tight_clearance", tight_clearance_,
                                    "m, tried where the usual clearance touches a neighbour (at most clearance)",
                                    Range::at_least(0));
    p.require(tight_clearance_ <= clearance_, "tight_clearance", "must be at most clearance");
    steps_ = p.get_int("approach_steps", steps_, "collision checks along the approach at the least", Range::closed(1, 100));
    resolution_ = p.get_double("resolution", resolution_, "rad between collision checks", Range::open(0, 1));
    max_usable_ = p.get_int("max_usable", max_usable_, "usable grasps after which sampling stops", Range::at_least(1));
    base_distance_ = p.get_double("base_distance", base_distance_,
                                  "m from a mobile base to the grasp, placed behind it (0: off)", Range::closed_open(0, 3));
  }

  GraspAnswer sample(plugin::PlanningContext& context, const plugin::GraspQuery& query) override {
    GraspAnswer answer;
    // The world as the query has it, with nothing in the hand (a held object stays where it is).
    WorldState empty_handed = query.state;
    empty_handed.held.reset();
    const std::unique_ptr<plugin::WorldView> world = context.world_at(empty_handed);
    if (!world || !context.problem.robot.loaded) {
      answer.failure = Failure{"grasp", "the problem has no robot to grasp with", {}};
      return answer;
    }
    const robot::RobotDescription& robot = context.robot();
    const SceneObject& object = context.scene().objects.at(query.object);
    const Eigen::Isometry3d& world_T_object = query.state.world_T_objects.at(query.object);
    const auto half_width = graspable_half_width(object, world_T_object);
    if (!half_width) {
      answer.failure = Failure{"grasp", "'" + object.id + "' is not a standing cylinder or box the gripper can span", {}};
      return answer;
    }
    const robot::GripperParameters& gripper = robot.gripper();
    if (2 * *half_width > gripper.stroke) {
      answer.failure = Failure{"grasp", "'" + object.id + "' is wider than the gripper's stroke", {}};
      return answer;
    }
    const Eigen::Isometry3d base_T_world = context.scene().world_T_robot_base.inverse();
    const Eigen::VectorXd seed = query.state.robot_configuration.size() ? query.state.robot_configuration : robot.home();
    const auto mobile = base_distance_ > 0 ? manipulation::BasePlacement::of(robot) : std::nullopt;
    std::mt19937_64 rng(context.seed ^ (0x9e3779b97f4a7c15ull * (query.object + 1)));

    bool previous_unreachable = true;
    // Evaluates `tried` in order into `answer`, up to max_usable_ usable grasps.
    auto try_candidates = [&](const std::vector<Candidate>& tried) {
      for (const Candidate& c : tried) {
        // The wrist turned over (tool x up) is tried only where the upright one is out of reach.
        if (c.flipped && !previous_unreachable) continue;
        context.count(counter::samples);
        Grasp grasp = make_grasp(c, *half_width, object_height(object), world_T_object, gripper);
        const std::size_t blocked_before = answer.blocked.size();
        evaluate(context, *world, robot, mobile, base_T_world, seed, query.object, grasp, answer);
        if (answer.blocked.size() > blocked_before && answer.blocked.back().freeable && tight_clearance_ < clearance_) {
          // Objects may stand closer than the fingers' usual clearance (the paper's shelves
          // keep no gap): the same grasp with the fingers opened just enough.
          grasp.finger_open = std::min(gripper.stroke / 2, *half_width + tight_clearance_);
          GraspAnswer tight;
          evaluate(context, *world, robot, mobile, base_T_world, seed, query.object, grasp, tight);
          if (!tight.usable.empty()) {
            answer.blocked.pop_back();
            answer.usable.push_back(std::move(tight.usable.front()));
          } else if (tight.blocked.back().freeable &&
                     tight.blocked.back().blocking_objects.size() < answer.blocked.back().blocking_objects.size()) {
            answer.blocked.back() = std::move(tight.blocked.back());
          }
        }
        previous_unreachable = answer.blocked.size() > blocked_before && !answer.blocked.back().freeable &&
                               answer.blocked.back().reason.rfind("unreachable", 0) == 0;
        if (static_cast<std::int64_t>(answer.usable.size()) >= max_usable_) break;
      }
    };
    try_candidates(candidates(object, world_T_object, context.scene().world_T_robot_base, rng));
    // Two cylinders standing a few millimetres apart side by side block each other's
    // grasps from the front: from further round, across the line between them, they
    // may come free (the paper's shelves keep no gap between objects).
    if (answer.usable.empty()) try_candidates(wide_candidates(object, world_T_object, context.scene().world_T_robot_base));
    if (answer.usable.empty()) {
      const BlockedGrasp* best = answer.least_blocked();
      Failure failure{"grasp", "no usable grasp of '" + object.id + "'", {}};
      if (best) {
        failure.blocking_objects = best->blocking_objects;
        failure.reason += "; the least blocked grasp is blocked by " + std::to_string(best->blocking_objects.size()) +
                          " object(s) (" + best->reason + ")";
      }
      answer.failure = failure;
    }
    return answer;
  }

 private:
  struct Candidate {
    double yaw;     // approach direction, world frame
    double height;  // fraction of the object's height
    bool flipped;   // tool x up instead of down
  };

  static double object_height(const SceneObject& o) {
    if (const auto* c = std::get_if<Cylinder>(&o.shape)) return c->height;
    if (const auto* b = std::get_if<Box>(&o.shape)) return b->size.z();
    return 0.0;
  }

  // Half the width the fingers must span, for objects standing upright.
  static std::optional<double> graspable_half_width(const SceneObject& o, const Eigen::Isometry3d& pose) {
    if (std::abs(pose.linear()(2, 2)) < 1 - 1e-6) return std::nullopt;
    if (const auto* c = std::get_if<Cylinder>(&o.shape)) return c->radius;
    if (const auto* b = std::get_if<Box>(&o.shape)) return std::min(b->size.x(), b->size.y()) / 2;
    return std::nullopt;
  }

  std::vector<Candidate> candidates(const SceneObject& object, const Eigen::Isometry3d& world_T_object,
                                    const Eigen::Isometry3d& world_T_base, std::mt19937_64& rng) const {
    // Face the robot: approach along the direction from the robot base to the object.
    const Eigen::Vector2d d = (world_T_object.translation() - world_T_base.translation()).head<2>();
    const double facing = std::atan2(d.y(), d.x());
    const double spread = spread_ * kPi / 180.0;
    std::vector<double> yaws;
    // All around (spread 180): `directions_` evenly over the circle, -180 and 180 once.
    const bool circle = spread_ >= 180.0 - 1e-9;
    for (std::int64_t i = 0; i < directions_; ++i) {
      if (directions_ == 1) {
        yaws.push_back(facing);
      } else if (circle) {
        yaws.push_back(facing + std::remainder(2 * kPi * double(i) / double(directions_), 2 * kPi));
      } else {
        yaws.push_back(facing - spread + 2 * spread * double(i) / double(directions_ - 1));
      }
    }
    // Straight-on first: it is the most likely to be free.
    std::stable_sort(yaws.begin(), yaws.end(), [&](double a, double b) { return std::abs(a - facing) < std::abs(b - facing); });
    if (const auto* box = std::get_if<Box>(&object.shape)) {
      // Boxes are held across their narrow side: approach along the long axis' normal.
      const Eigen::Vector3d x = world_T_object.linear().col(0);
      const double axis = std::atan2(x.y(), x.x()) + (box->size.x() <= box->size.y() ? kPi / 2 : 0.0);
      yaws.clear();
      for (double k : {0.0, 1.0}) {
        const double yaw = axis + k * kPi;
        if (std::abs(std::remainder(yaw - facing, 2 * kPi)) <= spread + 1e-9) yaws.push_back(yaw);
      }
    }
    std::vector<Candidate> out;
    for (double yaw : yaws) {
      for (double h : heights_) {
        out.push_back({yaw, h, false});
        out.push_back({yaw, h, true});
      }
    }
    std::uniform_real_distribution<double> yaw(facing - spread, facing + spread), height(0.3, 0.7);
    for (std::int64_t i = 0; i < random_ && !std::holds_alternative<Box>(object.shape); ++i) {
      const double y = yaw(rng), h = height(rng);
      out.push_back({y, h, false});  // upright first; turned over only where it is out of reach
      out.push_back({y, h, true});
    }
    return out;
  }

  // Beyond +-spread, in the ring's steps (at least kWideStep), out to +-wide_spread of
  // facing the robot: tried only when no grasp within the spread is usable. Upright
  // cylinders only (a box has its own two sides).
  std::vector<Candidate> wide_candidates(const SceneObject& object, const Eigen::Isometry3d& world_T_object,
                                         const Eigen::Isometry3d& world_T_base) const {
    std::vector<Candidate> out;
    if (!std::holds_alternative<Cylinder>(object.shape) || directions_ < 2 || spread_ >= 180.0 - 1e-9) return out;
    const Eigen::Vector2d d = (world_T_object.translation() - world_T_base.translation()).head<2>();
    const double facing = std::atan2(d.y(), d.x());
    const double step = std::max(kWideStep, 2 * spread_ / double(directions_ - 1));
    for (double off = spread_ + step; off <= wide_spread_ + 1e-9; off += step) {
      for (double side : {-1.0, 1.0}) {
        for (double h : heights_) {
          out.push_back({facing + side * off * kPi / 180.0, h, false});
          out.push_back({facing + side * off * kPi / 180.0, h, true});
        }
      }
    }
    return out;
  }

  Grasp make_grasp(const Candidate& c, double half_width, double height, const Eigen::Isometry3d& world_T_object,
                   const robot::GripperParameters& gripper) const {
    const Eigen::Vector3d approach(std::cos(c.yaw), std::sin(c.yaw), 0.0);
    const Eigen::Vector3d x = c.flipped ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d(-Eigen::Vector3d::UnitZ());
    Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();
    tool.linear().col(0) = x;
    tool.linear().col(1) = approach.cross(x);
    tool.linear().col(2) = approach;
    tool.translation() = world_T_object.translation();
    tool.translation().z() += (c.height - 0.5) * height;
    Grasp g;
    g.world_T_gripper = tool;
    g.world_T_pregrasp = tool;
    g.world_T_pregrasp.translation() -= approach_ * approach;
    g.world_T_lift = tool;
    g.world_T_lift.translation().z() += lift_;
    g.gripper_T_object = tool.inverse() * world_T_object;
    g.finger_open = std::min(gripper.stroke / 2, half_width + clearance_);
    g.finger_closed = half_width;
    return g;
  }

  // One IK solution through the grasp, and how the pre-grasp and lift near it are solved.
  struct Branch {
    Eigen::VectorXd q_grasp;
    const manipulation::BasePlacement* placed;  // the base placed, the arm solved alone; null: the whole robot
  };

  // The IK solutions through the grasp that are checked. A mobile base first stands
  // behind the grasp with the arm solved alone (Tian et al., Section V-B): IK of the
  // whole robot from where it is leaves the base wherever its steps end, often in the
  // table. Then the whole robot from where it stands: the near side is often better
  // reached from there, and a fixed base has only this.
  std::vector<Branch> ik_branches(const plugin::WorldView& world, const robot::RobotDescription& robot, const std::optional<manipulation::BasePlacement>& mobile,
                                  const Eigen::Isometry3d& base_T_world, const Eigen::VectorXd& open_seed,
                                  const Grasp& grasp) const {
    std::vector<Branch> branches;
    if (mobile) {
      // Placing the base looks at fixed and self contacts: the world behind the view.
      for (Eigen::VectorXd& q : mobile->solve(collision::synced_world(world), collision::view_checker(world),
                                              grasp.world_T_gripper, open_seed, base_distance_, 1)) {
        branches.push_back({std::move(q), &*mobile});
      }
    }
    auto whole = robot.ik().solve(base_T_world * grasp.world_T_gripper, open_seed);
    for (std::size_t i = 0; i < whole.size() && i < 2; ++i) branches.push_back({std::move(whole[i]), nullptr});
    return branches;
  }

  // Per IK branch, the pre-grasp and lift nearest to it; checks the approach (fingers
  // open, the object itself ignored), the grasp and the lift (object held). Files the
  // grasp as usable or blocked, with the objects in the way.
  void evaluate(plugin::PlanningContext& context, const plugin::WorldView& world, const robot::RobotDescription& robot, const std::optional<manipulation::BasePlacement>& mobile,
                const Eigen::Isometry3d& base_T_world, const Eigen::VectorXd& seed, ObjectIndex object, Grasp& grasp,
                GraspAnswer& answer) const {
    const auto finger = robot.finger_variable();
    Eigen::VectorXd open_seed = seed;
    if (finger) open_seed[*finger] = grasp.finger_open;
    const std::vector<Branch> branches = ik_branches(world, robot, mobile, base_T_world, open_seed, grasp);
    for (const Branch& b : branches) grasp.ik_solutions.push_back(b.q_grasp);
    if (grasp.ik_solutions.empty()) {
      answer.blocked.push_back({grasp, {}, "unreachable: no IK solution", false});
      return;
    }
    // The best failed branch: freeable first, then fewest blocking objects.
    collision::ObjectSet blocking;
    bool freeable = false, any_branch = false;
    std::string why = "unreachable: the approach or lift leaves the workspace";
    const ObjectIndex ignore_target[] = {object};
    for (const Branch& branch : branches) {
      const Eigen::VectorXd& q_grasp = branch.q_grasp;
      auto near = [&](const Eigen::Isometry3d& world_T_tool) {
        return branch.placed ? branch.placed->solve_arm(context.scene().world_T_robot_base, world_T_tool, q_grasp)
                             : robot.ik().solve(base_T_world * world_T_tool, q_grasp);
      };
      const auto pre = near(grasp.world_T_pregrasp);
      const auto lift = near(grasp.world_T_lift);
      if (pre.empty() || lift.empty() || (pre[0] - q_grasp).cwiseAbs().maxCoeff() > 0.8 ||
          (lift[0] - q_grasp).cwiseAbs().maxCoeff() > 0.8) {
        continue;  // not one continuous branch
      }
      GraspMotion motion{pre[0], q_grasp, lift[0]};
      if (finger) motion.lift[*finger] = grasp.finger_closed;
      collision::ObjectSet objects;
      bool hits_fixed = false, self = false;
      std::string fixed_contacts;  // which link met which fixed body, first time seen
      auto check = [&](const plugin::WorldView& at, const Eigen::VectorXd& q, std::span<const ObjectIndex> ignored) {
        context.count(counter::collision_checks);
        const plugin::Contacts r = at.contacts(q, ignored);
        objects.insert(objects.end(), r.objects.begin(), r.objects.end());
        if (r.fixed && !hits_fixed) fixed_contacts = at.describe_fixed_contacts(q);
        hits_fixed = hits_fixed || r.fixed;
        self = self || r.self;
      };
      // Straight joint-space segments, checked every `resolution_` radians; a blocked
      // segment reports the objects at a few of its colliding steps.
      auto segment = [&](const plugin::WorldView& at, const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                         std::span<const ObjectIndex> ignored, double resolution) {
        const int n = std::max<int>(static_cast<int>(steps_),
                                    static_cast<int>(std::ceil((b - a).cwiseAbs().maxCoeff() / resolution)));
        int blocked_at = -1;
        for (int s = 0; s <= n && blocked_at < 0; ++s) {
          context.count(counter::collision_checks);
          if (!at.is_valid(a + (b - a) * (double(s) / n), ignored)) blocked_at = s;
        }
        if (blocked_at < 0) return;
        // What is in the way: the full collision sets where it was met (so that a blocked
        // segment never reads as free), at both ends and in the middle.
        check(at, a + (b - a) * (double(blocked_at) / n), ignored);
        for (int r = 0; r <= 2; ++r) check(at, a + (b - a) * (r / 2.0), ignored);
      };
      Eigen::VectorXd closed = motion.grasp;
      if (finger) closed[*finger] = grasp.finger_closed;
      auto both = [&](double resolution) {
        segment(world, motion.pregrasp, motion.grasp, ignore_target, resolution);
        segment(*world.holding(object, grasp.gripper_T_object), closed, motion.lift, {}, resolution);
      };
      both(resolution_);
      // A grasp free at the coarse resolution is checked as densely as pick checks it
      // (kDenseResolution): else it would be offered as usable and then fail there, with
      // nothing to blame, while a truly free grasp was never sampled.
      if (objects.empty() && !hits_fixed && !self && resolution_ > kDenseResolution) both(kDenseResolution);
      std::sort(objects.begin(), objects.end());
      objects.erase(std::unique(objects.begin(), objects.end()), objects.end());
      if (objects.empty() && !hits_fixed && !self) {
        grasp.motions.push_back(motion);
        answer.usable.push_back(grasp);
        return;
      }
      const bool branch_freeable = !hits_fixed && !self;
      if (!any_branch || (branch_freeable && (!freeable || objects.size() < blocking.size()))) {
        blocking = objects;
        freeable = branch_freeable;
        why = hits_fixed ? "fixed geometry is in the way: " + fixed_contacts
              : self     ? "the arm would hit itself"
                         : "movable objects are in the way";
      }
      any_branch = true;
    }
    answer.blocked.push_back({grasp, blocking, why, freeable});
  }

  std::int64_t directions_ = 7;
  double spread_ = 60.0;  // degrees either side of facing the robot
  double wide_spread_ = 100.0;  // degrees either side, tried when nothing within spread_ is usable
  std::vector<double> heights_{0.5, 0.35, 0.65};
  std::int64_t random_ = 4;
  double approach_ = 0.10;
  double lift_ = 0.03;
  double clearance_ = 0.008;
  double tight_clearance_ = 0.002;  // m, the fingers' opening tried where clearance_ is blocked
  std::int64_t steps_ = 5;
  double resolution_ = 0.02;  // rad between checks along straight segments
  std::int64_t max_usable_ = 3;
  double base_distance_ = 0.0;  // m behind each grasp a mobile base is first placed; 0: off
};


}  // namespace

CLUTTERTAMP_EXPORT_GRASP_SAMPLER(SideGrasps, grasp_side, "Side grasps facing the robot, with the objects that block each",
                                 "1.0.0")
