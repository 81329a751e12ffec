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
#include "cluttertamp/manipulation/grasp_check.hpp"
#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"

namespace {

using namespace cluttertamp;
using plugin::BlockedGrasp;
using plugin::Grasp;
using plugin::GraspAnswer;
using plugin::GraspMotion;

constexpr double kPi = M_PI;
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
    const Eigen::VectorXd seed = query.state.robot_configuration.size() ? query.state.robot_configuration : robot.home();
    const manipulation::GraspChecker checker(context, *world, query.object, seed,
                                             {steps_, resolution_, base_distance_});
    std::mt19937_64 rng(context.seed ^ (0x9e3779b97f4a7c15ull * (query.object + 1)));

    bool previous_unreachable = true;
    // Evaluates `tried` in order into `answer`, up to max_usable_ usable grasps.
    auto try_candidates = [&](const std::vector<Candidate>& tried) {
      for (const Candidate& c : tried) {
        // The wrist turned over (tool x up) is tried only where the upright one is out of reach.
        if (c.flipped && !previous_unreachable) continue;
        context.count(counter::samples);
        Grasp grasp = make_grasp(c, object_height(object), object, world_T_object, gripper);
        const std::size_t blocked_before = answer.blocked.size();
        checker.check(grasp, answer);
        if (answer.blocked.size() > blocked_before && answer.blocked.back().freeable && tight_clearance_ < clearance_) {
          // Objects may stand closer than the fingers' usual clearance (the paper's shelves
          // keep no gap): the same grasp with the fingers opened just enough.
          grasp.finger_open = std::min(gripper.stroke / 2, *half_width + tight_clearance_);
          GraspAnswer tight;
          checker.check(grasp, tight);
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
    if (answer.usable.empty()) answer.failure = manipulation::GraspChecker::no_usable_grasp(object.id, answer);
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

  Grasp make_grasp(const Candidate& c, double height, const SceneObject& object, const Eigen::Isometry3d& world_T_object,
                   const robot::GripperParameters& gripper) const {
    const Eigen::Vector3d approach(std::cos(c.yaw), std::sin(c.yaw), 0.0);
    const Eigen::Vector3d x = c.flipped ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d(-Eigen::Vector3d::UnitZ());
    Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();
    tool.linear().col(0) = x;
    tool.linear().col(1) = approach.cross(x);
    tool.linear().col(2) = approach;
    tool.translation() = world_T_object.translation();
    tool.translation().z() += (c.height - 0.5) * height;
    return manipulation::grasp_at(object, world_T_object, tool, gripper.stroke, approach_, lift_, clearance_);
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
