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
  const std::span<const int> goal_ops = relaxed.achievers(goal);
  Labelling labelling(relaxed, work_budget);
  complete_ = labelling.run(initial);
  if (complete_ && !labelling.labelled(goal)) return;  // unreachable even relaxed: the FF heuristic says so
  // Goal facts: in every goal disjunct (the goal operators' preconditions).
  Label in_every_disjunct;
  for (std::size_t k = 0; k < goal_ops.size(); ++k) {
    const Label pre(ops[goal_ops[k]].pre.begin(), ops[goal_ops[k]].pre.end());  // sorted
    if (k == 0) {
      in_every_disjunct = pre;
      continue;
    }
    Label both;
    std::set_intersection(in_every_disjunct.begin(), in_every_disjunct.end(), pre.begin(), pre.end(), std::back_inserter(both));
    in_every_disjunct.swap(both);
  }
  std::vector<FactId> facts_;
  if (complete_) {
    for (FactId f : labelling.label(goal)) {
      if (f != goal) facts_.push_back(f);
    }
  } else {
    facts_ = in_every_disjunct;
  }
  for (FactId f : facts_) atoms_.push_back({f});
  labelling.allow(work_budget);  // as much again for the orders
  std::vector<int> index(relaxed.fact_count(), -1);
  for (std::size_t i = 0; i < facts_.size(); ++i) index[facts_[i]] = static_cast<int>(i);
  parents_.assign(facts_.size(), {});
  needed_by_.assign(facts_.size(), {});
  reasonable_.assign(facts_.size(), {});
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
      const Label pre(ops[op].pre.begin(), ops[op].pre.end());  // sorted
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
  // Distinct pairs: a greedy-necessary order may also be a parent's.
  std::size_t n = 0;
  for (std::size_t i = 0; i < atoms_.size(); ++i) {
    n += parents_[i].size();
    for (int child : needed_by_[i]) {
      const auto& p = parents_[child];
      n += std::find(p.begin(), p.end(), static_cast<int>(i)) == p.end();
    }
  }
  return n;
}

std::size_t Landmarks::disjunctive_count() const {
  return static_cast<std::size_t>(
      std::count_if(atoms_.begin(), atoms_.end(), [](const std::vector<FactId>& a) { return a.size() > 1; }));
}

LandmarkCount::LandmarkCount(const Landmarks& landmarks)
    : landmarks_(landmarks), words_(std::max<std::size_t>(1, (landmarks.size() + 63) / 64)) {}

void LandmarkCount::grow(int id) {
  const std::size_t size = static_cast<std::size_t>(id + 1) * words_;
  if (past_.size() < size) {
    past_.resize(size, 0);
    future_.resize(size, 0);
  }
}

void LandmarkCount::start(int id, const State& s) {
  grow(id);
  std::uint64_t* past = bits(past_, id);
  std::uint64_t* future = bits(future_, id);
  std::fill(past, past + words_, 0);
  std::fill(future, future + words_, 0);
  const int n = static_cast<int>(landmarks_.size());
  for (int l = 0; l < n; ++l) {
    if (!landmarks_.holds(l, s)) {
      set(future, l);
      continue;
    }
    set(past, l);
    // True initially but ordered after a landmark that is not: it must come again.
    auto not_true = [&](int p) { return !landmarks_.holds(p, s); };
    const auto& parents = landmarks_.parents(l);
    const auto& reasonable = landmarks_.reasonable_parents(l);
    if (std::any_of(parents.begin(), parents.end(), not_true) ||
        std::any_of(reasonable.begin(), reasonable.end(), not_true)) {
      set(future, l);
    }
  }
}

void LandmarkCount::reach(int parent, int child, const State& parent_state, const State& child_state, bool is_new) {
  if (parent == child) return;
  grow(std::max(parent, child));
  const std::uint64_t* parent_past = bits(past_, parent);
  const std::uint64_t* parent_future = bits(future_, parent);
  std::uint64_t* past = bits(past_, child);
  std::uint64_t* future = bits(future_, child);
  if (is_new) {
    std::fill(past, past + words_, ~std::uint64_t{0});
    std::fill(future, future + words_, 0);
  }
  const int n = static_cast<int>(landmarks_.size());
  std::vector<char>& holds = holds_;  // scratch, kept to spare an allocation per transition
  holds.resize(static_cast<std::size_t>(n));
  for (int l = 0; l < n; ++l) holds[l] = landmarks_.holds(l, child_state);
  for (int l = 0; l < n; ++l) {
    if (!test(parent_future, l)) continue;
    if (!holds[l]) {
      set(future, l);
      if (!test(parent_past, l)) reset(past, l);
    } else if (landmarks_.holds(l, parent_state)) {
      set(future, l);  // true already: not achieved by this transition
    }
  }
  for (int l = 0; l < n; ++l) {
    if (holds[l]) {
      const auto& before = landmarks_.reasonable_parents(l);
      if (std::any_of(before.begin(), before.end(), [&](int p) { return !test(past, p); })) set(future, l);
      continue;
    }
    const auto& later = landmarks_.needed_by(l);
    if (landmarks_.is_goal(l) || std::any_of(later.begin(), later.end(), [&](int c) { return !test(past, c); })) {
      set(future, l);
    }
    const auto& before = landmarks_.reasonable_parents(l);
    if (std::any_of(before.begin(), before.end(), [&](int p) { return !test(past, p); })) set(future, l);
  }
}

double LandmarkCount::value(int id, const State&) const {
  const std::uint64_t* future = bits(future_, id);
  double h = 0.0;
  const int n = static_cast<int>(landmarks_.size());
  for (int l = 0; l < n; ++l) {
    if (test(future, l)) h += landmarks_.cost(l);
  }
  return h;
}

}  // namespace cluttertamp::search::detail
