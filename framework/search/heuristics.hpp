#pragma once
// Internal: delete-relaxation heuristics over a grounded task.

#include <chrono>
#include <limits>
#include <vector>

#include "search/state_space.hpp"

namespace cluttertamp::search::detail {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// The delete relaxation: operators with their positive preconditions and adds (each
/// conditional effect a relaxed operator of its own), axioms at cost 0, and one
/// operator per goal disjunct reaching an artificial goal fact.
class RelaxedTask {
 public:
  explicit RelaxedTask(const Task& task);
  /// LM-cut looks at the clock between its rounds and throws TimeLimit after `at`: one
  /// evaluation on hundreds of blocks takes seconds.
  void set_deadline(std::chrono::steady_clock::time_point at) { deadline_ = at; }

  struct Op {
    std::vector<FactId> pre;
    std::vector<FactId> eff;
    double cost;
    OperatorId origin;  ///< the task operator; -1 for axioms and goal operators
  };

  /// h_max (max = true) or h_add of state s; fills cost and supporter per fact.
  double cost_to_goal(const State& s, bool max);
  /// h_FF; `preferred` receives the relaxed plan's operators applicable in s.
  double ff(const State& s, const StateSpace& space, std::vector<OperatorId>* preferred);
  /// LM-cut (admissible).
  double lmcut(const State& s);

 private:
  std::chrono::steady_clock::time_point deadline_ = std::chrono::steady_clock::time_point::max();
  void exploration(const State& s, bool max, const std::vector<double>& op_cost, bool stop_at_goal);

  std::size_t facts_;
  FactId goal_;
  std::vector<Op> ops_;
  std::vector<std::vector<int>> precondition_of_;
  std::vector<std::vector<int>> achievers_;  // per fact: operators adding it
  std::vector<int> no_precondition_;
  // Scratch, reused between calls.
  std::vector<double> fact_cost_;
  std::vector<int> supporter_;
  std::vector<int> unsatisfied_;
  std::vector<double> op_value_;
  std::vector<double> base_cost_;
  // LM-cut scratch.
  std::vector<FactId> pcf_;
  std::vector<char> in_goal_zone_, reached_, in_cut_;
  std::vector<int> cut_;
  std::vector<FactId> open_;
  std::size_t origin_count_;
  std::vector<double> remaining_;      // per task operator: cost left in this LM-cut evaluation
  std::vector<char> origin_reduced_;  // per task operator: already reduced by the current cut
};

}  // namespace cluttertamp::search::detail
