// Richter, Helmert & Westphal's landmarks (AAAI 2008), as LAMA finds them.
#include <algorithm>
#include <deque>
#include <map>
#include <string>
#include <unordered_map>

#include "cluttertamp/search/grounding.hpp"
#include "search/landmarks.hpp"
#include "search/mutex_groups.hpp"

namespace cluttertamp::search::detail {

namespace {

// Order strength: a greedy-necessary order is also natural.
enum class Order { greedy_necessary = 0, natural = 1 };

// The predicate of "(pred a b)".
std::string predicate_of(const std::string& fact) {
  std::size_t begin = fact.empty() || fact[0] != '(' ? 0 : 1;
  std::size_t end = fact.find_first_of(" )", begin);
  return fact.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
}

bool sorted_contains(const std::vector<FactId>& v, FactId f) { return std::binary_search(v.begin(), v.end(), f); }

}  // namespace

class RhwFactory {
  struct Variable {
    std::vector<FactId> facts;
    std::vector<std::vector<int>> successors;  // per value (the last: none of those)
    int initial;
  };

 public:
  RhwFactory(const RelaxedTask& relaxed, const Task& task, const State& initial, std::uint64_t budget,
             std::chrono::steady_clock::time_point deadline, const MutexGroups* mutexes)
      : relaxed_(relaxed), task_(task), budget_(budget), deadline_(deadline), out_(relaxed) {
    const std::size_t n = relaxed.fact_count();
    initially_.resize(n);
    for (FactId f = 0; f < static_cast<FactId>(n); ++f) {
      initially_[f] = relaxed.holds_in(initial, f);
      if (initially_[f]) initial_facts_.push_back(f);
    }
    build_classes();
    build_variables(mutexes ? *mutexes : find_mutex_groups(task_, budget_ / 4));
    atomic_of_.assign(n, -1);
    disjunctive_of_.assign(n, -1);
    reached_.resize(n);
  }

  Landmarks run() {
    add_goal_landmarks();
    while (!open_.empty()) {
      if (work_ >= budget_) {
        out_.complete_ = false;
        break;
      }
      if (std::chrono::steady_clock::now() >= deadline_) throw TimeLimit("time limit (finding landmarks)");
      const int l = open_.front();
      open_.pop_front();
      if (dead_[l] || holds_initially(l)) continue;
      explore_without(atoms_[l]);
      const std::vector<int> achievers = first_achievers(l);  // found once: lookahead_orders keeps reached_
      shared_precondition_landmarks(l, achievers);
      lookahead_orders(l);
      disjunctive_precondition_landmarks(l, achievers);
    }
    add_forward_orders();
    return finish();
  }

 private:
  // --- set-up -------------------------------------------------------------------------

  // Disjunctive landmarks join facts of one predicate only; complements and the goal
  // fact join none (-1).
  void build_classes() {
    class_.assign(relaxed_.fact_count(), -1);
    std::unordered_map<std::string, int> index;
    for (FactId f = 0; f < static_cast<FactId>(task_.fact_count()); ++f) {
      class_[f] = index.emplace(predicate_of(task_.fact_names[f]), static_cast<int>(index.size())).first->second;
    }
  }

  // Variables of several facts, and their transition graphs. Value k < size is the
  // variable's k-th fact; value size is "none of those".
  void build_variables(const MutexGroups& mutexes) {
    groups_of_.assign(relaxed_.fact_count(), {});
    for (std::size_t g = 0; g < mutexes.groups.size(); ++g) {
      for (FactId f : mutexes.groups[g]) groups_of_[f].push_back(static_cast<int>(g));
    }
    var_of_.assign(relaxed_.fact_count(), -1);
    value_of_.assign(relaxed_.fact_count(), -1);
    for (const std::vector<FactId>& facts : mutexes.variables) {
      if (facts.size() < 2) continue;
      const int v = static_cast<int>(variables_.size());
      for (std::size_t k = 0; k < facts.size(); ++k) {
        var_of_[facts[k]] = v;
        value_of_[facts[k]] = static_cast<int>(k);
      }
      Variable var;
      var.facts = facts;
      var.successors.assign(var.facts.size() + 1, {});
      var.initial = static_cast<int>(var.facts.size());
      for (std::size_t k = 0; k < var.facts.size(); ++k) {
        if (initially_[var.facts[k]]) var.initial = static_cast<int>(k);
      }
      variables_.push_back(std::move(var));
    }
    for (OperatorId o = 0; o < static_cast<OperatorId>(task_.operators.size()); ++o) {
      if (relaxed_.left_out(o)) continue;
      const Operator& op = task_.operators[o];
      dtg_edges(op.precondition.positive, nullptr, op.add, op.del);
      for (const ConditionalEffect& c : op.conditional) {
        std::vector<FactId> del = op.del;
        del.insert(del.end(), c.del.begin(), c.del.end());
        dtg_edges(op.precondition.positive, &c.condition.positive, c.add, del);
      }
    }
    for (Variable& var : variables_) {
      for (auto& s : var.successors) {
        std::sort(s.begin(), s.end());
        s.erase(std::unique(s.begin(), s.end()), s.end());
      }
    }
  }

  // The value of variable v a condition requires, or -1.
  int required(int v, const std::vector<FactId>& condition) const {
    for (FactId f : condition) {
      if (var_of_[f] == v) return value_of_[f];
    }
    return -1;
  }

  void dtg_edges(const std::vector<FactId>& pre, const std::vector<FactId>* condition, const std::vector<FactId>& add,
                 const std::vector<FactId>& del) {
    auto edge = [&](int v, int from_pre, int from_condition, int to) {
      Variable& var = variables_[v];
      if (from_pre >= 0 && from_condition >= 0 && from_pre != from_condition) return;  // never applies
      const int from = from_pre >= 0 ? from_pre : from_condition;
      if (from >= 0) {
        if (from != to) var.successors[from].push_back(to);
        return;
      }
      for (int k = 0; k < static_cast<int>(var.successors.size()); ++k) {
        if (k != to) var.successors[k].push_back(to);
      }
    };
    auto condition_value = [&](int v) { return condition ? required(v, *condition) : -1; };
    std::vector<int>& changed = changed_;
    changed.clear();
    for (FactId f : add) {
      const int v = var_of_[f];
      if (v < 0) continue;
      changed.push_back(v);
      edge(v, required(v, pre), condition_value(v), value_of_[f]);
    }
    for (FactId f : del) {
      const int v = var_of_[f];
      if (v < 0 || std::find(changed.begin(), changed.end(), v) != changed.end()) continue;
      // The fact goes and no other of its variable comes: "none of those" follows it.
      edge(v, value_of_[f], -1, static_cast<int>(variables_[v].facts.size()));
    }
  }

  // --- landmarks and orders -----------------------------------------------------------

  int add_landmark(std::vector<FactId> atoms, bool goal) {
    const int l = static_cast<int>(atoms_.size());
    std::sort(atoms.begin(), atoms.end());
    for (FactId f : atoms) (atoms.size() == 1 ? atomic_of_ : disjunctive_of_)[f] = l;
    atoms_.push_back(std::move(atoms));
    goal_.push_back(goal);
    dead_.push_back(0);
    parents_.emplace_back();
    unreached_.emplace_back();
    open_.push_back(l);
    return l;
  }

  void order(int from, int to, Order type) {
    if (from == to) return;
    auto [at, inserted] = parents_[to].emplace(from, type);
    if (!inserted && type < at->second) at->second = type;
  }

  void add_goal_landmarks() {
    // Facts in every goal disjunct: the goal operators' shared preconditions.
    std::vector<FactId> shared;
    bool first = true;
    for (int op : relaxed_.achievers(relaxed_.goal_fact())) {
      const std::vector<FactId> pre(relaxed_.ops()[op].pre.begin(), relaxed_.ops()[op].pre.end());  // sorted
      shared = first ? pre : intersection(shared, pre);
      first = false;
    }
    for (FactId f : shared) add_landmark({f}, true);
  }

  void add_atomic(FactId f, int child, Order type) {
    if (atomic_of_[f] >= 0) {
      order(atomic_of_[f], child, type);
      return;
    }
    const int l = add_landmark({f}, false);
    order(l, child, type);
    // A fact is a stronger landmark than a disjunction holding it: the disjunction goes,
    // and what was ordered before it is ordered (naturally) before the fact.
    if (const int d = disjunctive_of_[f]; d >= 0 && !dead_[d]) {
      dead_[d] = 1;
      for (FactId g : atoms_[d]) disjunctive_of_[g] = -1;
      for (auto [parent, t] : parents_[d]) order(parent, l, Order::natural);
      parents_[d].clear();
      unreached_[d].clear();
    }
  }

  void add_disjunctive(const std::vector<FactId>& atoms, int child) {
    for (FactId f : atoms) {
      if (atomic_of_[f] >= 0) return;  // the fact is stronger; its order would not hold
    }
    for (FactId f : atoms) {
      const int d = disjunctive_of_[f];
      if (d < 0) continue;
      // Overlapping an existing disjunction: order that one when it holds all of these.
      if (std::all_of(atoms.begin(), atoms.end(), [&](FactId g) { return sorted_contains(atoms_[d], g); })) {
        order(d, child, Order::greedy_necessary);
      }
      return;
    }
    order(add_landmark(atoms, false), child, Order::greedy_necessary);
  }

  bool holds_initially(int l) const {
    return std::any_of(atoms_[l].begin(), atoms_[l].end(), [&](FactId f) { return initially_[f]; });
  }

  // --- the relaxed task without a landmark ----------------------------------------------

  // reached_: facts reachable in the delete relaxation when no operator may achieve one
  // of `excluded`: an operator achieving one unconditionally is left out whole, a
  // conditional effect (or axiom) achieving one is left out alone.
  void explore_without(const std::vector<FactId>& excluded) {
    const auto& ops = relaxed_.ops();
    std::fill(reached_.begin(), reached_.end(), 0);
    is_excluded_fact_.assign(relaxed_.fact_count(), 0);
    for (FactId f : excluded) is_excluded_fact_[f] = 1;
    // Per task operator: left out (origin_out_ is all zero between calls).
    std::vector<char>& origin_out = origin_out_;
    origin_out.resize(task_.operators.size(), 0);
    std::vector<OperatorId>& left_out = left_out_;
    left_out.clear();
    for (FactId f : excluded) {
      for (int i : relaxed_.achievers(f)) {
        if (ops[i].origin >= 0 && !ops[i].conditional && !origin_out[ops[i].origin]) {
          origin_out[ops[i].origin] = 1;
          left_out.push_back(ops[i].origin);
        }
      }
    }
    unsatisfied_.assign(relaxed_.precondition_counts().begin(), relaxed_.precondition_counts().end());
    std::vector<FactId>& queue = queue_;  // first in, first out from `head`
    queue.clear();
    std::size_t head = 0;
    auto reach = [&](FactId f) {
      if (reached_[f] || is_excluded_fact_[f]) return;
      reached_[f] = 1;
      queue.push_back(f);
    };
    // An op excluded for a conditional achiever still achieves its other effects.
    auto apply = [&](int i) {
      if (ops[i].origin >= 0 && origin_out[ops[i].origin]) return;
      for (FactId e : relaxed_.effects(i)) reach(e);  // the set reached is the same in any order
    };
    for (FactId f : initial_facts_) reach(f);
    for (int i : relaxed_.without_preconditions()) apply(i);
    while (head < queue.size()) {
      const FactId f = queue[head++];
      for (int i : relaxed_.precondition_of(f)) {
        ++work_;
        if (--unsatisfied_[i] == 0) apply(i);
      }
    }
    for (OperatorId o : left_out) origin_out[o] = 0;
  }

  bool possibly_first(int op) const {
    for (FactId p : relaxed_.ops()[op].pre) {
      if (!reached_[p]) return false;
    }
    return true;
  }

  // The first achievers of landmark l: achievers applicable without it.
  std::vector<int> first_achievers(int l) {
    std::vector<int> out;
    for (FactId f : atoms_[l]) {
      for (int op : relaxed_.achievers(f)) {
        ++work_;
        if (relaxed_.ops()[op].eff.front() == relaxed_.goal_fact()) continue;
        if (possibly_first(op) && std::find(out.begin(), out.end(), op) == out.end()) out.push_back(op);
      }
    }
    return out;
  }

  static std::vector<FactId> intersection(const std::vector<FactId>& a, const std::vector<FactId>& b) {
    std::vector<FactId> both;
    std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(both));
    return both;
  }

  std::vector<FactId> sorted_pre(int op) const {  // a relaxed operator's pre is sorted
    return {relaxed_.ops()[op].pre.begin(), relaxed_.ops()[op].pre.end()};
  }

  void shared_precondition_landmarks(int l, const std::vector<int>& achievers) {
    if (achievers.empty()) return;
    std::vector<FactId> shared = sorted_pre(achievers.front());
    for (std::size_t k = 1; k < achievers.size() && !shared.empty(); ++k) shared = intersection(shared, sorted_pre(achievers[k]));
    for (FactId f : shared) add_atomic(f, l, Order::greedy_necessary);
  }

  void disjunctive_precondition_landmarks(int l, const std::vector<int>& achievers) {
    if (achievers.empty()) return;
    std::map<int, std::vector<FactId>> by_class;
    std::map<int, std::size_t> used_by;
    for (int op : achievers) {
      std::vector<int> classes;
      for (FactId p : relaxed_.ops()[op].pre) {
        const int c = class_[p];
        if (c < 0 || atomic_of_[p] >= 0) continue;
        by_class[c].push_back(p);
        if (std::find(classes.begin(), classes.end(), c) == classes.end()) classes.push_back(c);
      }
      for (int c : classes) ++used_by[c];
    }
    for (auto& [c, facts] : by_class) {
      if (used_by[c] != achievers.size()) continue;
      std::sort(facts.begin(), facts.end());
      facts.erase(std::unique(facts.begin(), facts.end()), facts.end());
      if (facts.size() < 2 || facts.size() > 4) continue;
      if (std::any_of(facts.begin(), facts.end(), [&](FactId f) { return initially_[f]; })) continue;
      add_disjunctive(facts, l);
    }
  }

  // Values of the landmark's variable every transition-graph path from the initial value
  // to it passes through (over values reachable without it), and facts not reachable
  // without it (ordered after it once known to be landmarks).
  void lookahead_orders(int l) {
    auto& bits = unreached_[l];
    bits.assign((reached_.size() + 63) / 64, 0);
    for (std::size_t f = 0; f < reached_.size(); ++f) {
      if (!reached_[f]) bits[f >> 6] |= std::uint64_t{1} << (f & 63);
    }
    work_ += reached_.size() / 8;
    if (atoms_[l].size() != 1) return;
    const FactId target = atoms_[l].front();
    const int v = var_of_[target];
    if (v < 0) return;
    const Variable& var = variables_[v];
    const int goal_value = value_of_[target];
    for (int x = 0; x < static_cast<int>(var.facts.size()); ++x) {
      if (x == goal_value || !reached_[var.facts[x]]) continue;
      if (critical(var, goal_value, x)) add_atomic(var.facts[x], l, Order::natural);
    }
  }

  bool value_reached(const Variable& var, int x) const {
    return x == static_cast<int>(var.facts.size()) || reached_[var.facts[x]];
  }

  // Whether every path from the variable's initial value to `goal_value` passes `excluded`.
  bool critical(const Variable& var, int goal_value, int excluded) {
    if (excluded == var.initial) return true;
    std::vector<char> closed(var.successors.size(), 0);
    std::deque<int> queue{var.initial};
    closed[var.initial] = 1;
    while (!queue.empty()) {
      const int x = queue.front();
      queue.pop_front();
      for (int y : var.successors[x]) {
        ++work_;
        if (y == goal_value) return false;
        if (y == excluded || closed[y] || !value_reached(var, y)) continue;
        closed[y] = 1;
        queue.push_back(y);
      }
    }
    return true;
  }

  // Whether one operator achieves both f and a fact of landmark l.
  bool achieved_together(FactId f, int l) const {
    for (FactId g : atoms_[l]) {
      if (g == f) return true;
      for (int a : relaxed_.achievers(f)) {
        const OperatorId origin = relaxed_.ops()[a].origin;
        for (int b : relaxed_.achievers(g)) {
          if (a == b || (origin >= 0 && relaxed_.ops()[b].origin == origin)) return true;
        }
      }
    }
    return false;
  }

  // A fact landmark not reachable without landmark l, and not achieved together with it,
  // comes after it.
  void add_forward_orders() {
    for (std::size_t l = 0; l < atoms_.size(); ++l) {
      const auto& bits = unreached_[l];
      if (dead_[l] || bits.empty()) continue;
      for (std::size_t k = 0; k < atoms_.size(); ++k) {
        if (k == l || dead_[k] || atoms_[k].size() != 1) continue;
        const FactId f = atoms_[k].front();
        if (!((bits[f >> 6] >> (f & 63)) & 1u) || achieved_together(f, static_cast<int>(l))) continue;
        order(static_cast<int>(l), static_cast<int>(k), Order::natural);
      }
    }
  }

  // --- the result -----------------------------------------------------------------------

  Landmarks finish() {
    std::vector<int> index(atoms_.size(), -1);
    for (std::size_t l = 0; l < atoms_.size(); ++l) {
      if (dead_[l]) continue;
      index[l] = static_cast<int>(out_.atoms_.size());
      out_.atoms_.push_back(atoms_[l]);
      out_.goal_.push_back(goal_[l]);
    }
    const std::size_t n = out_.atoms_.size();
    out_.parents_.assign(n, {});
    out_.needed_by_.assign(n, {});
    std::vector<std::vector<std::pair<int, Order>>> into(n);
    for (std::size_t l = 0; l < atoms_.size(); ++l) {
      if (index[l] < 0) continue;
      for (auto [parent, type] : parents_[l]) {
        if (index[parent] >= 0) into[index[l]].emplace_back(index[parent], type);
      }
    }
    drop_cycles(into);
    for (std::size_t i = 0; i < n; ++i) {
      for (auto [parent, type] : into[i]) {
        out_.parents_[i].push_back(parent);
        if (type == Order::greedy_necessary) out_.needed_by_[parent].push_back(static_cast<int>(i));
      }
    }
    out_.cost_.assign(n, 1.0);
    for (std::size_t i = 0; i < n; ++i) {
      double cheapest = -1.0;
      for (FactId f : out_.atoms_[i]) {
        for (int op : relaxed_.achievers(f)) {
          if (cheapest < 0 || relaxed_.ops()[op].cost < cheapest) cheapest = relaxed_.ops()[op].cost;
        }
      }
      if (cheapest >= 0) out_.cost_[i] = cheapest;
    }
    out_.variables_ = variables_.size();
    out_.reasonable_.assign(n, {});
    reasonable_orders();
    return std::move(out_);
  }

  // --- reasonable orders ------------------------------------------------------------------

  // The task fact a relaxed fact is about (a complement's fact).
  FactId base(FactId f) const {
    if (f < static_cast<FactId>(task_.fact_count())) return f;
    return f < relaxed_.goal_fact() ? relaxed_.complemented(f) : -1;
  }
  // Two facts of one finite-domain variable, or of one mutex group: never true together.
  bool mutex(FactId a, FactId b) const {
    if (a == b) return false;
    const FactId task_facts = static_cast<FactId>(task_.fact_count());
    if (a >= task_facts && b >= task_facts) return false;
    if (a >= task_facts || b >= task_facts) return relaxed_.complement_of(a < task_facts ? a : b) == (a < task_facts ? b : a);
    for (int g : groups_of_[a]) {
      if (std::find(groups_of_[b].begin(), groups_of_[b].end(), g) != groups_of_[b].end()) return true;
    }
    return false;
  }

  // Effects every operator achieving fact a has, on other variables than a's: +f for an
  // add (2f), -d for a delete of a fact no add of its variable replaces (2d + 1).
  std::vector<int> shared_effects(FactId a) const {
    std::vector<int> shared;
    bool first = true;
    const FactId a_base = base(a);
    const int a_var = a_base >= 0 ? var_of_[a_base] : -1;
    auto other_variable = [&](FactId f) { return f != a_base && (a_var < 0 || var_of_[f] != a_var); };
    for (int r : relaxed_.achievers(a)) {
      const OperatorId o = relaxed_.ops()[r].origin;
      if (o < 0) return {};  // an axiom: its effect is conditional
      const Operator& op = task_.operators[o];
      std::vector<int> effects;
      std::vector<int> changed;
      for (FactId f : op.add) {
        if (var_of_[f] >= 0) changed.push_back(var_of_[f]);
        if (other_variable(f)) effects.push_back(2 * f);
      }
      for (FactId d : op.del) {
        const bool replaced = var_of_[d] >= 0 && std::find(changed.begin(), changed.end(), var_of_[d]) != changed.end();
        if (!replaced && other_variable(d)) effects.push_back(2 * d + 1);
      }
      std::sort(effects.begin(), effects.end());
      if (first) {
        shared = std::move(effects);
        first = false;
      } else {
        std::vector<int> both;
        std::set_intersection(shared.begin(), shared.end(), effects.begin(), effects.end(), std::back_inserter(both));
        shared.swap(both);
      }
      if (shared.empty()) break;
    }
    return shared;
  }

  // Whether achieving landmark x (one fact) makes landmark fact b false.
  bool interferes(FactId x, FactId b, const std::vector<int>& effects_of_x) const {
    if (x == b) return false;
    if (mutex(x, b)) return true;
    const FactId task_facts = static_cast<FactId>(task_.fact_count());
    for (int e : effects_of_x) {
      const FactId f = e / 2;
      if (f == x || f == b) {
        if ((e & 1) && f == b) return true;  // x's achievers delete b
        continue;
      }
      if (e & 1) {
        // Deleted with no replacement: its variable's "none of those" excludes b's value.
        if (b < task_facts && var_of_[f] >= 0 && var_of_[f] == var_of_[b]) return true;
      } else if (mutex(f, b)) {
        return true;
      }
    }
    return false;
  }

  void reasonable_orders() {
    const std::size_t n = out_.atoms_.size();
    std::vector<std::vector<int>> effects(n);
    std::vector<char> atomic(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      atomic[i] = out_.atoms_[i].size() == 1;
      if (atomic[i]) effects[i] = shared_effects(out_.atoms_[i].front());
    }
    auto ordered = [&](int from, int to) {
      const auto& p = out_.parents_[to];
      return std::find(p.begin(), p.end(), from) != p.end();
    };
    auto consider = [&](int x, int l) {
      ++work_;
      if (x == l || !atomic[x] || ordered(x, l) || ordered(l, x)) return;
      if (!interferes(out_.atoms_[x].front(), out_.atoms_[l].front(), effects[x])) return;
      auto& r = out_.reasonable_[l];
      if (std::find(r.begin(), r.end(), x) == r.end()) r.push_back(x);
    };
    std::vector<std::vector<int>> children(n);
    for (std::size_t i = 0; i < n; ++i) {
      for (int p : out_.parents_[i]) children[p].push_back(static_cast<int>(i));
    }
    for (std::size_t i = 0; i < n && work_ < 2 * budget_; ++i) {
      const int l = static_cast<int>(i);
      if (!atomic[l]) continue;
      if (out_.goal_[l]) {
        for (std::size_t x = 0; x < n; ++x) consider(static_cast<int>(x), l);
        continue;
      }
      // Parents (and their ancestors) of what l is greedy-necessary for.
      std::vector<char> candidate(n, 0);
      std::vector<int> stack;
      for (int child : out_.needed_by_[l]) {
        for (int p : out_.parents_[child]) {
          if (p != l && atomic[p] && !candidate[p]) {
            candidate[p] = 1;
            stack.push_back(p);
          }
        }
      }
      while (!stack.empty()) {
        const int c = stack.back();
        stack.pop_back();
        for (int p : out_.parents_[c]) {
          if (!candidate[p]) {
            candidate[p] = 1;
            stack.push_back(p);
          }
        }
      }
      for (std::size_t x = 0; x < n; ++x) {
        if (candidate[x]) consider(static_cast<int>(x), l);
      }
    }
  }

  // Removes orders until none closes a cycle: a depth-first search drops each order back
  // into its own path, natural ones before greedy-necessary ones.
  static void drop_cycles(std::vector<std::vector<std::pair<int, Order>>>& into) {
    for (auto& list : into) {
      std::stable_sort(list.begin(), list.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
    }
    const std::size_t n = into.size();
    std::vector<char> state(n, 0);  // 0 new, 1 on the path, 2 done
    for (std::size_t root = 0; root < n; ++root) {
      if (state[root]) continue;
      std::vector<std::pair<int, std::size_t>> stack{{static_cast<int>(root), 0}};
      state[root] = 1;
      while (!stack.empty()) {
        auto& [node, next] = stack.back();
        auto& list = into[node];
        if (next == list.size()) {
          state[node] = 2;
          stack.pop_back();
          continue;
        }
        const int parent = list[next].first;
        if (state[parent] == 1) {
          list.erase(list.begin() + static_cast<std::ptrdiff_t>(next));
          continue;
        }
        ++next;
        if (state[parent] == 0) {
          state[parent] = 1;
          stack.emplace_back(parent, 0);
        }
      }
    }
  }

  const RelaxedTask& relaxed_;
  const Task& task_;
  std::uint64_t budget_;
  std::chrono::steady_clock::time_point deadline_;
  std::uint64_t work_ = 0;
  Landmarks out_;

  std::vector<char> initially_;
  std::vector<int> class_;
  std::vector<Variable> variables_;
  std::vector<int> changed_;  // dtg_edges' scratch: the variables an effect sets
  // explore_without's scratch, kept between its calls.
  std::vector<char> origin_out_;
  std::vector<OperatorId> left_out_;
  std::vector<FactId> queue_;
  std::vector<FactId> initial_facts_;  // relaxed facts true initially, in order
  std::vector<int> var_of_, value_of_;
  std::vector<std::vector<int>> groups_of_;  // per task fact: the mutex groups holding it

  std::vector<std::vector<FactId>> atoms_;
  std::vector<char> goal_, dead_;
  std::vector<std::map<int, Order>> parents_;  // per landmark: parent -> strongest order
  std::vector<std::vector<std::uint64_t>> unreached_;  // per landmark: facts unreachable without it (bits)
  std::vector<int> atomic_of_, disjunctive_of_;
  std::deque<int> open_;

  std::vector<char> reached_, is_excluded_fact_;
  std::vector<int> unsatisfied_;
};

Landmarks Landmarks::rhw(const RelaxedTask& relaxed, const Task& task, const State& initial, std::uint64_t work_budget,
                         std::chrono::steady_clock::time_point deadline, const MutexGroups* mutexes) {
  return RhwFactory(relaxed, task, initial, work_budget, deadline, mutexes).run();
}

}  // namespace cluttertamp::search::detail
