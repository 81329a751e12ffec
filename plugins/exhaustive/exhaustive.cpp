// exhaustive: the brute-force retrieval baseline of Tian et al. (T-RO 2023, Section
// VI-F, Table VI) — every removal set and order, smallest sets first, with the same
// feasibility checks as retrieval_graph. The first set whose removal lets the target
// out is a minimum one.
//
// Orders are enumerated by dynamic programming over sets: a set of k + 1 objects is
// removable when some removable set of k objects, then one more object, works. Every
// last object after every removable set is tried, so every order is reached unless two
// orders of the same set leave the world in different states (only the buffer
// placements differ; the first order found stands for its set).
//
// A motion that was not found within its budget is no proof that none exists: a check
// that fails for lack of a motion is tried again with `motion_draws` fresh draws of the
// samplers before its set counts as not removable, and a search that ends without a
// plan says how many sets failed that way (then "every set was checked" would not hold).
#include <chrono>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/task_planner.hpp"
#include "cluttertamp/retrieval/removal_checker.hpp"

namespace {

using namespace cluttertamp;
using Clock = std::chrono::steady_clock;
using Order = std::vector<ObjectIndex>;
using Set = std::vector<bool>;

// An order that removes its set, and the draw of the samplers (the checker's salt) that did.
struct Removal {
  Order order;
  std::uint64_t salt = 0;
};

// Failures that prove nothing about the set: a motion the planner did not find within
// its budget (or the run's limits stopped the check).
bool unproven(const retrieval::RemovalCheck& check) {
  if (check.ok || !check.failure) return false;
  const std::string& stage = check.failure->stage;
  return stage == "motion" || stage == "carry" || stage == "plan";
}

class Exhaustive final : public plugin::TaskPlanner {
 public:
  void configure(const Parameters& p) override {
    region_ = p.get_string("region", region_, "the scene's region removed objects are placed in");
    max_removals_ = static_cast<int>(
        p.get_int("max_removals", max_removals_, "objects removed at most before the target", Range::at_least(0)));
    motion_draws_ = static_cast<int>(p.get_int("motion_draws", motion_draws_,
                                               "draws of the samplers before a check failing for want of a motion "
                                               "counts as failed",
                                               Range::closed(1, 100)));
  }

  std::vector<std::string> required_kinds() const override { return retrieval::retrieval_sampler_kinds(); }

  Result solve(plugin::PlanningContext& context, const WorldState& initial) override {
    Result result;
    if (auto why = retrieval::retrieval_inputs_missing(context, "exhaustive")) {
      result.reason = *why;
      return result;
    }
    const auto start = Clock::now();
    const ObjectIndex target = context.scene().target;
    const int objects = static_cast<int>(context.scene().objects.size());
    retrieval::RemovalChecker checker(context, initial, region_);
    Counts counts;

    // Level k: every removable set of k objects with one order that removes it.
    std::map<Set, Removal> level{{Set(objects, false), Removal{}}};
    int k = 0;
    bool solved = false;
    for (; !level.empty() && !context.deadline.expired(); ++k) {
      for (const auto& [set, removal] : level) {
        if (context.deadline.expired()) break;
        ++counts.sets_checked;
        if (const auto salt = works(checker, removal, true, counts)) {
          checker.write_plan(removal.order, *salt, result);
          solved = true;
          break;
        }
      }
      if (solved || k >= max_removals_) break;
      level = next_level(context, checker, level, target, counts);
    }

    checker.record_times(result, start);
    result.counters[counter::removal_sets_checked] = counts.sets_checked;
    result.counters[counter::checks_without_motion] = counts.unproven;
    result.solved = solved;
    if (!solved) {
      const std::string size = std::to_string(k);
      result.reason = context.deadline.expired() ? "time limit reached while checking removal sets of " + size + " objects"
                      : level.empty()            ? "no removal set lets the target out"
                                                 : "no removal set of at most " + size + " objects lets the target out";
      if (!context.deadline.expired()) {
        result.reason += counts.unproven == 0
                             ? "; every removable set was checked"
                             : "; " + std::to_string(counts.unproven) + " checks failed only for want of a motion within " +
                                   std::to_string(motion_draws_) + " draws of the motion planner's budget, so this is no proof";
      }
    }
    return result;
  }

 private:
  struct Counts {
    std::uint64_t sets_checked = 0;
    std::uint64_t unproven = 0;  // checks that failed every draw for want of a motion
  };

  // The draw (salt) with which `removal.order` is removed (and the target retrieved,
  // with `retrieve`): its own draw first, then fresh ones while the failure is only a
  // motion not found; nothing when it fails.
  std::optional<std::uint64_t> works(retrieval::RemovalChecker& checker, const Removal& removal, bool retrieve,
                                     Counts& counts) const {
    for (int draw = 0; draw < motion_draws_; ++draw) {
      const std::uint64_t salt = removal.salt + static_cast<std::uint64_t>(draw);
      const retrieval::RemovalCheck check = retrieve ? checker.retrieve(removal.order, salt) : checker.remove(removal.order, salt);
      if (check.ok) return salt;
      if (!unproven(check)) return std::nullopt;
    }
    ++counts.unproven;
    return std::nullopt;
  }

  // Every removable set one object larger than those of `level`.
  std::map<Set, Removal> next_level(plugin::PlanningContext& context, retrieval::RemovalChecker& checker,
                                    const std::map<Set, Removal>& level, ObjectIndex target, Counts& counts) const {
    std::map<Set, Removal> next;
    for (const auto& [set, removal] : level) {
      for (ObjectIndex o = 0; o < set.size(); ++o) {
        if (context.deadline.expired()) return next;
        if (o == target || set[o]) continue;
        Set bigger = set;
        bigger[o] = true;
        if (next.count(bigger)) continue;  // already removable in another order
        Removal longer = removal;
        longer.order.push_back(o);
        if (const auto salt = works(checker, longer, false, counts)) {
          longer.salt = *salt;
          next.emplace(std::move(bigger), std::move(longer));
        }
      }
    }
    return next;
  }

  std::string region_ = "buffer";
  int max_removals_ = 1 << 20;
  int motion_draws_ = 3;  // draws of the samplers before a motion failure counts
};

}  // namespace

CLUTTERTAMP_EXPORT_TASK_PLANNER(Exhaustive, exhaustive,
                                "Brute force over removal sets and orders, smallest first: the optimal baseline", "0.1.0")
