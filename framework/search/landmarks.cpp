#include "search/landmarks.hpp"

#include <algorithm>
#include <deque>
#include <iterator>

namespace cluttertamp::search::detail {

namespace {

using Label = std::vector<FactId>;  // sorted

// Label propagation to a fixpoint: a fact's label is the intersection, over the
// operators adding it, of the union of their preconditions' labels, plus the fact.
class Labelling {
 public:
  Labelling(const RelaxedTask& relaxed, std::uint64_t budget)
      : relaxed_(relaxed), label_(relaxed.fact_count()), labelled_(relaxed.fact_count(), 0), budget_(budget) {}

  // False when the budget ran out first.
  bool run(const State& initial) {
    const auto& ops = relaxed_.ops();
    std::vector<int> unsatisfied(ops.size());
    for (std::size_t i = 0; i < ops.size(); ++i) unsatisfied[i] = static_cast<int>(ops[i].pre.size());
    std::vector<char> queued(label_.size(), 0), counted(label_.size(), 0);
    for (FactId f = 0; f < relaxed_.goal_fact(); ++f) {
      if (!relaxed_.holds_in(initial, f)) continue;
      label_[f] = {f};
      labelled_[f] = 1;
      queued[f] = 1;
      queue_.push_back(f);
    }
    for (int i : relaxed_.without_preconditions()) apply(i, queued);
    while (!queue_.empty()) {
      if (work_ > budget_) return false;
      const FactId f = queue_.front();
      queue_.pop_front();
      queued[f] = 0;
      for (int i : relaxed_.precondition_of(f)) {
        if (!counted[f]) --unsatisfied[i];
        if (unsatisfied[i] == 0) apply(i, queued);
      }
      counted[f] = 1;
    }
    return true;
  }

  bool labelled(FactId f) const { return labelled_[f]; }
  const Label& label(FactId f) const { return label_[f]; }
  bool reachable(int op) const {
    for (FactId p : relaxed_.ops()[op].pre) {
      if (!labelled_[p]) return false;
    }
    return true;
  }
  // The union of an operator's preconditions' labels.
  const Label& op_label(int op) {
    op_label_.clear();
    for (FactId p : relaxed_.ops()[op].pre) {
      merged_.clear();
      std::set_union(op_label_.begin(), op_label_.end(), label_[p].begin(), label_[p].end(), std::back_inserter(merged_));
      work_ += merged_.size();
      op_label_.swap(merged_);
    }
    return op_label_;
  }
  bool over_budget() const { return work_ > budget_; }
  void allow(std::uint64_t more) { budget_ += more; }

 private:
  void apply(int op, std::vector<char>& queued) {
    const Label& through = op_label(op);
    for (FactId e : relaxed_.ops()[op].eff) {
      candidate_ = through;
      const auto at = std::lower_bound(candidate_.begin(), candidate_.end(), e);
      if (at == candidate_.end() || *at != e) candidate_.insert(at, e);
      work_ += candidate_.size();
      if (labelled_[e]) {
        merged_.clear();
        std::set_intersection(label_[e].begin(), label_[e].end(), candidate_.begin(), candidate_.end(),
                              std::back_inserter(merged_));
        if (merged_.size() == label_[e].size()) continue;
        label_[e].swap(merged_);
      } else {
        label_[e] = candidate_;
        labelled_[e] = 1;
      }
      if (!queued[e]) {
        queued[e] = 1;
        queue_.push_back(e);
      }
    }
  }

  const RelaxedTask& relaxed_;
  std::vector<Label> label_;
  std::vector<char> labelled_;
  std::deque<FactId> queue_;
  Label op_label_, candidate_, merged_;
  std::uint64_t work_ = 0;
  std::uint64_t budget_;
};

bool contains(const Label& label, FactId f) { return std::binary_search(label.begin(), label.end(), f); }

}  // namespace

Landmarks::Landmarks(const RelaxedTask& relaxed, const State& initial, std::uint64_t work_budget) : relaxed_(relaxed) {
  const auto& ops = relaxed.ops();
  const FactId goal = relaxed.goal_fact();
  std::vector<int> goal_ops = relaxed.achievers(goal);
  Labelling labelling(relaxed, work_budget);
  complete_ = labelling.run(initial);
  if (complete_ && !labelling.labelled(goal)) return;  // unreachable even relaxed: the FF heuristic says so
  // Goal facts: in every goal disjunct (the goal operators' preconditions).
  Label in_every_disjunct;
  for (std::size_t k = 0; k < goal_ops.size(); ++k) {
    Label pre = ops[goal_ops[k]].pre;
    std::sort(pre.begin(), pre.end());
    if (k == 0) {
      in_every_disjunct = pre;
      continue;
    }
    Label both;
    std::set_intersection(in_every_disjunct.begin(), in_every_disjunct.end(), pre.begin(), pre.end(), std::back_inserter(both));
    in_every_disjunct.swap(both);
  }
  if (complete_) {
    for (FactId f : labelling.label(goal)) {
      if (f != goal) facts_.push_back(f);
    }
  } else {
    facts_ = in_every_disjunct;
  }
  labelling.allow(work_budget);  // as much again for the orders
  std::vector<int> index(relaxed.fact_count(), -1);
  for (std::size_t i = 0; i < facts_.size(); ++i) index[facts_[i]] = static_cast<int>(i);
  parents_.assign(facts_.size(), {});
  needed_by_.assign(facts_.size(), {});
  goal_.assign(facts_.size(), 0);
  cost_.assign(facts_.size(), 1.0);
  for (FactId f : in_every_disjunct) {
    if (index[f] >= 0) goal_[index[f]] = 1;
  }
  for (std::size_t i = 0; i < facts_.size(); ++i) {
    const FactId f = facts_[i];
    double cheapest = -1.0;
    for (int op : relaxed.achievers(f)) {
      if (complete_ && !labelling.reachable(op)) continue;
      if (cheapest < 0 || ops[op].cost < cheapest) cheapest = ops[op].cost;
    }
    if (cheapest >= 0) cost_[i] = cheapest;
    if (!complete_) continue;
    for (FactId p : labelling.label(f)) {
      if (p != f && index[p] >= 0) parents_[i].push_back(index[p]);
    }
    // Greedy-necessary: preconditions shared by every operator reachable without f.
    // (Past the budget, the landmarks left get none: fewer orders, same landmarks.)
    if (relaxed.holds_in(initial, f) || labelling.over_budget()) continue;
    bool first = true;
    Label shared;
    for (int op : relaxed.achievers(f)) {
      if (!labelling.reachable(op) || contains(labelling.op_label(op), f)) continue;
      Label pre = ops[op].pre;
      std::sort(pre.begin(), pre.end());
      if (first) {
        shared = pre;
        first = false;
      } else {
        Label both;
        std::set_intersection(shared.begin(), shared.end(), pre.begin(), pre.end(), std::back_inserter(both));
        shared.swap(both);
      }
    }
    for (FactId p : shared) {
      if (index[p] >= 0 && index[p] != static_cast<int>(i)) needed_by_[index[p]].push_back(static_cast<int>(i));
    }
  }
}

std::size_t Landmarks::order_count() const {
  std::size_t n = 0;
  for (std::size_t i = 0; i < facts_.size(); ++i) n += parents_[i].size() + needed_by_[i].size();
  return n;
}

LandmarkCount::LandmarkCount(const Landmarks& landmarks)
    : landmarks_(landmarks), words_(std::max<std::size_t>(1, (landmarks.size() + 63) / 64)), scratch_(words_) {}

void LandmarkCount::start(int id, const State& s) {
  accepted_.resize(static_cast<std::size_t>(id + 1) * words_, 0);
  std::uint64_t* a = accepted(id);
  std::fill(a, a + words_, 0);
  for (std::size_t i = 0; i < landmarks_.size(); ++i) {
    if (landmarks_.holds(static_cast<int>(i), s)) a[i >> 6] |= std::uint64_t{1} << (i & 63);
  }
}

void LandmarkCount::reach(int parent, int child, const State& child_state, bool is_new) {
  const std::uint64_t* before = accepted(parent);
  std::copy(before, before + words_, scratch_.begin());
  for (std::size_t i = 0; i < landmarks_.size(); ++i) {
    const int l = static_cast<int>(i);
    if (is_accepted(before, l) || !landmarks_.holds(l, child_state)) continue;
    const auto& parents = landmarks_.parents(l);
    if (std::all_of(parents.begin(), parents.end(), [&](int p) { return is_accepted(before, p); })) {
      scratch_[i >> 6] |= std::uint64_t{1} << (i & 63);
    }
  }
  if (is_new) {
    accepted_.resize(std::max(accepted_.size(), static_cast<std::size_t>(child + 1) * words_), 0);
    std::copy(scratch_.begin(), scratch_.end(), accepted(child));
  } else {
    std::uint64_t* a = accepted(child);
    for (std::size_t w = 0; w < words_; ++w) a[w] &= scratch_[w];
  }
}

double LandmarkCount::value(int id, const State& s) const {
  const std::uint64_t* a = accepted(id);
  double h = 0.0;
  for (std::size_t i = 0; i < landmarks_.size(); ++i) {
    const int l = static_cast<int>(i);
    if (!is_accepted(a, l)) {
      h += landmarks_.cost(l);
      continue;
    }
    if (landmarks_.holds(l, s)) continue;
    const auto& later = landmarks_.needed_by(l);
    if (landmarks_.is_goal(l) || std::any_of(later.begin(), later.end(), [&](int c) { return !is_accepted(a, c); })) {
      h += landmarks_.cost(l);
    }
  }
  return h;
}

}  // namespace cluttertamp::search::detail
