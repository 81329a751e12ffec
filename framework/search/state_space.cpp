#include "search/state_space.hpp"

#include <algorithm>

namespace cluttertamp::search::detail {

StateSpace::StateSpace(const Task& task, TieOrder order, std::vector<char> left_out)
    : task_(task), words_((task.fact_count() + 63) / 64 + 1), order_(std::move(order)), left_out_(std::move(left_out)) {
  const auto searched = [&](OperatorId op) { return left_out_.empty() || !left_out_[op]; };
  const auto ops = static_cast<OperatorId>(task.operators.size());
  precondition_start_.reserve(task.operators.size() + 1);
  negative_start_.reserve(task.operators.size());
  trigger_start_.assign(task.fact_count() + 1, 0);
  for (OperatorId op = 0; op < ops; ++op) {
    const Condition& pre = task.operators[op].precondition;
    precondition_start_.push_back(static_cast<std::uint32_t>(precondition_facts_.size()));
    precondition_facts_.insert(precondition_facts_.end(), pre.positive.begin(), pre.positive.end());
    negative_start_.push_back(static_cast<std::uint32_t>(precondition_facts_.size()));
    precondition_facts_.insert(precondition_facts_.end(), pre.negative.begin(), pre.negative.end());
    if (!searched(op)) continue;
    if (pre.positive.empty()) always_.push_back(op);
    else ++trigger_start_[static_cast<std::size_t>(pre.positive.front()) + 1];
  }
  precondition_start_.push_back(static_cast<std::uint32_t>(precondition_facts_.size()));
  for (std::size_t f = 0; f < task.fact_count(); ++f) trigger_start_[f + 1] += trigger_start_[f];
  triggered_.resize(trigger_start_.back());
  std::vector<std::uint32_t> next(trigger_start_.begin(), trigger_start_.end() - 1);
  for (OperatorId op = 0; op < ops; ++op) {  // in operator order within each fact
    const auto& positive = task.operators[op].precondition.positive;
    if (!positive.empty() && searched(op)) triggered_[next[positive.front()]++] = op;
  }
  for (FactId f = 0; f < static_cast<FactId>(task.fact_count()); ++f) {
    if (task.derived[f]) derived_facts_.push_back(f);
  }
  cost_.reserve(task.operators.size());
  for (const Operator& op : task.operators) cost_.push_back(op.cost);
}

State StateSpace::initial() const {
  State s(words_, 0);
  for (FactId f : task_.initial) set(s, f);
  evaluate_axioms(s);
  return s;
}

bool StateSpace::satisfied(const State& s, const Condition& c) const {
  for (FactId f : c.positive) {
    if (!holds(s, f)) return false;
  }
  for (FactId f : c.negative) {
    if (holds(s, f)) return false;
  }
  return true;
}

bool StateSpace::is_goal(const State& s) const {
  for (const Condition& c : task_.goal) {
    if (satisfied(s, c)) return true;
  }
  return false;
}

State StateSpace::apply(const State& s, OperatorId id) const {
  State next;
  apply(s, id, next);
  return next;
}

void StateSpace::apply(const State& s, OperatorId id, State& next) const {
  const Operator& op = task_.operators[id];
  next.assign(s.begin(), s.end());
  // Conditions of conditional effects are read in s, the state before the action; all
  // deletes come before all adds.
  for (FactId f : op.del) clear(next, f);
  for (const ConditionalEffect& c : op.conditional) {
    if (!satisfied(s, c.condition)) continue;
    for (FactId f : c.del) clear(next, f);
  }
  for (FactId f : op.add) set(next, f);
  for (const ConditionalEffect& c : op.conditional) {
    if (!satisfied(s, c.condition)) continue;
    for (FactId f : c.add) set(next, f);
  }
  evaluate_axioms(next);
}

void StateSpace::evaluate_axioms(State& s) const {
  if (task_.axioms.empty()) return;
  for (FactId f : derived_facts_) clear(s, f);
  std::size_t begin = 0;
  while (begin < task_.axioms.size()) {
    std::size_t end = begin;
    while (end < task_.axioms.size() && task_.axioms[end].stratum == task_.axioms[begin].stratum) ++end;
    bool changed = true;
    while (changed) {
      changed = false;
      for (std::size_t i = begin; i < end; ++i) {
        const Axiom& a = task_.axioms[i];
        if (!holds(s, a.head) && satisfied(s, a.body)) {
          set(s, a.head);
          changed = true;
        }
      }
    }
    begin = end;
  }
}

void StateSpace::applicable_operators(const State& s, std::vector<OperatorId>& out) const {
  out.clear();
  for_each_applicable(s, [&](OperatorId op) { out.push_back(op); });
  const std::vector<std::uint32_t>& rank = order_.successor_rank;
  if (!rank.empty()) std::sort(out.begin(), out.end(), [&](OperatorId a, OperatorId b) { return rank[a] < rank[b]; });
}

template <class F>
void StateSpace::for_each_applicable(const State& s, const F& f) const {
  for (OperatorId op : always_) {
    if (applicable(s, op)) f(op);
  }
  for (std::size_t w = 0; w < s.size(); ++w) {
    std::uint64_t bits = s[w];
    while (bits) {
      const int bit = __builtin_ctzll(bits);
      bits &= bits - 1;
      const FactId fact = static_cast<FactId>(w * 64 + static_cast<std::size_t>(bit));
      if (fact >= static_cast<FactId>(trigger_start_.size()) - 1) break;
      for (std::uint32_t k = trigger_start_[fact]; k < trigger_start_[fact + 1]; ++k) {
        if (applicable(s, triggered_[k])) f(triggered_[k]);
      }
    }
  }
}

std::vector<FactId> StateSpace::facts(const State& s) const {
  std::vector<FactId> out;
  for (FactId f = 0; f < static_cast<FactId>(task_.fact_count()); ++f) {
    if (holds(s, f)) out.push_back(f);
  }
  return out;
}

}  // namespace cluttertamp::search::detail
