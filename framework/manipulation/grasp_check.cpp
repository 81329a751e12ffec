#include "cluttertamp/manipulation/grasp_check.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/robot/ik.hpp"
#include "cluttertamp/robot/robot_description.hpp"

namespace cluttertamp::manipulation {

namespace {
// rad between the checks of a grasp's approach and lift that looked free: pick's dense check.
constexpr double kDenseResolution = 0.01;
// rad a joint may change between the grasp and its pre-grasp or lift on one IK branch.
constexpr double kBranchJump = 0.8;
}  // namespace

// One IK solution through the grasp, and how the pre-grasp and lift near it are solved.
struct GraspChecker::Branch {
  Eigen::VectorXd q_grasp;
  const BasePlacement* placed;  // the base placed, the arm solved alone; null: the whole robot
};

GraspChecker::GraspChecker(plugin::PlanningContext& context, const plugin::WorldView& world, ObjectIndex object,
                           Eigen::VectorXd seed, GraspCheckSettings settings)
    : context_(context),
      world_(world),
      object_(object),
      seed_(std::move(seed)),
      settings_(settings),
      mobile_(settings.base_distance > 0 ? BasePlacement::of(context.robot()) : std::nullopt),
      base_T_world_(context.robot().world_T_ik_base(context.scene().world_T_robot_base).inverse()) {}

// A mobile base first stands behind the grasp with the arm solved alone (Tian et al.,
// Section V-B): IK of the whole robot from where it is leaves the base wherever its
// steps end, often in the table. Then the whole robot from where it stands: the near
// side is often better reached from there, and a fixed base has only this.
std::vector<GraspChecker::Branch> GraspChecker::ik_branches(const Eigen::VectorXd& open_seed,
                                                            const plugin::Grasp& grasp) const {
  std::vector<Branch> branches;
  if (mobile_) {
    // Placing the base looks at fixed and self contacts: the world behind the view.
    for (Eigen::VectorXd& q : mobile_->solve(collision::synced_world(world_), collision::view_checker(world_),
                                             grasp.world_T_gripper, open_seed, settings_.base_distance, 1)) {
      branches.push_back({std::move(q), &*mobile_});
    }
  }
  auto whole = context_.robot().ik().solve(base_T_world_ * grasp.world_T_gripper, open_seed);
  for (std::size_t i = 0; i < whole.size() && i < 2; ++i) branches.push_back({std::move(whole[i]), nullptr});
  return branches;
}

void GraspChecker::check(plugin::Grasp grasp, plugin::GraspAnswer& answer) const {
  const robot::RobotDescription& robot = context_.robot();
  const auto finger = robot.finger_variable();
  Eigen::VectorXd open_seed = seed_;
  if (finger) open_seed[*finger] = grasp.finger_open;
  const std::vector<Branch> branches = ik_branches(open_seed, grasp);
  for (const Branch& b : branches) grasp.ik_solutions.push_back(b.q_grasp);
  if (grasp.ik_solutions.empty()) {
    answer.blocked.push_back({grasp, {}, "unreachable: no IK solution", false});
    return;
  }
  // The best failed branch: freeable first, then fewest blocking objects.
  std::vector<ObjectIndex> blocking;
  bool freeable = false, any_branch = false;
  std::string why = "unreachable: the approach or lift leaves the workspace";
  const ObjectIndex ignore_target[] = {object_};
  for (const Branch& branch : branches) {
    const Eigen::VectorXd& q_grasp = branch.q_grasp;
    auto near = [&](const Eigen::Isometry3d& world_T_tool) {
      return branch.placed ? branch.placed->solve_arm(context_.scene().world_T_robot_base, world_T_tool, q_grasp)
                           : robot.ik().solve(base_T_world_ * world_T_tool, q_grasp);
    };
    const auto pre = near(grasp.world_T_pregrasp);
    const auto lift = near(grasp.world_T_lift);
    if (pre.empty() || lift.empty() || (pre[0] - q_grasp).cwiseAbs().maxCoeff() > kBranchJump ||
        (lift[0] - q_grasp).cwiseAbs().maxCoeff() > kBranchJump) {
      continue;  // not one continuous branch
    }
    plugin::GraspMotion motion{pre[0], q_grasp, lift[0]};
    if (finger) motion.lift[*finger] = grasp.finger_closed;
    std::vector<ObjectIndex> objects;
    bool hits_fixed = false, self = false;
    std::string fixed_contacts;  // which link met which fixed body, first time seen
    auto contacts_at = [&](const plugin::WorldView& at, const Eigen::VectorXd& q, std::span<const ObjectIndex> ignored) {
      context_.count(counter::collision_checks);
      const plugin::Contacts r = at.contacts(q, ignored);
      objects.insert(objects.end(), r.objects.begin(), r.objects.end());
      if (r.fixed && !hits_fixed) fixed_contacts = at.describe_fixed_contacts(q);
      hits_fixed = hits_fixed || r.fixed;
      self = self || r.self;
    };
    // A straight joint-space segment checked every `resolution` rad; a blocked segment
    // reports the full collision sets where it was met (so that a blocked segment never
    // reads as free), at both ends and in the middle.
    auto segment = [&](const plugin::WorldView& at, const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                       std::span<const ObjectIndex> ignored, double resolution) {
      const int n = std::max<int>(static_cast<int>(settings_.approach_steps),
                                  static_cast<int>(std::ceil((b - a).cwiseAbs().maxCoeff() / resolution)));
      int blocked_at = -1;
      for (int s = 0; s <= n && blocked_at < 0; ++s) {
        context_.count(counter::collision_checks);
        if (!at.is_valid(a + (b - a) * (double(s) / n), ignored)) blocked_at = s;
      }
      if (blocked_at < 0) return;
      contacts_at(at, a + (b - a) * (double(blocked_at) / n), ignored);
      for (int r = 0; r <= 2; ++r) contacts_at(at, a + (b - a) * (r / 2.0), ignored);
    };
    Eigen::VectorXd closed = motion.grasp;
    if (finger) closed[*finger] = grasp.finger_closed;
    auto both = [&](double resolution) {
      segment(world_, motion.pregrasp, motion.grasp, ignore_target, resolution);
      segment(*world_.holding(object_, grasp.gripper_T_object), closed, motion.lift, {}, resolution);
    };
    both(settings_.resolution);
    // A grasp free at the coarse resolution is checked as densely as pick checks it:
    // else it would be offered as usable and then fail there, with nothing to blame,
    // while a truly free grasp was never sampled.
    if (objects.empty() && !hits_fixed && !self && settings_.resolution > kDenseResolution) both(kDenseResolution);
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

Failure GraspChecker::no_usable_grasp(const std::string& object_id, const plugin::GraspAnswer& answer) {
  Failure failure{"grasp", "no usable grasp of '" + object_id + "'", {}};
  if (const plugin::BlockedGrasp* best = answer.least_blocked()) {
    failure.blocking_objects = best->blocking_objects;
    failure.reason += "; the least blocked grasp is blocked by " + std::to_string(best->blocking_objects.size()) +
                      " object(s) (" + best->reason + ")";
  } else if (!answer.blocked.empty()) {
    failure.reason += "; moving objects frees none (" + answer.blocked.front().reason + ")";
  }
  return failure;
}

plugin::Grasp grasp_at(const SceneObject& object, const Eigen::Isometry3d& world_T_object,
                       const Eigen::Isometry3d& world_T_gripper, double gripper_stroke, double approach, double lift,
                       double clearance) {
  double half_width = 0.0;
  if (const auto* c = std::get_if<Cylinder>(&object.shape)) half_width = c->radius;
  if (const auto* b = std::get_if<Box>(&object.shape)) half_width = std::min(b->size.x(), b->size.y()) / 2;
  if (const auto* s = std::get_if<Sphere>(&object.shape)) half_width = s->radius;
  plugin::Grasp g;
  g.world_T_gripper = world_T_gripper;
  g.world_T_pregrasp = world_T_gripper;
  g.world_T_pregrasp.translation() -= approach * world_T_gripper.linear().col(2);
  g.world_T_lift = world_T_gripper;
  g.world_T_lift.translation().z() += lift;
  g.gripper_T_object = world_T_gripper.inverse() * world_T_object;
  g.finger_open = std::min(gripper_stroke / 2, half_width + clearance);
  g.finger_closed = half_width;
  return g;
}

}  // namespace cluttertamp::manipulation
