#include <algorithm>
#include <cstddef>
#include <limits>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

#include "stream/searches.hpp"

namespace cluttertamp::stream::detail {

namespace {

// PDDLStream's adaptive algorithm: plan with optimistic outputs for the streams not yet
// evaluated, queue the plan's skeleton, refine the queue for a budget in proportion to
// the search's work, and raise the level (the complexity bound of optimistic instances
// and calls) when nothing new comes.
class AdaptiveSearch {
 public:
  AdaptiveSearch(SearchCore& core, SkeletonQueue& queue)
      : core_(core), base_(core.facts()), evaluator_(core.evaluator()), context_(core.context()),
        options_(core.options()), problem_(core.problem()), out_(core.out()), queue_(queue) {}

  void run();

 private:
  // Optimistic facts for every enabled instance within `level`; returns whether an
  // instance was left out for its complexity.
  bool instantiate_optimistic(int level);

  SearchCore& core_;
  FactBase& base_;
  StreamEvaluator& evaluator_;
  plugin::PlanningContext& context_;
  const StreamSearchOptions& options_;
  const StreamProblem& problem_;
  StreamSolution& out_;
  SkeletonQueue& queue_;
  std::optional<std::pair<std::size_t, int>> shortest_;  // the shortest plan found, and its level
  int level_ = 0;  // the complexity bound of optimistic instances and calls
};

bool AdaptiveSearch::instantiate_optimistic(int level) {
  base_.clear_optimistic();
  bool pruned = false;
  // A stream none of whose domain predicates gained facts since its last pass has no
  // new bindings (free inputs range over the real objects, which do not change here).
  const std::size_t streams = problem_.streams->streams.size();
  std::vector<std::size_t> seen(streams, std::numeric_limits<std::size_t>::max());
  for (bool changed = true; changed;) {
    changed = false;
    for (int s = 0; s < static_cast<int>(streams); ++s) {
      // High levels of a generative domain make many instances: keep the time limit.
      if (context_.deadline.expired()) throw search::TimeLimit("time limit (optimistic instantiation)");
      const StreamDecl& d = base_.decl(s);
      if (d.kind == StreamDecl::Kind::function) continue;
      if (d.is_test() && core_.negated_tests().count(d.certified.front().predicate)) continue;  // false until tested
      if (evaluator_.options_of(d).p_success == 0.0) continue;  // only real evaluations certify its facts
      std::size_t facts = 0;
      for (const pddl::Atom& a : d.domain) facts += base_.fact_count(a.predicate);
      if (std::exchange(seen[static_cast<std::size_t>(s)], facts) == facts) continue;
      // The bindings in one flat array (an input tuple per stride): millions of them
      // must not be millions of allocations to free when the time limit ends the pass.
      const std::size_t stride = d.inputs.size();
      std::vector<ObjectId> found;
      std::vector<int> found_complexity;
      base_.bindings(d.inputs, d.domain, true, [&](const std::vector<ObjectId>& inputs, int c) {
        core_.keep_time_limit();
        found.insert(found.end(), inputs.begin(), inputs.end());
        found_complexity.push_back(c);
      });
      std::vector<ObjectId> inputs(stride);
      for (std::size_t k = 0; k < found_complexity.size(); ++k) {
        core_.keep_time_limit();
        std::copy_n(found.begin() + static_cast<std::ptrdiff_t>(k * stride), stride, inputs.begin());
        const int domain_complexity = found_complexity[k];
        const int id = base_.instance(s, inputs);
        Instance& inst = base_.instance_at(id);
        if (inst.real && (inst.exhausted || inst.disabled)) continue;
        // Not counting calls here: a stream that keeps failing must not starve every
        // fact that depends on its next output (advance() bounds calls per level).
        const int complexity = domain_complexity + 1;
        if (complexity > level) {
          pruned = true;
          continue;
        }
        if (inst.optimistic_outputs.size() != d.outputs.size()) {
          for (const pddl::Term& o : d.outputs) {
            ObjectRecord r;
            r.name = o.name;  // "?p" -> "@p12" (assigned in steps: GCC 12 warns on "@" + string)
            r.name[0] = '@';
            r.name += std::to_string(id);
            r.optimistic = true;
            r.maker = id;
            inst.optimistic_outputs.push_back(base_.add_object(std::move(r)));
          }
        }
        const Env env = base_.env_of(inst, &inst.optimistic_outputs);
        for (const pddl::Atom& a : d.certified) {
          if (const auto fact = base_.ground(a, env)) changed |= base_.add_fact(*fact, FactInfo{true, complexity, id});
        }
      }
    }
  }
  return pruned;
}

void AdaptiveSearch::run() {
  while (!context_.deadline.expired()) {
    evaluator_.close_real();
    const bool pruned = instantiate_optimistic(level_);
    const auto steps = core_.plan_symbolic(true);
    bool fresh = false, too_long = false;
    if (steps) {
      // Plans may grow by plan_growth actions per level above the one of the shortest
      // plan found: sampling the short skeletons again beats detours through real
      // values. (With one action per level, stacked4 spent four levels resampling the
      // target's blocked pick before the five-step plan that moves two objects.)
      if (!shortest_ || steps->size() < shortest_->first) shortest_ = {steps->size(), level_};
      too_long = steps->size() > shortest_->first + static_cast<std::size_t>(options_.plan_growth * (level_ - shortest_->second));
    }
    if (steps && !too_long) {
      auto sk = queue_.skeleton_of(*steps);
      if (!sk) {
        out_.reason = "internal error: an optimistic plan does not hold when checked";
        return;
      }
      if (sk->stream_plan.empty() && core_.verify(*steps)) {
        if (core_.accept(*steps) || core_.improved_enough()) return;
        continue;  // the next search is bounded by the best cost
      }
      if (queue_.add(std::move(*sk))) {
        ++out_.statistics.skeletons;
        fresh = true;
      }
    }
    if (options_.trace) {
      std::ostringstream line;
      line << "level " << level_ << ": " << (steps ? "plan of " + std::to_string(steps->size()) + " steps" : "no plan")
           << (fresh ? " (queued)" : "") << (too_long ? " (too long)" : "") << ", queue " << queue_.size() << ", calls " << out_.statistics.stream_calls
           << ", objects " << base_.object_count() << ", facts " << base_.facts().size() << ", operators "
           << core_.last_grounding().operators << " (" << core_.last_grounding().reused_instances << " instances re-used)";
      if (steps) {
        line << ":";
        for (const Step& st : *steps) {
          line << " (" << st.action->name;
          for (ObjectId o : st.args) line << ' ' << base_.object(o).name;
          line << ')';
        }
      }
      options_.trace(line.str());
    }
    bool progress = false;
    const double budget = std::max(options_.min_sampling, core_.last_search_work() * options_.sampling_ratio);
    if (auto done = queue_.refine(budget, level_, progress); done && core_.accept(std::move(*done))) return;
    if (core_.improved_enough()) return;
    if (!steps || too_long || (!fresh && !progress)) {
      bool any_disabled = false;
      for (std::size_t i = 0; i < base_.instance_count(); ++i) {
        Instance& inst = base_.instance_at(static_cast<int>(i));
        any_disabled |= inst.disabled;
        inst.disabled = false;
      }
      if (!steps && !pruned && !any_disabled && queue_.empty()) {
        out_.reason = "no plan exists: not even with optimistic stream outputs";
        return core_.settle();
      }
      ++level_;
      out_.statistics.level = static_cast<std::uint64_t>(level_);
    }
  }
}

}  // namespace

void adaptive_search(SearchCore& core, SkeletonQueue& queue) { AdaptiveSearch(core, queue).run(); }

}  // namespace cluttertamp::stream::detail
