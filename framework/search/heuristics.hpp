#pragma once
// Internal: delete-relaxation heuristics over a grounded task.

#include <chrono>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "search/state_space.hpp"

namespace cluttertamp::search::detail {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// The delete relaxation: operators with their preconditions and adds (each conditional
/// effect a relaxed operator of its own), axioms at cost 0, and one operator per goal
/// disjunct reaching an artificial goal fact. Facts: the task's, then a complement per
/// fluent fact that some condition needs false (added by the operators deleting it),
/// then the goal fact.
class RelaxedTask {
 public:
  /// How an operator's cost enters the relaxation: as it is, as 1 (plan length), or
  /// plus one (LAMA's later iterations: zero-cost operators still count).
  enum class Costs { normal, one, plus_one };
  /// `left_out` (per operator, may be empty): operators the relaxation leaves out, as
  /// the search does (StateSpace::left_out).
  explicit RelaxedTask(const Task& task, Costs costs = Costs::normal, const std::vector<char>& left_out = {});
  RelaxedTask(const RelaxedTask&) = delete;  // its operators view its own arrays
  RelaxedTask& operator=(const RelaxedTask&) = delete;
  /// Explorations take the true facts and each operator's effects in `order`'s fact
  /// orders (a complement as its fact): among facts of equal cost the last taken comes
  /// first, so these orders decide the supporters where costs tie.
  void follow(const TieOrder& order);
  /// LM-cut looks at the clock between its rounds and throws TimeLimit after `at`: one
  /// evaluation on hundreds of blocks takes seconds.
  void set_deadline(std::chrono::steady_clock::time_point at) { deadline_ = at; }

  /// A relaxed operator; `pre` (sorted, no repeats) and `eff` view arrays the task
  /// keeps, one for all operators.
  struct Op {
    std::span<const FactId> pre;
    std::span<const FactId> eff;
    double cost;
    OperatorId origin;  ///< the task operator; -1 for axioms and goal operators
    bool conditional = false;  ///< one conditional effect of `origin` (pre holds its condition too)
  };

  /// h_max (max = true) or h_add of state s; fills cost and supporter per fact.
  double cost_to_goal(const State& s, bool max);
  /// h_FF; `preferred` receives the relaxed plan's operators applicable in s.
  double ff(const State& s, const StateSpace& space, std::vector<OperatorId>* preferred);
  /// LM-cut (admissible).
  double lmcut(const State& s);

  const std::vector<Op>& ops() const { return ops_; }
  /// Facts including the complements and the artificial goal fact, which is the last.
  std::size_t fact_count() const { return facts_; }
  FactId goal_fact() const { return goal_; }
  /// Whether relaxed fact f holds in state s (a complement: its fact does not).
  bool holds_in(const State& s, FactId f) const {
    if (f < task_facts_) return holds(s, f);
    return f < goal_ && !holds(s, complemented_[f - task_facts_]);
  }
  /// The relaxed operators fact f is a precondition of.
  std::span<const int> precondition_of(FactId f) const {
    return {triggers_.data() + trigger_start_[f], triggers_.data() + trigger_start_[f + 1]};
  }
  /// Operator i's effects (in follow()'s order) and preconditions counted, from the flat
  /// arrays the explorations read.
  std::span<const FactId> effects(int i) const {
    return {effects_.data() + effect_start_[i], effects_.data() + effect_start_[i + 1]};
  }
  const std::vector<int>& precondition_counts() const { return pre_count_; }
  std::span<const int> achievers(FactId f) const {
    return {achievers_.data() + achiever_start_[f], achievers_.data() + achiever_start_[f + 1]};
  }
  /// Task fact f's complement, or -1 when no condition needs f false.
  FactId complement_of(FactId f) const { return complement_[f]; }
  /// The task fact of complement c (task facts <= c < goal fact).
  FactId complemented(FactId c) const { return complemented_[c - task_facts_]; }
  const std::vector<int>& without_preconditions() const { return no_precondition_; }
  /// Whether task operator `op` has no relaxed operator because the search leaves it out.
  bool left_out(OperatorId op) const { return !left_out_.empty() && left_out_[op]; }

 private:
  std::chrono::steady_clock::time_point deadline_ = std::chrono::steady_clock::time_point::max();
  /// Fills the facts' costs and supporters (for whole-cost h_add of base_cost_, only the
  /// supporters); returns the goal fact's cost.
  double exploration(const State& s, bool max, const std::vector<double>& op_cost, bool stop_at_goal);
  template <bool Max, class Queue, class Value, class Record>
  void explore(Queue& queue, const State& s, const Value* cost_of, Value* fact_cost, Record* op_state, bool stop_at_goal);
  void lower_hmax(const std::vector<int>& cheaper, const std::vector<double>& op_cost);
  void build_operators(const Task& task, Costs costs, const std::vector<char>& left_out);
  void index_operators();

  std::vector<char> left_out_;  // per task operator, or empty
  FactId task_facts_;
  std::vector<FactId> complement_;    // per task fact: its complement, or -1
  std::vector<FactId> complemented_;  // per complement (from task_facts_ on): its fact
  std::size_t facts_;
  FactId goal_;
  std::vector<Op> ops_;
  std::vector<FactId> op_facts_;  // every operator's preconditions and effects, which ops_ view
  std::vector<std::uint32_t> achiever_start_;  // per fact: into achievers_
  std::vector<int> achievers_;                 // per fact: operators adding it
  std::vector<int> no_precondition_;
  // Scratch, reused between calls.
  std::vector<double> fact_cost_;
  std::vector<int> supporter_;
  std::vector<char> marked_fact_, used_origin_;  // h_FF's relaxed plan extraction
  struct OpState {
    int unsatisfied;   // preconditions not reached yet
    FactId costliest;  // h_max: a precondition of the largest cost (LM-cut's choice); -1: none
    double value;      // max or sum of the reached preconditions' costs
  };
  std::vector<OpState> op_state_;
  template <class Value>
  struct AddState {  // h_add needs no costliest precondition
    int unsatisfied;
    Value value;
  };
  std::vector<AddState<double>> add_state_;
  // Whole-cost h_add in 32 bits (whole_base_cost_ empty when costs are not whole).
  std::vector<AddState<std::int32_t>> whole_add_state_;
  std::vector<std::int32_t> whole_base_cost_, whole_fact_cost_;
  std::vector<int> pre_count_;
  std::vector<std::uint32_t> effect_start_, trigger_start_;  // per operator, per fact: into the flat arrays
  std::vector<FactId> effects_;
  std::vector<FactId> initial_order_;  // facts (not the goal fact) in the order true ones are taken
  std::vector<int> triggers_;  // per fact: the operators it is a precondition of
  std::vector<double> base_cost_;
  bool whole_costs_ = false;  // every base cost a whole number: LM-cut's reduced costs stay whole too
  std::vector<std::vector<FactId>> buckets_;  // the exploration's bucket queue, kept between calls
  // LM-cut scratch.
  std::vector<char> in_goal_zone_, reached_, in_cut_;
  std::vector<int> cut_;
  std::vector<FactId> open_;
  std::size_t origin_count_;
  std::vector<double> remaining_;      // per task operator: cost left in this LM-cut evaluation
  std::vector<double> lmcut_cost_;     // per relaxed operator: its origin's remaining cost
  std::vector<int> cheaper_;           // relaxed operators the last cut made cheaper
  std::vector<std::uint32_t> relaxed_start_;  // per task operator: into relaxed_of_
  std::vector<int> relaxed_of_;               // the relaxed operators of each task operator
  std::vector<char> origin_reduced_;  // per task operator: already reduced by the current cut
};

}  // namespace cluttertamp::search::detail
