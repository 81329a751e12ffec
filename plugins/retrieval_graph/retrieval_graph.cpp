// retrieval_graph: the incremental sampling-based retrieval planner of Tian et al.
// (T-RO 2023), Algorithm 1: grow the roadmap of the held target's positions under an
// exploration limit L (Algorithm 2), cluster it into the retrieval graph, find the
// removal sequence with the fewest objects (Algorithm 3), check it with the robot
// (grasp, motion and placement samplers) removing objects in order; a failure adds the
// robot-obstacle collisions as new graph nodes in place of the failed edge (Fig. 5) and
// the search runs again; with no sequence of at most L objects left, L grows. Each
// sequence is checked from the initial world (a failed check is planning, not
// execution), so the plan holds the last sequence only: R and Pi of Algorithm 1.
#include <algorithm>
#include <chrono>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <variant>

#include "cluttertamp/collision/shared_world.hpp"
#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/grasp_sampler.hpp"
#include "cluttertamp/plugin/object_pruner.hpp"
#include "cluttertamp/plugin/push_sampler.hpp"
#include "cluttertamp/plugin/task_planner.hpp"
#include "cluttertamp/retrieval/removal_checker.hpp"
#include "cluttertamp/retrieval/roadmap.hpp"
#include "feedback_graph.hpp"
#include "shortener.hpp"

namespace {

using namespace cluttertamp;
using retrieval::ObjectSet;
using retrieval_graph_plugin::Endpoint;
using retrieval_graph_plugin::Feedback;
using retrieval_graph_plugin::FeedbackGraph;
using Clock = std::chrono::steady_clock;

struct Settings {
  retrieval::RoadmapOptions roadmap;
  std::string initial_limit = "one";  // Table I: 1, |n_g.NodeCol| or |O|
  std::string region = "buffer";
  int max_feedback = 200;
  bool shorten = true;  // drop objects the found order does not need
  std::int64_t shorten_max_checks = 300000;  // collision checks per shorter order tried
  bool restart = true;  // after every limit failed: forget the feedback, draw afresh
  bool push = false;    // Section VI-G: push instead of pick-and-place where a push works
  double area_margin = 0.0;  // m beyond the objects and x_s where the roadmap samples (Section V-B: all around)
  int goal_branches = 6;     // target grasps fed back side by side; 1: the paper's one node
  int grasp_orders = 0;      // shortening also tries this many of the target's grasps' blocker sets

  void read(const Parameters& p) {
    roadmap.read(p);
    initial_limit = p.get_string("initial_L", initial_limit,
                                 "the first exploration limit L: one, nodecol (|n_g.NodeCol|) or objects (|O|)");
    region = p.get_string("region", region, "the scene's region removed objects are placed in");
    shorten = p.get_bool("shorten", shorten, "drop the objects a working order does not need");
    p.require(!p.contains("shorten_time"), "shorten_time",
              "is no longer read: shortening's budget is work, so that a seed gives the same plan on any machine; "
              "set shorten_max_checks (collision checks per shorter order tried, default 300000)");
    shorten_max_checks = p.get_int("shorten_max_checks", shorten_max_checks, "collision checks per shorter order tried",
                                   Range::above(0));
    restart = p.get_bool("restart", restart,
                         "when every limit has failed, forget the feedback and search again with fresh draws");
    area_margin = p.get_double("area_margin", area_margin,
                               "m beyond the objects and x_s on every side where the roadmap samples",
                               Range::closed(0, 5));
    goal_branches = static_cast<int>(p.get_int("goal_branches", goal_branches,
                                               "target grasps' blocker sets fed back side by side (1: one node)",
                                               Range::closed(1, 100)));
    grasp_orders = static_cast<int>(p.get_int("grasp_orders", grasp_orders,
                                              "target grasps' blocker sets shortening also tries (0: off)",
                                              Range::closed(0, 100)));
    p.require(initial_limit == "one" || initial_limit == "nodecol" || initial_limit == "objects", "initial_L",
              "must be one, nodecol or objects");
  }
};

class Search {
 public:
  Search(plugin::PlanningContext& context, const Settings& settings, const WorldState& initial)
      : context_(context), settings_(settings), initial_(initial), checker_(context, initial, settings.region) {
    const Scene& scene = context.scene();
    target_ = scene.target;
    footprint_ = retrieval::held_footprint(context, initial, target_);
    Eigen::AlignedBox2d area(scene.world_T_exit.translation().head<2>());
    for (const SceneObject& o : scene.objects) area.extend(o.world_T_object.translation().head<2>());
    area.min().array() -= footprint_.radius + settings.area_margin;
    area.max().array() += footprint_.radius + settings.area_margin;
    world_ = collision::shared_world(context);
    world_->sync(initial_);
    roadmap_ = std::make_unique<retrieval::Roadmap>(*world_, footprint_, area, scene.world_T_exit.translation().head<2>(),
                                                    initial.world_T_objects[target_].translation().head<2>(), target_,
                                                    context.seed);
    // The target leaves along its footprint's free way (the paper's end-effector path):
    // a carry that follows it needs no motion planning.
    checker_.set_way_out([this](const WorldState& after) {
      world_->sync(after);
      return roadmap_->free_way(after.removed);
    });
  }

  // Task planning only (object pruning for the symbolic layer): the removal sequence
  // of the first exploration limit that has one, without checking it with the robot.
  plugin::PruneAnswer prune() {
    plugin::PruneAnswer answer;
    const int objects = static_cast<int>(context_.scene().objects.size());
    for (int limit = initial_limit(); limit <= objects && !context_.deadline.expired(); ++limit) {
      roadmap_->expand(limit, settings_.roadmap);
      retrieval::RetrievalGraph g = feedback_graph_.graph(*roadmap_);
      const auto removal = g.removal_sequence();
      if (removal && static_cast<int>(removal->objects_in_order.size()) <= limit) {
        answer.removal_sequences.push_back(feedback_graph_.in_precedence_order(removal->objects_in_order));
        return answer;
      }
    }
    answer.failure = Failure{"object_pruner", context_.deadline.expired() ? "time limit reached" : "no removal sequence found", {}};
    return answer;
  }

  /// Every removal order run() checked with the robot, first tried first.
  const std::vector<ObjectSet>& tried() const { return tried_; }

  Result run() {
    Result result;
    const auto start = Clock::now();
    int limit = initial_limit();
    const int objects = static_cast<int>(context_.scene().objects.size());
    std::uint64_t iterations = 0;
    // At L = |O| the limit cannot grow: a few more rounds, each drawing afresh after an
    // attempt that taught nothing, or growing a roadmap that has not yet joined x_s to
    // x_g (with initial_L: objects, one expansion of T samples is all it had), before
    // giving up.
    constexpr int kRoundsAtFullLimit = 3;
    int rounds_at_full_limit = 0;
    // Limits in a row whose expanded roadmap, with the feedback, held no path at all:
    // the feedback has cut every way out, and growing the roadmap rarely reopens one.
    constexpr int kLimitsWithoutPath = 5;
    int limits_without_path = 0;
    bool stuck = false;
    bool unjoined = false;  // the last expansion's roadmap held no way at all, with no feedback
    std::uint64_t sequences_at_restart = 0;
    int explored_limit = 0;  // the roadmap has been expanded for every L up to this
    // Rounds (restart to restart) whose feedback ended the same; at kSameRounds, stop.
    constexpr int kSameRounds = 2;
    std::map<std::vector<std::vector<std::uint64_t>>, int> rounds_seen;
    bool repeated = false;
    for (;;) {
      if (context_.stopped()) break;
      const bool exhausted = limit > objects && !((stuck || unjoined) && ++rounds_at_full_limit < kRoundsAtFullLimit);
      const bool cut_off = settings_.restart && limits_without_path >= kLimitsWithoutPath &&
                           result.counters[counter::planning_sequences] > sequences_at_restart;
      if (exhausted || cut_off) {
        // Every limit tried, or the feedback cut every way out: the feedback collected
        // with these draws (grasps blocked by objects that only other grasps could free)
        // leaves no sequence. Start over with fresh draws and no feedback, keeping the
        // roadmap, while time remains, but only if this round checked a sequence (else
        // the next would do the same).
        if (!settings_.restart || result.counters[counter::planning_sequences] == sequences_at_restart) break;
        sequences_at_restart = result.counters[counter::planning_sequences];
        // The same feedback as after an earlier round: the draws did not matter (grasps
        // blocked whatever the seed), and another round would learn it again.
        if (++rounds_seen[feedback_graph_.signature()] >= kSameRounds) {
          repeated = true;
          break;
        }
        forget_feedback();
        ++result.counters[counter::restarts];
        limit = initial_limit();
        rounds_at_full_limit = 0;
        limits_without_path = 0;
      }
      limit = std::min(limit, objects);
      stuck = false;
      unjoined = false;
      // After a restart, the limits already explored keep their roadmap.
      if (result.counters[counter::restarts] == 0 || limit > explored_limit) roadmap_->expand(limit, settings_.roadmap);
      explored_limit = std::max(explored_limit, limit);
      result.counters[counter::iterations] = ++iterations;
      for (int attempt = 0; attempt < settings_.max_feedback && !context_.stopped(); ++attempt) {
        retrieval::RetrievalGraph g = feedback_graph_.graph(*roadmap_);
        auto removal = g.removal_sequence();
        if (!removal) {
          if (!feedback_graph_.empty()) ++limits_without_path;  // without feedback: K still too low
          unjoined = feedback_graph_.empty();
          break;
        }
        limits_without_path = 0;
        if (const int needed = static_cast<int>(removal->objects_in_order.size()); needed > limit) {
          // Limits the roadmap was already expanded for (after a restart) leave the
          // graph as it is: skip to the first limit where the search can differ.
          if (limit < explored_limit) limit = std::min(needed, explored_limit + 1) - 1;
          break;
        }
        removal->objects_in_order = feedback_graph_.in_precedence_order(std::move(removal->objects_in_order));
        ++result.counters[counter::planning_sequences];
        const Attempt attempt_result = execute(g, *removal, result);
        if (attempt_result == Attempt::solved) {
          result.solved = true;
          finish(result, start);
          return result;
        }
        if (attempt_result == Attempt::stuck) {  // the same sequence would come back
          ++reseeds_;
          stuck = true;
          break;
        }
      }
      ++limit;
      result.counters[counter::exploration_limit] = static_cast<std::uint64_t>(limit);
    }
    result.reason = context_.deadline.expired() ? "time limit reached before the target was retrieved"
                    : context_.stopped()        ? "work budget (collision checks) used up before the target was retrieved"
                    : repeated                  ? stuck_reason(result.counters[counter::restarts] + 1)
                                                : "no removal sequence works within the exploration limit";
    finish(result, start);
    return result;
  }

 private:
  int initial_limit() {
    if (settings_.initial_limit == "objects") return static_cast<int>(context_.scene().objects.size());
    if (settings_.initial_limit == "nodecol") return std::max(1, static_cast<int>(roadmap_->col(roadmap_->graph()[1].x).size()));
    return 1;
  }

  void finish(Result& result, Clock::time_point start) {
    checker_.record_times(result, start);
    result.time.motion_planning += push_seconds_;  // pushes and the checks around them
    result.time.task_planning = std::max(0.0, result.time.task_planning - push_seconds_);
    result.counters[counter::roadmap_nodes] = roadmap_->size();
    result.counters[counter::feedback_nodes] = feedback_graph_.size();
    draw(result);
  }

  // The roadmap and the last retrieval graph (feedback nodes included) with its best
  // path, for the plan viewer.
  void draw(Result& result) {
    PlaneDrawing roadmap{"roadmap", {}, {}, {}, {}};
    const retrieval::RoadmapGraph& r = roadmap_->graph();
    for (std::size_t v = 0; v < boost::num_vertices(r); ++v) roadmap.nodes.push_back(r[v].x);
    for (auto [e, end] = boost::edges(r); e != end; ++e) {
      roadmap.edges.emplace_back(static_cast<int>(boost::source(*e, r)), static_cast<int>(boost::target(*e, r)));
    }
    result.drawings.push_back(std::move(roadmap));

    const retrieval::RetrievalGraph g = feedback_graph_.graph(*roadmap_);
    const Scene& scene = context_.scene();
    PlaneDrawing drawing{"retrieval graph", {}, {}, {}, {}};
    const retrieval::Graph& gg = g.graph();
    for (std::size_t v = 0; v < g.size(); ++v) {
      drawing.nodes.push_back(gg[v].position);
      std::string label;
      for (ObjectIndex o : gg[v].node_col) label += (label.empty() ? "" : " ") + scene.objects[o].id;
      if (static_cast<int>(v) == g.start()) label = "start" + (label.empty() ? "" : ": " + label);
      if (static_cast<int>(v) == g.goal()) label = "goal" + (label.empty() ? "" : ": " + label);
      drawing.labels.push_back(label);
    }
    for (auto [e, end] = boost::edges(gg); e != end; ++e) {
      drawing.edges.emplace_back(static_cast<int>(boost::source(*e, gg)), static_cast<int>(boost::target(*e, gg)));
    }
    if (const auto removal = g.removal_sequence()) drawing.path = removal->nodes;
    result.drawings.push_back(std::move(drawing));
  }

  // Feedback for a failure while removing `object` on `removal`: new nodes with the
  // robot's collisions replace the edge into the failing node. Returns false when the
  // failure teaches the graph nothing new (so the same sequence would come back).
  bool feed_back(const retrieval::RetrievalGraph& g, const retrieval::RetrievalGraph::Removal& removal, ObjectIndex object,
                 const Failure& failure, const WorldState& at_failure, Result& result) {
    retrieval::record_failure_once(result, failure);
    ObjectSet blocking = feedback_graph_.removable(failure.blocking_objects);
    // The goal branch (a target grasp's blockers) the path took to the target, if any:
    // the last one on it (guards and other feedback can lie between it and the goal).
    std::optional<int> branch;
    if (object == target_ && failure.stage != "carry") {
      for (std::size_t i = removal.nodes.size(); i-- > 0;) {
        const Endpoint e = feedback_graph_.endpoint(removal.nodes[i]);
        if (std::holds_alternative<int>(e) && feedback_graph_.is_branch(std::get<int>(e))) {
          branch = std::get<int>(e);
          break;
        }
      }
    }
    // A grasp the target or an avoided object blocks cannot be freed: blame another.
    if (!feedback_graph_.freeable_for(object, failure.blocking_objects)) {
      const auto other = other_grasp_blockers(object, failure, at_failure);
      if (!other && !branch && object != target_ && blocked_by_target(failure)) return stay(object, failure);
      if (!other) return branch ? kill_branch(*branch) : avoid(object, failure);
      blocking = *other;
    }
    std::size_t fail = removal.nodes.size() - 1;
    for (std::size_t i = 0; i < removal.nodes.size(); ++i) {
      const ObjectSet& col = g.node(removal.nodes[i]).node_col;
      if (std::binary_search(col.begin(), col.end(), object)) {
        fail = i;
        break;
      }
    }
    // Nothing to remove would help — or the motion search ran out of time: only a second
    // such failure, after a fresh draw, keeps the graph away from the object.
    if (blocking.empty()) {
      if (branch) return ++unexplained_branch_[*branch] >= 2 && kill_branch(*branch);
      return ++unexplained_[object] >= 2 && avoid(object, failure);
    }
    // Objects blocking each other's least blocked grasps (two cylinders millimetres
    // apart): one of them already waits for this object, so removing them first cannot
    // work; another grasp's blockers that wait for nothing of this object's may.
    if (object != target_ && any_waits_for(blocking, object)) {
      if (const auto other = other_grasp_blockers(object, failure, at_failure, true)) blocking = *other;
    }
    if (!seen_failures_[object].insert(blocking).second) {
      // The same object blocked by the same objects again: removing them first did not
      // help (objects blocking each other's least blocked grasps). Feed back the next
      // least blocked grasp instead; avoid the object once every grasp has been tried.
      const auto other = other_grasp_blockers(object, failure, at_failure);
      if (!other) return avoid(object, failure);
      blocking = *other;
      seen_failures_[object].insert(blocking);
    }
    // Reaching the target is needed on every path; carrying it out is this path's.
    if (branch) {  // this grasp's way needs more: on the branch, not on every way
      feedback_graph_.add({*branch, {}, blocking, Feedback::Where::branch});
    } else if (object == target_ && failure.stage != "carry") {
      feedback_graph_.add({{}, {}, blocking, Feedback::Where::after_goal, 0, other_grasps(object, at_failure)});
    } else if (fail == 0) {
      feedback_graph_.add({{}, {}, blocking, Feedback::Where::before_start});
    } else if (object != target_) {
      feedback_graph_.add({{}, {}, blocking, Feedback::Where::object, object});
    } else {
      feedback_graph_.add(
          {feedback_graph_.endpoint(removal.nodes[fail - 1]), feedback_graph_.endpoint(removal.nodes[fail]), blocking});
    }
    return true;
  }

  void forget_feedback() {
    ++reseeds_;
    feedback_graph_.clear();
    unexplained_branch_.clear();
    unexplained_.clear();
    seen_failures_.clear();
  }

  bool kill_branch(int branch) { return feedback_graph_.kill_branch(branch); }

  // Keeps the retrieval graph away from `object`; the target cannot be avoided.
  bool avoid(ObjectIndex object, const Failure& why) {
    if (object == target_) {
      why_stuck_[object] = why;
      return false;
    }
    if (!feedback_graph_.block(object)) return false;
    why_stuck_[object] = why;
    return true;
  }

  bool blocked_by_target(const Failure& failure) const {
    return std::find(failure.blocking_objects.begin(), failure.blocking_objects.end(), target_) !=
           failure.blocking_objects.end();
  }

  // Lets the graph's ways pass `object`, which can leave only after the target.
  bool stay(ObjectIndex object, const Failure& why) {
    if (feedback_graph_.stays(object)) return avoid(object, why);
    feedback_graph_.let_stay(object);
    why_stuck_[object] = why;
    return true;
  }

  // Why no sequence works once rounds repeat: the objects the feedback could not get
  // out of the way, each with its last failure.
  std::string stuck_reason(std::uint64_t restarts) const {
    std::string out = "no removal sequence works: " + std::to_string(restarts) +
                      " fresh draws of the samplers met the same failures";
    const Scene& scene = context_.scene();
    for (const auto& [object, failure] : why_stuck_) {
      out += "; '" + scene.objects[object].id + "' " +
             (object == target_ ? "cannot be retrieved" : "cannot be moved out of the way") + " (" + failure.stage + ": " +
             failure.reason + ")";
    }
    return out;
  }

  // The distinct sets of removable objects blocking `object`'s freeable grasps in
  // `state`, fewest objects first (the sampler's order among equals); with `unseen`,
  // only those not fed back yet.
  std::vector<ObjectSet> grasp_blocker_sets(ObjectIndex object, const WorldState& state, bool unseen) {
    std::vector<ObjectSet> sets;
    const auto grasp_sampler = context_.samplers.get<plugin::GraspSampler>();
    if (!grasp_sampler) return sets;
    const plugin::GraspAnswer answer = grasp_sampler->sample(context_, {object, state});
    for (const plugin::BlockedGrasp& b : answer.blocked) {
      if (!b.freeable || !feedback_graph_.freeable_for(object, b.blocking_objects)) continue;
      ObjectSet set = feedback_graph_.removable(b.blocking_objects);
      if (set.empty() || (unseen && seen_failures_[object].count(set))) continue;
      if (std::find(sets.begin(), sets.end(), set) == sets.end()) sets.push_back(std::move(set));
    }
    std::stable_sort(sets.begin(), sets.end(), [](const ObjectSet& a, const ObjectSet& b) { return a.size() < b.size(); });
    return sets;
  }

  // The smallest of those (with `acyclic`, of those none of whose objects waits for
  // `object`), or nothing. Only grasp failures have alternatives.
  std::optional<ObjectSet> other_grasp_blockers(ObjectIndex object, const Failure& failure, const WorldState& at_failure,
                                                bool acyclic = false) {
    if (failure.stage != "grasp") return std::nullopt;
    for (ObjectSet& set : grasp_blocker_sets(object, at_failure, true)) {
      if (!acyclic || !any_waits_for(set, object)) return std::move(set);
    }
    return std::nullopt;
  }

  // True when one of `objects` was fed back as blocked by `object`: it waits for
  // `object` to leave first.
  bool any_waits_for(const ObjectSet& objects, ObjectIndex object) const {
    return std::any_of(objects.begin(), objects.end(), [&](ObjectIndex b) {
      const auto it = seen_failures_.find(b);
      return it != seen_failures_.end() && std::any_of(it->second.begin(), it->second.end(), [&](const ObjectSet& s) {
               return std::binary_search(s.begin(), s.end(), object);
             });
    });
  }

  // The goal branches beside a target grasp's fed-back blockers (already seen): at most
  // goal_branches - 1 of the other grasps' sets.
  std::vector<ObjectSet> other_grasps(ObjectIndex object, const WorldState& at_failure) {
    if (settings_.goal_branches < 2) return {};
    std::vector<ObjectSet> sets = grasp_blocker_sets(object, at_failure, true);
    if (sets.size() >= static_cast<std::size_t>(settings_.goal_branches)) sets.resize(settings_.goal_branches - 1);
    return sets;
  }

  // solved: the target is out; retry: the world or the graph changed; stuck: neither.
  enum class Attempt { solved, retry, stuck };

  Attempt execute(const retrieval::RetrievalGraph& g, const retrieval::RetrievalGraph::Removal& removal, Result& result) {
    // After an attempt that taught nothing (a motion failed within its budget with
    // nothing to blame), the samplers draw afresh, deterministically.
    if (std::find(tried_.begin(), tried_.end(), removal.objects_in_order) == tried_.end()) {
      tried_.push_back(removal.objects_in_order);
    }
    const retrieval::RemovalCheck check = checker_.retrieve(removal.objects_in_order, reseeds_);
    if (check.ok) {
      const ObjectSet order =
          settings_.shorten ? shortener_.shortened(removal.objects_in_order, reseeds_,
                                                   [&] { return grasp_blocker_sets(target_, initial_, false); }, result)
                            : removal.objects_in_order;
      if (settings_.push) {
        const retrieval::PushReplacement pushes =
            retrieval::write_plan_with_pushes(context_, checker_, order, settings_.region, reseeds_, result);
        result.counters[counter::pushes] = pushes.pushes;
        result.counters[counter::pushes_tried] = pushes.pushes_tried;
        push_seconds_ = pushes.seconds;
      } else {
        checker_.write_plan(order, reseeds_, result);
      }
      return Attempt::solved;
    }
    if (context_.stopped()) return Attempt::retry;
    return feed_back(g, removal, *check.failed_object, *check.failure, check.state, result) ? Attempt::retry
                                                                                          : Attempt::stuck;
  }

  plugin::PlanningContext& context_;
  const Settings& settings_;
  const WorldState initial_;  // every check starts here: a failed sequence moves nothing
  ObjectIndex target_ = 0;
  collision::Footprint footprint_;
  collision::CollisionWorld* world_ = nullptr;
  std::unique_ptr<retrieval::Roadmap> roadmap_;
  FeedbackGraph feedback_graph_{initial_, context_.scene().target};
  std::map<int, int> unexplained_branch_;   // failures with nothing to blame, per goal branch
  std::map<ObjectIndex, int> unexplained_;  // failures with nothing to blame, per object
  std::map<ObjectIndex, Failure> why_stuck_;  // avoided objects (and the target), with why
  std::map<ObjectIndex, std::set<ObjectSet>> seen_failures_;
  std::vector<ObjectSet> tried_;  // every removal order checked, in order
  retrieval::RemovalChecker checker_;
  retrieval_graph_plugin::Shortener shortener_{context_, checker_, initial_, settings_.shorten_max_checks,
                                               settings_.grasp_orders};
  std::uint64_t reseeds_ = 0;
  double push_seconds_ = 0.0;
};

class RetrievalGraphPlanner final : public plugin::TaskPlanner {
 public:
  void configure(const Parameters& p) override {
    settings_.read(p);
    settings_.push = p.get_bool("push", settings_.push,
                                "push instead of pick-and-place where a push works (needs a push sampler)");
  }
  std::vector<std::string> required_kinds() const override {
    std::vector<std::string> kinds = retrieval::retrieval_sampler_kinds();
    if (settings_.push) kinds.emplace_back(plugin::KindOf<plugin::PushSampler>::name);
    return kinds;
  }

  Result solve(plugin::PlanningContext& context, const WorldState& initial) override {
    std::optional<std::string> why = retrieval::retrieval_inputs_missing(context, "retrieval_graph");
    if (!why && settings_.push && !context.samplers.get<plugin::PushSampler>()) {
      why = "retrieval_graph with push: true needs a push sampler (plugins: {push_sampler: push_ompl})";
    }
    if (why) {
      Result r;
      r.reason = *why;
      return r;
    }
    return Search(context, settings_, initial).run();
  }

 private:
  Settings settings_;
};

// The same planner as an object pruner, so that a symbolic search moves only the
// objects of its candidate removal sequences: with `checked` (default), first the
// objects a full run with robot feedback moved (within `checked_max_checks` collision
// checks), then
// every other order that run checked, then the best sequence of the task level alone
// (no robot checks), which is all there is without `checked`.
class RetrievalGraphPruner final : public plugin::ObjectPruner {
 public:
  void configure(const Parameters& p) override {
    settings_.read(p);
    checked_ = p.get_bool("checked", checked_,
                          "start from the objects a full run with robot checks moved (false: the task level alone)");
    p.require(!p.contains("checked_time"), "checked_time",
              "is no longer read: the checked run's budget is work, so that a seed gives the same removal sequences "
              "on any machine; set checked_max_checks (collision checks, default 4000000)");
    checked_max_checks_ = p.get_int("checked_max_checks", checked_max_checks_, "collision checks of the checked run",
                                    Range::above(0));
  }

  plugin::PruneAnswer prune(plugin::PlanningContext& context, const WorldState& state) override {
    plugin::PruneAnswer answer;
    if (!context.worlds || !context.problem.robot.loaded) {
      answer.failure = Failure{"object_pruner", "the problem has no robot", {}};
      return answer;
    }
    if (checked_) {
      plugin::PlanningContext run = context.with_checks(static_cast<std::uint64_t>(checked_max_checks_));
      Search search(run, settings_, state);
      const Result r = search.run();
      if (r.solved) answer.removal_sequences.push_back(r.moved_objects);
      // The orders that failed with the robot's motions may still be what another
      // planner's motions need.
      for (const ObjectSet& order : search.tried()) {
        if (std::find(answer.removal_sequences.begin(), answer.removal_sequences.end(), order) == answer.removal_sequences.end()) {
          answer.removal_sequences.push_back(order);
        }
      }
    }
    plugin::PruneAnswer unchecked = Search(context, settings_, state).prune();
    answer.removal_sequences.insert(answer.removal_sequences.end(), unchecked.removal_sequences.begin(),
                                    unchecked.removal_sequences.end());
    if (answer.removal_sequences.empty()) answer.failure = unchecked.failure;
    return answer;
  }

 private:
  Settings settings_;
  bool checked_ = true;
  std::int64_t checked_max_checks_ = 4000000;
};

}  // namespace

CLUTTERTAMP_EXPORT_OBJECT_PRUNER(RetrievalGraphPruner, retrieval_graph,
                                 "The retrieval graph's removal sequences (checked with the robot, and unchecked) to focus a symbolic search", "0.1.0")
CLUTTERTAMP_EXPORT_TASK_PLANNER(RetrievalGraphPlanner, retrieval_graph,
                                "Roadmap + retrieval graph with robot-collision feedback (Tian et al. 2023)", "0.1.0")
