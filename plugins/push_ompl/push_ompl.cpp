// push_ompl: push one object into a region (Papallas & Dogar, ICRA 2020, Section V-A).
// Two approach states are computed behind the object on the line to the region's
// centre (Fig. 2): the gripper's face towards the region, and its side edge towards it.
// First a quick pass tries a simulated feedback pusher (ours, not the paper's); then a
// kinodynamic search (RRT or KPIECE1 over the pushing physics) reaches either, then a
// second one pushes the object until its centre is in the region. Other objects may be
// pushed along the way; none may fall or leave the shelf.
#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "cluttertamp/physics/push_planning.hpp"
#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/push_sampler.hpp"

namespace {

using namespace cluttertamp;

std::string metres(double v) {
  std::ostringstream out;
  out.precision(3);
  out << v << " m";
  return out.str();
}

std::string xy(const Eigen::Vector2d& v) {
  std::ostringstream out;
  out.precision(3);
  out << "(" << v.x() << ", " << v.y() << ")";
  return out.str();
}

// The run's seed mixed with the query: the same query gives the same push (its budget
// is propagations; only the run's time limit, when it ends a search, can cut one short).
std::uint64_t query_seed(std::uint64_t seed, const plugin::PushQuery& q) {
  std::uint64_t h = seed ^ 0x9e3779b97f4a7c15ull;
  for (double v : {double(q.object), q.goal_xy.x(), q.goal_xy.y(), q.goal_radius, q.gripper.x(), q.gripper.y(), q.gripper.z()}) {
    h ^= std::hash<double>{}(v) + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
  }
  return h;
}

class PushOmpl final : public plugin::PushSampler {
 public:
  PushOmpl() {
    search_.steer = 0.3;
    search_.max_propagations = 10000;  // per query, both searches (about 8 s on our machine)
  }

  void configure(const Parameters& p) override {
    search_.read(p);
    gap_ = p.get_double("approach_gap", gap_, "m between the object's enclosing circle and the gripper at the approach",
                        Range::at_least(0));
    approach_position_ = p.get_double("approach_position", approach_position_,
                                      "m from an approach state within which the approach is reached", Range::above(0));
    approach_heading_ = p.get_double("approach_heading", approach_heading_,
                                     "rad from an approach state's heading within which the approach is reached",
                                     Range::above(0));
    approach_share_ = p.get_double("approach_share", approach_share_,
                                   "share of the query's propagations for the approach, at most", Range::open(0, 1));
    quick_rounds_ = static_cast<int>(
        p.get_int("quick_rounds", quick_rounds_, "rounds of the quick feedback pass (0: none)", Range::at_least(0)));
    quick_stroke_ = p.get_double("quick_stroke", quick_stroke_, "m the quick pass pushes per round, at most",
                                 Range::above(0));
  }

  plugin::PushAnswer push(plugin::PlanningContext& context, const plugin::PushQuery& q) override {
    plugin::PushAnswer answer;
    const Scene& scene = context.scene();
    const WorldState& before = q.state;
    const physics::PushWorld world(scene, before, physics::push_settings(context.problem));
    const std::string& id = scene.objects.at(q.object).id;
    const auto fail = [&](const std::string& reason, std::vector<ObjectIndex> blocking = {}) {
      answer.failure = Failure{"push", reason, std::move(blocking)};
      return answer;
    };
    if (!std::binary_search(world.pushable().begin(), world.pushable().end(), q.object)) {
      return fail("'" + id + "' cannot be pushed: it is fixed or no longer in the scene");
    }
    if (!world.support_region().contains(q.goal_xy)) {
      return fail("the goal " + xy(q.goal_xy) + " for '" + id + "' is off the support the target stands on");
    }
    const physics::PushState start = world.state_of(before, q.gripper);
    const physics::ObjectInRegionGoal in_region(world, q.object, q.goal_xy, q.goal_radius);
    if (in_region.distance(start) <= q.goal_radius) return done(world, physics::PushPath{{start}, {}, search_.step}, before, answer);

    std::string quick_failure;
    if (quick_rounds_ > 0) {
      if (auto path = quick_push(world, start, q, context.deadline, quick_failure)) {
        context.count(counter::quick_pushes);
        return done(world, *path, before, answer);
      }
    }
    const std::uint64_t seed = query_seed(context.seed, q);
    // The query's budget: the sampler's own, at most the query's; the approach gets its
    // share, the push the rest.
    const physics::PushBudget budget = physics::PushBudget::of(
        search_, context.deadline.remaining(), q.max_propagations > 0 ? q.max_propagations : physics::PushBudget::kNone);
    const std::vector<Eigen::Vector3d> approaches = approach_states(world, start, q);
    if (approaches.empty()) {
      return fail("no approach to '" + id + "' towards " + xy(q.goal_xy) + " within the pusher's yaw limits");
    }
    const physics::GripperPoseGoal approach(world, approaches, approach_position_, approach_heading_);
    const auto approached = physics::plan_pushes(world, start, approach, search_, budget.share(approach_share_), seed);
    context.count(counter::propagations, approached.propagations);
    if (!approached.path) {
      return fail("no approach to '" + id + "' (face or side towards " + xy(q.goal_xy) + "): " + approached.reason +
                  quick_note(quick_failure));
    }
    const auto pushed = physics::plan_pushes(world, approached.path->states.back(), in_region, search_,
                                             budget.after(approached.propagations, context.deadline.remaining()), seed + 1);
    context.count(counter::propagations, pushed.propagations);
    if (!pushed.path) {
      return fail("approached '" + id + "' but could not push it within " + metres(q.goal_radius) + " of " +
                  xy(q.goal_xy) + ": " + pushed.reason + quick_note(quick_failure));
    }
    physics::PushPath path = *approached.path;
    path.states.insert(path.states.end(), pushed.path->states.begin() + 1, pushed.path->states.end());
    path.controls.insert(path.controls.end(), pushed.path->controls.begin(), pushed.path->controls.end());
    return done(world, path, before, answer);
  }

 private:
  // Fig. 2: hand poses at a point behind the object on the line from the region's
  // centre through it, as far from the object's centre as its enclosing circle plus a
  // gap plus the hand's reach ahead (the fingertips: face towards the region) or half
  // width (side edge towards it: the floating gripper's side's middle, palm and finger,
  // facing the object; an arm's hand with its tool on the line, turned either way, so
  // that a base turning within its limits still pushes sideways). Those the pusher's
  // yaw limits allow.
  std::vector<Eigen::Vector3d> approach_states(const physics::PushWorld& world, const physics::PushState& s,
                                               const plugin::PushQuery& q) const {
    const Eigen::Vector2d object = s.objects.at(q.object).pose.head<2>();
    const Eigen::Vector2d dir = (q.goal_xy - object).normalized();
    const Eigen::Vector2d across(-dir.y(), dir.x());
    const double yaw = std::atan2(dir.y(), dir.x());
    const double r = world.footprint_radius(q.object) + gap_;
    const physics::PushSettings& g = world.settings();
    const Eigen::Vector2d face = object - (r + ahead(world)) * dir;
    std::vector<Eigen::Vector3d> states{{face.x(), face.y(), yaw}};
    if (!g.arm) {
      // Turned +90 degrees, the gripper's x is `across`: its side's middle lies at x =
      // finger_length / 2 in its frame.
      const Eigen::Vector2d side = object - (r + g.gripper_size.y() / 2) * dir - g.finger_length / 2 * across;
      states.push_back({side.x(), side.y(), std::remainder(yaw + M_PI / 2, 2 * M_PI)});
    } else {
      const Eigen::Vector2d side = object - (r + world.hand_half_width()) * dir;
      for (const double turn : {M_PI / 2, -M_PI / 2}) states.push_back({side.x(), side.y(), std::remainder(yaw + turn, 2 * M_PI)});
    }
    std::erase_if(states, [&](const Eigen::Vector3d& hand) { return !world.hand_heading_allowed(hand.z()); });
    return states;
  }

  // Controls that carry the hand from where pose `from` puts it to `to` on a straight
  // line, turning evenly. An arm's base turned in one straight control would swing the
  // hand on its lever: its way is cut into pieces of at most 0.05 rad of turn (the hand
  // then strays at most lever x 0.0003 from the line).
  std::vector<physics::PushControl> hand_controls(const physics::PushWorld& world, const Eigen::Vector3d& from,
                                                  const Eigen::Vector3d& to) const {
    if (!world.settings().arm) return physics::straight_controls(from, to, search_);  // the gripper is its hand
    const Eigen::Vector3d target = world.pose_for_hand(to);
    const Eigen::Vector3d start = world.hand(from);
    Eigen::Vector3d delta = to - start;
    delta.z() = std::remainder(delta.z(), 2 * M_PI);
    const int pieces = std::max(1, static_cast<int>(std::ceil(std::abs(delta.z()) / 0.05)));
    std::vector<physics::PushControl> controls;
    Eigen::Vector3d at = from;
    for (int k = 1; k <= pieces; ++k) {
      const Eigen::Vector3d next = k == pieces ? target : world.pose_for_hand(start + delta * (double(k) / pieces));
      const std::vector<physics::PushControl> piece = physics::straight_controls(at, next, search_);
      controls.insert(controls.end(), piece.begin(), piece.end());
      at = next;
    }
    return controls;
  }

  // How far the hand reaches ahead of its point: the fingertips (or the palm's face).
  static double ahead(const physics::PushWorld& world) {
    const physics::PushSettings& g = world.settings();
    return g.arm ? world.hand_face() : g.gripper_size.x() / 2 + g.finger_length;
  }

  // The quick pass, before any search: a feedback pusher simulated in the physics.
  // Each round lines the gripper up behind the object on its line to the region's
  // centre, face towards it, and pushes at most `quick_stroke` along that line. Of the
  // ways to line up (line_up_routes) it takes the valid one that disturbs the fewest
  // other objects. Null, with `why`, when no way or the push is valid, the deadline
  // passes, or the object is
  // not in the region after quick_rounds rounds.
  std::optional<physics::PushPath> quick_push(const physics::PushWorld& world, const physics::PushState& start,
                                              const plugin::PushQuery& q, const plugin::Deadline& deadline,
                                              std::string& why) const {
    // Lined up with the fingertips a gap behind the object; the push then carries it
    // in the pocket, against the palm.
    const physics::PushSettings& g = world.settings();
    const double standoff = world.footprint_radius(q.object) + ahead(world) + gap_;
    // In front of the shelf, the hand may turn without reaching into it.
    const double front = world.support_region().min().x() - std::hypot(ahead(world), g.gripper_size.y() / 2) - gap_;
    const double fingers = g.arm ? 0.0 : g.finger_length;
    physics::PushPath path{{start}, {}, search_.step};
    for (int round = 0; round < quick_rounds_; ++round) {
      if (deadline.expired()) {
        why = "time limit reached in round " + std::to_string(round + 1);
        return std::nullopt;
      }
      const physics::PushState& s = path.states.back();
      const Eigen::Vector2d object = s.objects[q.object].pose.head<2>();
      const Eigen::Vector2d to_goal = q.goal_xy - object;
      if (to_goal.norm() <= q.goal_radius) return path;
      const Eigen::Vector2d dir = to_goal.normalized();
      const double yaw = std::atan2(dir.y(), dir.x());
      const Eigen::Vector3d behind(object.x() - standoff * dir.x(), object.y() - standoff * dir.y(), yaw);
      std::optional<physics::PushPath> best;
      std::size_t best_disturbed = 0;
      for (const std::vector<Eigen::Vector3d>& route : line_up_routes(world.hand(s.gripper), behind, front, fingers + 0.03)) {
        if (deadline.expired()) break;
        physics::PushPath lined{{s}, {}, search_.step};
        bool ok = true;
        for (const Eigen::Vector3d& waypoint : route) {
          ok = ok && world.hand_heading_allowed(waypoint.z()) &&
               physics::simulate(world, lined, hand_controls(world, lined.states.back().gripper, waypoint));
        }
        if (!ok) continue;
        const std::size_t disturbed = disturbed_objects(s, lined.states.back(), q.object);
        if (!best || disturbed < best_disturbed) {
          best = std::move(lined);
          best_disturbed = disturbed;
        }
      }
      if (!best) {
        why = "round " + std::to_string(round + 1) +
              (deadline.expired() ? ": time limit reached" : ": no valid way to line up behind it");
        return std::nullopt;
      }
      const physics::PushState& lined_up = best->states.back();
      const Eigen::Vector2d now = q.goal_xy - lined_up.objects[q.object].pose.head<2>();
      // The fingers pass the object first: it moves once the palm's face meets it.
      const double stroke = std::min(quick_stroke_, std::max(0.0, now.dot(dir))) + fingers + gap_;
      const Eigen::Vector3d pushed = lined_up.gripper + Eigen::Vector3d(stroke * dir.x(), stroke * dir.y(), 0.0);
      if (!physics::simulate(world, *best, physics::straight_controls(lined_up.gripper, pushed, search_))) {
        why = "round " + std::to_string(round + 1) +
              ": the push made an object fall or leave the shelf, or the gripper hit a wall or left its region";
        return std::nullopt;
      }
      path.states.insert(path.states.end(), best->states.begin() + 1, best->states.end());
      path.controls.insert(path.controls.end(), best->controls.begin(), best->controls.end());
    }
    const Eigen::Vector2d object = path.states.back().objects[q.object].pose.head<2>();
    if ((q.goal_xy - object).norm() <= q.goal_radius) return path;
    why = "after " + std::to_string(quick_rounds_) + " rounds it is " + metres((q.goal_xy - object).norm()) +
          " from the centre";
    return std::nullopt;
  }

  static std::string quick_note(const std::string& why) {
    return why.empty() ? "" : " (the quick pass failed first: " + why + ")";
  }

  // Ways from the hand pose `g` to the hand pose `behind`, as waypoints: straight there,
  // turning on the way; turning first, then straight; straight, then turning; and, from
  // inside the shelf (front of it at x = `front`), backing `back_off` m away from what
  // the palm touches (out of the fingers), out to the front, across and in.
  static std::vector<std::vector<Eigen::Vector3d>> line_up_routes(const Eigen::Vector3d& g, const Eigen::Vector3d& behind,
                                                                  double front, double back_off) {
    std::vector<std::vector<Eigen::Vector3d>> routes{
        {behind}, {{g.x(), g.y(), behind.z()}, behind}, {{behind.x(), behind.y(), g.z()}, behind}};
    if (g.x() > front) {
      const Eigen::Vector3d back(g.x() - back_off * std::cos(g.z()), g.y() - back_off * std::sin(g.z()), g.z());
      routes.push_back({back, {front, back.y(), g.z()}, {front, behind.y(), behind.z()}, behind});
    }
    return routes;
  }

  // Objects other than `pushed` that moved more than 1 cm between two states.
  static std::size_t disturbed_objects(const physics::PushState& a, const physics::PushState& b, ObjectIndex pushed) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.objects.size(); ++i) {
      n += i != pushed && (a.objects[i].pose.head<2>() - b.objects[i].pose.head<2>()).norm() > 0.01;
    }
    return n;
  }

  plugin::PushAnswer& done(const physics::PushWorld& world, const physics::PushPath& path, const WorldState& before,
                           plugin::PushAnswer& answer) const {
    physics::PushPath p = path;
    p.step = search_.step;
    answer.step = physics::push_step(world, p, before);
    answer.resulting_state = physics::world_state_of(before, p.states.back());
    answer.gripper_end = p.states.back().gripper;
    return answer;
  }

  physics::KinodynamicSettings search_;
  double gap_ = 0.01;                // m between the object's enclosing circle and the gripper at the approach
  double approach_position_ = 0.02;  // m: approach reached within this of an approach state
  double approach_heading_ = 0.2;    // rad
  double approach_share_ = 0.5;      // of the query's propagations, at most, for the approach
  int quick_rounds_ = 6;             // of the quick pass; 0: none
  double quick_stroke_ = 0.08;       // m: the quick pass pushes at most this far per round
};

}  // namespace

CLUTTERTAMP_EXPORT_PUSH_SAMPLER(PushOmpl, push_ompl,
                                "Push an object into a region: approach states behind it (face or side towards the "
                                "region), then kinodynamic RRT or KPIECE1 over the pushing physics (Papallas & Dogar 2020)",
                                "0.1.0")
