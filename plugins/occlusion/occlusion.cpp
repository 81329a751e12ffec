// occlusion: retrieval when objects, even the target, are hidden behind others (Tian et
// al., Section V-A, Algorithm 4). The planner knows only what the scene's camera has
// observed (perception::ObservedWorld holds the truth). While the target is unseen it
// plans, on the roadmap and retrieval graph of the known objects, to a temporary goal
// x_temp behind the farthest known object, and removes the first object on the way;
// whatever that reveals is added to the roadmap (updated, not rebuilt) and it plans
// again. Once the target is seen, the goal becomes the target and the objects on the
// way are removed until it can be retrieved. Each removal is planned by the robot's
// samplers on the known world and checked against the truth: a motion that meets an
// unseen object finds it (it becomes known) and is planned again.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <set>

#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/perception/visibility.hpp"
#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/task_planner.hpp"
#include "cluttertamp/retrieval/removal_checker.hpp"
#include "cluttertamp/retrieval/roadmap.hpp"

namespace {

using namespace cluttertamp;
using retrieval::ObjectSet;
using Clock = std::chrono::steady_clock;

struct Settings {
  retrieval::RoadmapOptions roadmap;
  std::string region = "buffer";
  perception::VisibilitySettings visibility;
  int max_attempts = 3;  // removals of one object tried before it counts as blocked

  void read(const Parameters& p) {
    roadmap.read(p);
    region = p.get_string("region", region, "the scene's region removed objects are placed in");
    visibility.min_visible_fraction =
        p.get_double("min_visible", visibility.min_visible_fraction,
                     "fraction of an object's camera-facing surface seen for it to count as observed",
                     Range::open_closed(0, 1));
    visibility.horizontal_fov = p.get_double("horizontal_fov", visibility.horizontal_fov,
                                             "rad, the camera's full horizontal field of view", Range::open(0, M_PI));
    visibility.vertical_fov = p.get_double("vertical_fov", visibility.vertical_fov,
                                           "rad, the camera's full vertical field of view", Range::open(0, M_PI));
    max_attempts = static_cast<int>(p.get_int("max_attempts", max_attempts,
                                              "failed removals of one object before it is avoided (of the target: "
                                              "before the run ends)",
                                              Range::at_least(1)));
  }
};

class Run {
 public:
  Run(plugin::PlanningContext& context, const Settings& settings, const WorldState& initial)
      : context_(context), settings_(settings), scene_(context.scene()), initial_(initial),
        world_(scene_, initial, settings.visibility) {
    // What is known of the shelf comes from the objects seen at first: the board they
    // stand on bounds the search, and the target (whose model, not pose, is known)
    // would stand on it too.
    for (ObjectIndex o = 0; o < scene_.objects.size(); ++o) {
      if (world_.known(o) && !initial.removed[o]) seen_at_first_.push_back(o);
    }
    footprint_ = retrieval::held_footprint(context, initial, scene_.target);
    if (!seen_at_first_.empty()) {
      const ObjectIndex o = seen_at_first_.front();
      const double bottom = world_bounds(scene_.objects[o].shape, initial.world_T_objects[o]).min().z();
      const Eigen::AlignedBox3d target = world_bounds(scene_.objects[scene_.target].shape, Eigen::Isometry3d::Identity());
      footprint_.z_min = bottom;
      footprint_.z_max = bottom + target.sizes().z();
    }
  }

  Result run() {
    const auto start = Clock::now();
    Result result;
    count_known(result, counter::observed_initially);
    if (seen_at_first_.empty()) {
      result.reason = "the camera sees no object at the start: nothing to plan from";
      return result;
    }
    const Eigen::Vector2d x_s = scene_.world_T_exit.translation().head<2>();
    area_ = area();
    sync_roadmap();
    roadmap_ = std::make_unique<retrieval::Roadmap>(*collision::shared_world(context_), footprint_, area_, x_s, x_s, scene_.target, context_.seed);
    int limit = 1;
    roadmap_->expand(limit, settings_.roadmap);
    while (!context_.deadline.expired() && result.reason.empty()) {
      sync_roadmap();
      const std::optional<Goal> goal = next_goal();
      if (!goal) {
        result.reason = "the target was never seen, and there is no place behind an observed object left to look" +
                        std::string(unreachable_.empty() ? "" : " (" + std::to_string(unreachable_.size()) +
                                                                    " given up: no way there within the exploration limit)");
        break;
      }
      // An iteration of Algorithm 4: planning towards a new goal.
      if ((goal->x - roadmap_->graph()[1].x).norm() > 1e-9 || result.counters[counter::iterations] == 0) {
        roadmap_->move_goal(goal->x, settings_.roadmap);
        ++result.counters[counter::iterations];
      }
      std::optional<ObjectSet> order = way(limit);
      if (!order) {
        if (limit < known_movable()) {
          roadmap_->expand(++limit, settings_.roadmap);
          result.counters[counter::exploration_limit] = static_cast<std::uint64_t>(limit);
          continue;
        }
        // At the full limit an unjoined roadmap may only lack samples (a goal in a narrow
        // gap): it grows a few more times towards this goal before the goal is given up.
        if (extra_expansions_[goal->behind] < kExtraExpansions) {
          ++extra_expansions_[goal->behind];
          roadmap_->expand(limit, settings_.roadmap);
          ++result.counters[counter::extra_expansions];
          continue;
        }
        if (world_.known(scene_.target)) {
          // The graph's footprint is conservative and objects given up on stand in it
          // (one the target itself blocks, say): the robot may still get the target out.
          if (attempts_[scene_.target] < settings_.max_attempts) {
            ++result.counters[counter::retrievals_without_a_way];
            if (retrieve(result)) {
              mark_solved(result);
              break;
            }
            continue;
          }
          result.reason = "no way to the target within the exploration limit";
          break;
        }
        // No way behind this object: look behind the next one (next_goal skips it).
        unreachable_.insert(goal->behind);
        ++result.counters[counter::temporary_goals_given_up];
        continue;
      }
      if (order->empty() && world_.known(scene_.target)) {
        if (retrieve(result)) {
          mark_solved(result);
          break;
        }
        continue;
      }
      if (order->empty() && moved_.count(goal->behind)) {
        result.reason = "nothing left to take away in front of the temporary goal";
        break;
      }
      // Unseen target and a free way to x_temp: take away what x_temp looks behind.
      const ObjectIndex next = first_free(order->empty() ? goal->behind : order->front());
      remove(next, result);
    }
    if (!result.solved && result.reason.empty()) result.reason = "time limit reached before the target was retrieved";
    result.time.total = std::chrono::duration<double>(Clock::now() - start).count();
    result.time.motion_planning = motion_seconds_;
    result.time.task_planning = std::max(0.0, result.time.total - motion_seconds_);
    result.counters[counter::roadmap_nodes] = roadmap_->size();
    count_known(result, counter::observed);
    return result;
  }

 private:
  struct Goal {
    Eigen::Vector2d x;
    ObjectIndex behind = 0;  // the object a temporary goal lies behind
  };

  // The world the actions are planned in: the known objects where they are now.
  void sync() { collision::shared_world(context_)->sync(world_.belief()); }

  // The world the roadmap is queried in (it reads it live): every known object where it
  // stood at the start, moved ones too, as retrieval_graph keeps its initial world;
  // the retrieval graph discounts the moved ones (discounted()). Nodes and edges then
  // keep their collision sets consistent however many objects are taken away.
  void sync_roadmap() {
    WorldState state = initial_;
    for (ObjectIndex o = 0; o < scene_.objects.size(); ++o) state.removed[o] = initial_.removed[o] || !world_.known(o);
    state.held.reset();
    collision::shared_world(context_)->sync(state);
  }

  // Objects the retrieval graph does not count: unseen, or already taken away.
  std::vector<bool> discounted() const {
    std::vector<bool> out(scene_.objects.size());
    for (ObjectIndex o = 0; o < scene_.objects.size(); ++o) out[o] = !world_.known(o) || moved_.count(o) || initial_.removed[o];
    return out;
  }

  void count_known(Result& result, const std::string& key) const {
    result.counters[key] = static_cast<std::uint64_t>(std::count(world_.known_objects().begin(), world_.known_objects().end(), true));
  }

  int known_movable() const {  // known, movable and still in the shelf
    const std::vector<bool> gone = discounted();
    int n = 0;
    for (ObjectIndex o = 0; o < scene_.objects.size(); ++o) n += !gone[o] && scene_.objects[o].movable ? 1 : 0;
    return n;
  }

  Eigen::Vector2d position(ObjectIndex o) const { return world_.truth().world_T_objects[o].translation().head<2>(); }

  // Where the roadmap samples: x_s and the boards the objects seen at first stand on
  // (the shelf; not the buffer table beside it), grown by the footprint.
  Eigen::AlignedBox2d area() const {
    Eigen::AlignedBox2d box(scene_.world_T_exit.translation().head<2>());
    for (const FixedBody& f : scene_.fixed) {
      const Eigen::AlignedBox3d b = world_bounds(f.shape, f.world_T_body);
      const Eigen::AlignedBox2d top(b.min().head<2>(), b.max().head<2>());
      for (ObjectIndex o : seen_at_first_) {
        const Eigen::AlignedBox3d ob = world_bounds(scene_.objects[o].shape, initial_.world_T_objects[o]);
        if (std::abs(b.max().z() - ob.min().z()) < 0.01 && top.contains(initial_.world_T_objects[o].translation().head<2>())) {
          box.extend(top);
          break;
        }
      }
    }
    box.min().array() -= footprint_.radius;
    box.max().array() += footprint_.radius;
    return box;
  }

  // Line 3-7 of Algorithm 4: the target's position once seen, else x_temp just behind
  // the farthest known object (seen from x_s) that leaves room there.
  std::optional<Goal> next_goal() const {
    if (world_.known(scene_.target)) return Goal{position(scene_.target), scene_.target};
    const Eigen::Vector2d x_s = scene_.world_T_exit.translation().head<2>();
    std::vector<ObjectIndex> candidates;
    const std::vector<bool> gone = discounted();
    for (ObjectIndex o = 0; o < scene_.objects.size(); ++o) {
      if (!gone[o] && scene_.objects[o].movable && !blocked_.count(o) && !unreachable_.count(o)) candidates.push_back(o);
    }
    // Farthest first in depth (along x_s to the middle of the shelf), in rows as deep as
    // the target's footprint radius; in a row, the one nearest the line from x_s first: the
    // arm reaches it straightest, and a sideways one is no farther in.
    const Eigen::Vector2d into = (area_.center() - x_s).normalized();
    const double row = std::max(footprint_.radius, 0.01);
    auto depth = [&](ObjectIndex o) { return std::floor((position(o) - x_s).dot(into) / row); };
    auto aside = [&](ObjectIndex o) {
      const Eigen::Vector2d d = position(o) - x_s;
      return std::abs(d.x() * into.y() - d.y() * into.x());
    };
    std::sort(candidates.begin(), candidates.end(), [&](ObjectIndex a, ObjectIndex b) {
      if (depth(a) != depth(b)) return depth(a) > depth(b);
      return aside(a) < aside(b);
    });
    const Eigen::AlignedBox2d& shelf = area_;
    for (ObjectIndex o : candidates) {
      const Eigen::Vector2d away = (position(o) - x_s).normalized();
      const double r = footprint_radius(scene_.objects[o].shape, world_.truth().world_T_objects[o]);
      const Eigen::Vector2d x = position(o) + (r + footprint_.radius + 0.01) * away;
      if (shelf.contains(x) && collision::shared_world(context_)->fixed_clearance(x, footprint_) >= footprint_.radius) return Goal{x, o};
    }
    return std::nullopt;
  }

  // The objects on the best way to x_g within the exploration limit, in the order met.
  std::optional<ObjectSet> way(int limit) {
    auto where = [this](ObjectIndex o) { return position(o); };
    std::vector<int> node_of;
    retrieval::RetrievalGraph g = roadmap_->cluster(discounted(), where, node_of);
    for (ObjectIndex o : blocked_) g.block_object(o);
    g.update();
    const auto removal = g.removal_sequence();
    if (!removal || static_cast<int>(removal->objects_in_order.size()) > limit) return std::nullopt;
    return removal->objects_in_order;
  }

  // `object`, or the first known object the robot found in its way when removing it.
  ObjectIndex first_free(ObjectIndex object) const {
    std::set<ObjectIndex> seen;
    while (seen.insert(object).second) {
      const auto it = blockers_.find(object);
      if (it == blockers_.end()) return object;
      const std::vector<bool> gone = discounted();
      const auto next = std::find_if(it->second.begin(), it->second.end(),
                                     [&](ObjectIndex b) { return !gone[b] && !blocked_.count(b); });
      if (next == it->second.end()) return object;
      object = *next;
    }
    return object;
  }

  // The objects of `step` the robot's links meet in the truth but not in the belief:
  // unseen ones a motion planned without them would hit.
  std::vector<ObjectIndex> hidden_in_the_way(const PlanStep& step) {
    std::vector<ObjectIndex> hit;
    if (!step.trajectory) return hit;
    collision::CollisionWorld& world = *collision::shared_world(context_);
    world.sync(world_.truth());
    if (world.held()) world.detach(world.object_pose(*world.held()));  // the hand's own load is not in the way
    auto checker = world.make_context();
    std::set<ObjectIndex> found;
    for (const Eigen::VectorXd& q : step.trajectory->positions) {
      if (q.size() != world_.truth().robot_configuration.size()) {
        throw std::logic_error("occlusion: a removal's trajectory does not hold every joint of the robot");
      }
      for (ObjectIndex o : world.check(q, *checker).objects) {
        if (!world_.known(o)) found.insert(o);
      }
    }
    return {found.begin(), found.end()};
  }

  // The known movable objects a failed removal of `object` names as in the way, but
  // neither the target nor one given up on.
  std::vector<ObjectIndex> blockers_of(const retrieval::RemovalCheck& check, ObjectIndex object) const {
    std::vector<ObjectIndex> out;
    if (!check.failure) return out;
    for (ObjectIndex b : check.failure->blocking_objects) {
      if (b != object && b != scene_.target && world_.known(b) && scene_.objects[b].movable && !blocked_.count(b)) out.push_back(b);
    }
    return out;
  }

  // `blockers` of a failed removal of `object`, unless they are none or one of them
  // waits for `object` (two cylinders millimetres apart block each other's least blocked
  // grasps, or a blocker was given up on): then the blockers of another grasp of
  // `object`, the fewest, all known, movable and waiting for nothing of `object`'s.
  std::vector<ObjectIndex> not_waiting(ObjectIndex object, std::vector<ObjectIndex> blockers,
                                       const retrieval::RemovalCheck& check, const WorldState& belief) {
    auto waits = [&](ObjectIndex b) {
      const auto it = waits_for_.find(b);
      return it != waits_for_.end() && it->second.count(object);
    };
    const bool grasp_failed = check.failure && check.failure->stage == "grasp";
    if (!grasp_failed || (!blockers.empty() && std::none_of(blockers.begin(), blockers.end(), waits))) return blockers;
    collision::shared_world(context_)->sync(belief);
    const plugin::GraspAnswer answer = context_.samplers.get<plugin::GraspSampler>()->sample(context_, {object, belief});
    std::optional<std::vector<ObjectIndex>> best;
    for (const plugin::BlockedGrasp& g : answer.blocked) {
      if (!g.freeable || g.blocking_objects.empty()) continue;
      const bool usable = std::all_of(g.blocking_objects.begin(), g.blocking_objects.end(), [&](ObjectIndex b) {
        return b != object && b != scene_.target && world_.known(b) && scene_.objects[b].movable && !blocked_.count(b) && !waits(b);
      });
      if (usable && (!best || g.blocking_objects.size() < best->size())) best = g.blocking_objects;
    }
    return best ? *best : blockers;
  }

  // Picks `object` and places it in the region (or carries it out), planned on what is
  // known and checked against the truth; then looks again.
  void remove(ObjectIndex object, Result& result) {
    const auto t0 = Clock::now();
    sync();
    const WorldState belief = world_.belief();
    auto checker = std::make_unique<retrieval::RemovalChecker>(context_, belief, settings_.region);
    const ObjectIndex order[] = {object};
    const std::uint64_t salt = static_cast<std::uint64_t>(attempts_[object]);
    const retrieval::RemovalCheck check = checker->remove(order, salt);
    motion_seconds_ += std::chrono::duration<double>(Clock::now() - t0).count();
    ++result.counters[counter::removal_attempts];
    if (!check.ok) {
      if (check.failure) retrieval::record_failure_once(result, *check.failure);
      if (check.failure) waits_for_[object].insert(check.failure->blocking_objects.begin(), check.failure->blocking_objects.end());
      const std::vector<ObjectIndex> known_blockers = not_waiting(object, blockers_of(check, object), check, belief);
      // The blockers go first next time; an object that keeps failing is given up on.
      if (!known_blockers.empty()) blockers_[object] = known_blockers;
      if (++attempts_[object] >= settings_.max_attempts) blocked_.insert(object);
      return;
    }
    Result steps;
    checker->write_steps(order, salt, steps);
    for (const PlanStep& step : steps.plan) {
      const std::vector<ObjectIndex> hidden = hidden_in_the_way(step);
      if (!hidden.empty()) {
        found_by_touch(hidden, result);
        return;
      }
    }
    result.plan.insert(result.plan.end(), steps.plan.begin(), steps.plan.end());
    result.moved_objects.insert(result.moved_objects.end(), steps.moved_objects.begin(), steps.moved_objects.end());
    result.failures.insert(result.failures.end(), steps.failures.begin(), steps.failures.end());
    moved_.insert(object);
    done_.push_back({object, salt, std::move(checker)});
    const std::vector<ObjectIndex> revealed = world_.update(check.state);
    result.counters[counter::revealed] += revealed.size();
    // The world changed: what could not be removed before may come out now.
    blockers_.clear();
    blocked_.clear();
    attempts_.clear();
    unreachable_.clear();
    waits_for_.clear();
    if (!revealed.empty()) {
      sync_roadmap();
      roadmap_->reveal(revealed);
    }
  }

  void found_by_touch(const std::vector<ObjectIndex>& hidden, Result& result) {
    const std::vector<ObjectIndex> found = world_.touch(hidden);
    result.counters[counter::found_by_touch] += found.size();
    sync_roadmap();
    roadmap_->reveal(found);
  }

  // Algorithm 4's last round: the way is clear, the target is taken to x_s.
  bool retrieve(Result& result) {
    const auto t0 = Clock::now();
    sync();
    const WorldState belief = world_.belief();
    auto checker = std::make_unique<retrieval::RemovalChecker>(context_, belief, settings_.region);
    const std::uint64_t salt = static_cast<std::uint64_t>(attempts_[scene_.target]);
    const retrieval::RemovalCheck check = checker->retrieve({}, salt);
    motion_seconds_ += std::chrono::duration<double>(Clock::now() - t0).count();
    ++result.counters[counter::removal_attempts];
    if (!check.ok) {
      if (check.failure) retrieval::record_failure_once(result, *check.failure);
      const std::vector<ObjectIndex> known_blockers = not_waiting(scene_.target, blockers_of(check, scene_.target), check, belief);
      if (!known_blockers.empty()) {
        remove(first_free(known_blockers.front()), result);
      } else if (++attempts_[scene_.target] >= settings_.max_attempts) {
        result.reason = "the target is seen and nothing known is in its way, but the robot could not retrieve it: " +
                        (check.failure ? check.failure->reason : std::string("no reason given"));
      }
      return false;
    }
    Result steps;
    checker->write_plan({}, salt, steps);
    for (const PlanStep& step : steps.plan) {
      const std::vector<ObjectIndex> hidden = hidden_in_the_way(step);
      if (!hidden.empty()) {
        found_by_touch(hidden, result);
        return false;
      }
    }
    result.plan.insert(result.plan.end(), steps.plan.begin(), steps.plan.end());
    result.moved_objects.insert(result.moved_objects.end(), steps.moved_objects.begin(), steps.moved_objects.end());
    result.failures.insert(result.failures.end(), steps.failures.begin(), steps.failures.end());
    done_.push_back({scene_.target, salt, std::move(checker)});
    return true;
  }

  void mark_solved(Result& result) const {
    result.solved = true;
    result.counters[counter::final_sequence] = final_sequence();
  }

  // Tian et al.'s Table II counts the final removal sequence: objects moved only to
  // look behind them are the extra cost of occlusion. These are the moved objects the
  // plan needed moved (target included): those the target's retrieval would have met
  // where they stood at first, then those the removal of a needed one would have met.
  std::size_t final_sequence() const {
    std::set<ObjectIndex> needed{scene_.target};
    for (std::size_t i = done_.size(); i-- > 0;) {
      const Removal& d = done_[i];
      if (!needed.count(d.object)) continue;
      std::vector<ObjectIndex> earlier;
      for (std::size_t j = 0; j < i; ++j) earlier.push_back(done_[j].object);
      const bool target = d.object == scene_.target;
      const std::vector<ObjectIndex> order = target ? std::vector<ObjectIndex>{} : std::vector<ObjectIndex>{d.object};
      for (ObjectIndex o : d.checker->met_by_plan(order, d.salt, target, earlier, initial_)) needed.insert(o);
    }
    return needed.size();
  }

  plugin::PlanningContext& context_;
  const Settings& settings_;
  const Scene& scene_;
  WorldState initial_;
  perception::ObservedWorld world_;
  std::vector<ObjectIndex> seen_at_first_;
  collision::Footprint footprint_;
  Eigen::AlignedBox2d area_;
  std::set<ObjectIndex> moved_;  // taken away by the plan
  struct Removal {  // a removal in the plan (the target's retrieval last), with its checker's motions
    ObjectIndex object;
    std::uint64_t salt;
    std::unique_ptr<retrieval::RemovalChecker> checker;
  };
  std::vector<Removal> done_;
  std::unique_ptr<retrieval::Roadmap> roadmap_;
  std::set<ObjectIndex> blocked_;                           // could not be removed
  std::set<ObjectIndex> unreachable_;  // no way to the temporary goal behind them (until the world changes)
  static constexpr int kExtraExpansions = 3;
  std::map<ObjectIndex, int> extra_expansions_;  // per goal (keyed by what it lies behind; the target's own)
  std::map<ObjectIndex, std::vector<ObjectIndex>> blockers_;  // known objects in the way of removing one
  std::map<ObjectIndex, std::set<ObjectIndex>> waits_for_;    // every object a failed removal named, target included
  std::map<ObjectIndex, int> attempts_;
  double motion_seconds_ = 0.0;
};

class OcclusionPlanner final : public plugin::TaskPlanner {
 public:
  void configure(const Parameters& p) override { settings_.read(p); }

  std::vector<std::string> required_kinds() const override { return retrieval::retrieval_sampler_kinds(); }

  Result solve(plugin::PlanningContext& context, const WorldState& initial) override {
    if (const auto missing = retrieval::retrieval_inputs_missing(context, "occlusion")) {
      Result r;
      r.reason = *missing;
      return r;
    }
    if (!context.scene().world_T_camera) {
      Result r;
      r.reason = "occlusion needs the scene's camera (camera: in the scene file) to know what is seen";
      return r;
    }
    return Run(context, settings_, initial).run();
  }

 private:
  Settings settings_;
};

}  // namespace

CLUTTERTAMP_EXPORT_TASK_PLANNER(OcclusionPlanner, occlusion,
                                "Retrieval when objects, even the target, are hidden: plans to x_temp behind the "
                                "farthest observed object until the target is seen (Tian et al. 2023, Algorithm 4)",
                                "0.1.0")
