#include "search/successor_order.hpp"

#include <algorithm>
#include <compare>
#include <map>
#include <numeric>

#include "search/small_sort.hpp"
#include "search/tuple_index.hpp"

namespace cluttertamp::search::detail {

namespace {

using Fact = std::pair<int, int>;  // (variable, value)

// The operators as the translator writes them, one after another in flat arrays (a
// task has thousands): preconditions, variables of several facts one of which the
// precondition needs false, and per changed variable the value it requires (-1: any)
// and the value it sets, with the variables of the effect's condition.
struct SasEffect {
  int var, pre, post;
  std::uint32_t condition_begin, condition_end;  // into SasOperators::condition_vars
};
template <class T>
struct Ranges {
  std::vector<T> items;
  std::vector<std::uint32_t> begin{0};  // per operator, and one past the last
  void close() { begin.push_back(static_cast<std::uint32_t>(items.size())); }
  const T* first(std::size_t o) const { return items.data() + begin[o]; }
  const T* last(std::size_t o) const { return items.data() + begin[o + 1]; }
};
struct SasOperators {
  Ranges<Fact> pre;  // sorted by variable, one value each
  Ranges<int> negated;
  Ranges<SasEffect> effects;
  std::vector<int> condition_vars;
  std::size_t size() const { return pre.begin.size() - 1; }
};

class Encoding {
 public:
  Encoding(const Task& task, const MutexGroups& mutexes) {
    var_of_.assign(task.fact_count(), -1);
    value_of_.assign(task.fact_count(), -1);
    for (const std::vector<FactId>& facts : mutexes.variables) add_variable(facts);
    for (FactId f = 0; f < static_cast<FactId>(task.fact_count()); ++f) {
      if (task.derived[f]) add_variable({f});
    }
    initial_.resize(domain_.size());
    for (std::size_t v = 0; v < domain_.size(); ++v) initial_[v] = domain_[v] - 1;
    for (FactId f : task.initial) initial_[var_of_[f]] = value_of_[f];
  }

  int variables() const { return static_cast<int>(domain_.size()); }
  int var(FactId f) const { return var_of_[f]; }
  int value(FactId f) const { return value_of_[f]; }
  int none(int var) const { return domain_[var] - 1; }
  int initial(int var) const { return initial_[var]; }

  /// Appends `op` to `out` (nothing of it when `skip`: an operator without any).
  void translate(const Operator& op, bool skip, SasOperators& out) const {
    if (!skip) add(op, out);
    out.pre.close();
    out.negated.close();
    out.effects.close();
  }

 private:
  void add(const Operator& op, SasOperators& out) const {
    // By variable, the first fact of each (as a map's emplace would keep it).
    std::vector<Fact>& pre = out.pre.items;
    const auto pre_begin = static_cast<long>(pre.size());
    for (FactId f : op.precondition.positive) pre.emplace_back(var(f), value(f));
    for (FactId f : op.precondition.negative) {
      if (domain_[var(f)] == 2) pre.emplace_back(var(f), 1);  // the atom's negation
      else out.negated.items.push_back(var(f));
    }
    const auto by_var = [](const Fact& a, const Fact& b) { return a.first < b.first; };
    stable_sort_short(pre.begin() + pre_begin, pre.end(), by_var);
    pre.erase(std::unique(pre.begin() + pre_begin, pre.end(), [](const Fact& a, const Fact& b) { return a.first == b.first; }),
              pre.end());
    // The value the precondition requires of `v`, or -1.
    const auto required = [&](int v) {
      const auto it = std::lower_bound(pre.begin() + pre_begin, pre.end(), Fact{v, -1});
      return it != pre.end() && it->first == v ? it->second : -1;
    };
    // A delete sets "none of those" unless the same effect or an unconditional one adds
    // a value of the variable.
    const auto added_by = [&](const std::vector<FactId>& add, int v) {
      return std::any_of(add.begin(), add.end(), [&](FactId f) { return var(f) == v; });
    };
    const auto effects = [&](const std::vector<FactId>& add, const std::vector<FactId>& del, const Condition* when) {
      const auto condition_begin = static_cast<std::uint32_t>(out.condition_vars.size());
      if (when) {
        for (FactId f : when->positive) out.condition_vars.push_back(var(f));
        for (FactId f : when->negative) out.condition_vars.push_back(var(f));
      }
      const auto condition_end = static_cast<std::uint32_t>(out.condition_vars.size());
      // An effect setting `v` to `post`; `deleted` is the value a delete takes away (-1
      // for an add). Effects that change nothing or contradict the precondition are dropped.
      const auto push = [&](int v, int deleted, int post) {
        const int needed = required(v);
        if (needed >= 0 && deleted >= 0 && needed != deleted) return;
        const int before = needed >= 0 ? needed : deleted;
        if (before != post) out.effects.items.push_back({v, before, post, condition_begin, condition_end});
      };
      for (FactId f : add) push(var(f), -1, value(f));
      for (FactId f : del) {
        if (!added_by(op.add, var(f)) && (!when || !added_by(add, var(f)))) push(var(f), value(f), none(var(f)));
      }
    };
    effects(op.add, op.del, nullptr);
    for (const ConditionalEffect& c : op.conditional) effects(c.add, c.del, &c.condition);
  }

  void add_variable(const std::vector<FactId>& facts) {
    const int v = static_cast<int>(domain_.size());
    for (std::size_t k = 0; k < facts.size(); ++k) {
      var_of_[facts[k]] = v;
      value_of_[facts[k]] = static_cast<int>(k);
    }
    domain_.push_back(static_cast<int>(facts.size()) + 1);
  }

  std::vector<int> var_of_, value_of_, domain_, initial_;
};

// Variables whose transition graph has an arc from the initial value to another: an
// effect that sets another value from the initial one or from any.
std::vector<char> changing_variables(const Encoding& enc, const SasOperators& ops, const Task& task) {
  std::vector<char> changing(static_cast<std::size_t>(enc.variables()), 0);
  for (const SasEffect& e : ops.effects.items) {
    const int start = enc.initial(e.var);
    if ((e.pre < 0 || e.pre == start) && e.post != start) changing[e.var] = 1;
  }
  for (const Axiom& a : task.axioms) {
    if (enc.value(a.head) != enc.initial(enc.var(a.head))) changing[enc.var(a.head)] = 1;
  }
  return changing;
}

// Tarjan's strongly connected components, in topological order; the vertices of a
// component in the order they were reached (as the translator's iterative version).
std::vector<std::vector<int>> components(const std::vector<std::vector<int>>& successors) {
  const int n = static_cast<int>(successors.size());
  std::vector<int> index(n, 0), low(n, 0), on_stack_at(n, -1);
  std::vector<int> stack;
  std::vector<std::vector<int>> out;
  int counter = 0;
  struct Frame {
    int v;
    std::size_t next;
  };
  for (int root = 0; root < n; ++root) {
    if (index[root]) continue;
    std::vector<Frame> frames{{root, 0}};
    index[root] = low[root] = ++counter;
    on_stack_at[root] = static_cast<int>(stack.size());
    stack.push_back(root);
    while (!frames.empty()) {
      Frame& f = frames.back();
      if (f.next < successors[f.v].size()) {
        const int w = successors[f.v][f.next++];
        if (!index[w]) {
          index[w] = low[w] = ++counter;
          on_stack_at[w] = static_cast<int>(stack.size());
          stack.push_back(w);
          frames.push_back({w, 0});
        } else if (on_stack_at[w] >= 0) {
          low[f.v] = std::min(low[f.v], index[w]);
        }
        continue;
      }
      const int v = f.v;
      frames.pop_back();
      if (!frames.empty()) low[frames.back().v] = std::min(low[frames.back().v], low[v]);
      if (low[v] != index[v]) continue;
      std::vector<int> scc(stack.begin() + on_stack_at[v], stack.end());
      stack.resize(static_cast<std::size_t>(on_stack_at[v]));
      for (int w : scc) on_stack_at[w] = -1;
      out.push_back(std::move(scc));
    }
  }
  std::reverse(out.begin(), out.end());
  return out;
}

using Weights = std::vector<std::vector<std::pair<int, long>>>;  // per source: (target, weight), by target

// The translator's greedy order inside one component: repeatedly the variable with the
// least weight of incoming edges from the variables not yet taken; an edge into a goal
// variable also counts 100000 that is never taken away, so goal variables come last.
// Variables are numbered by their place in `scc` here.
std::vector<int> order_component(const std::vector<int>& scc, const Weights& weights, const std::vector<char>& goal) {
  constexpr long kGoal = 100000;
  std::vector<int> place(weights.size(), -1);
  for (std::size_t k = 0; k < scc.size(); ++k) place[scc[k]] = static_cast<int>(k);
  std::vector<std::vector<std::pair<int, long>>> edges(scc.size());  // (target's place, weight)
  std::vector<long> incoming(scc.size(), 0);
  for (std::size_t k = 0; k < scc.size(); ++k) {
    auto& list = edges[k];
    for (const auto& [target, cost] : weights[scc[k]]) {
      if (place[target] < 0) continue;
      if (goal[target]) list.push_back({place[target], kGoal + cost});
      list.push_back({place[target], cost});
    }
    for (const auto& [target, w] : list) incoming[target] += w;
  }
  // Per weight, the variables listed with it, taken from `head` on (first in, first out).
  struct Listed {
    std::size_t head = 0;
    std::vector<int> entries;
  };
  std::map<long, Listed> by_weight;
  for (std::size_t k = 0; k < scc.size(); ++k) by_weight[incoming[k]].entries.push_back(static_cast<int>(k));
  std::vector<char> done(scc.size(), 0);
  std::vector<int> result;
  while (!by_weight.empty()) {
    const auto least = by_weight.begin();
    const long key = least->first;
    Listed& listed = least->second;
    int taken = -1;
    while (listed.head < listed.entries.size() && (taken < 0 || done[taken] || key > incoming[taken])) {
      taken = listed.entries[listed.head++];
    }
    if (listed.head == listed.entries.size()) by_weight.erase(least);
    if (taken < 0 || done[taken]) continue;
    done[taken] = 1;
    result.push_back(scc[taken]);
    for (const auto& [target, w] : edges[taken]) {
      if (done[target]) continue;
      const long weight = w % kGoal;
      if (weight == 0) continue;
      incoming[target] -= weight;
      by_weight[incoming[target]].entries.push_back(target);
    }
  }
  return result;
}

}  // namespace

SuccessorOrder successor_order(const Task& task, const MutexGroups& mutexes, const std::vector<char>& left_out) {
  const Encoding enc(task, mutexes);
  const int n = enc.variables();
  const std::size_t op_count = task.operators.size();
  SasOperators ops;
  for (std::size_t o = 0; o < op_count; ++o) enc.translate(task.operators[o], left_out[o] != 0, ops);
  const std::vector<char> changing = changing_variables(enc, ops, task);

  // The causal graph: weighted edges source -> target, and each target's sources. The
  // arcs are counted in an n x n table of their ids where that is small (a tree per
  // source was most of this function), else in a hash index of (source, target).
  const bool small = static_cast<std::size_t>(n) * static_cast<std::size_t>(n) <= (1u << 14);
  std::vector<std::uint32_t> arc_at(small ? static_cast<std::size_t>(n) * static_cast<std::size_t>(n) : 0);  // id + 1
  TupleIndex<int> arcs(2);
  std::vector<std::pair<int, int>> arc_ends;
  std::vector<long> arc_weight;
  const auto edge = [&](int source, int target) {
    if (source == target || !changing[source] || !changing[target]) return;
    std::size_t id;
    if (small) {
      std::uint32_t& at = arc_at[static_cast<std::size_t>(source) * static_cast<std::size_t>(n) + static_cast<std::size_t>(target)];
      if (at == 0) at = static_cast<std::uint32_t>(arc_ends.size() + 1);
      id = at - 1;
    } else {
      const int pair[2] = {source, target};
      id = arcs.insert(pair).first;
    }
    if (id == arc_ends.size()) {
      arc_ends.push_back({source, target});
      arc_weight.push_back(0);
    }
    ++arc_weight[id];
  };
  for (std::size_t o = 0; o < op_count; ++o) {
    for (const SasEffect* e = ops.effects.first(o); e != ops.effects.last(o); ++e) {
      for (const Fact* p = ops.pre.first(o); p != ops.pre.last(o); ++p) edge(p->first, e->var);
      for (const int* v = ops.negated.first(o); v != ops.negated.last(o); ++v) edge(*v, e->var);
      for (std::uint32_t c = e->condition_begin; c < e->condition_end; ++c) edge(ops.condition_vars[c], e->var);
    }
  }
  for (const Axiom& a : task.axioms) {
    for (FactId f : a.body.positive) edge(enc.var(f), enc.var(a.head));
    for (FactId f : a.body.negative) edge(enc.var(f), enc.var(a.head));
  }
  Weights weights(n);
  std::vector<std::vector<int>> predecessors(n);
  for (std::size_t id = 0; id < arc_ends.size(); ++id) {
    const auto [source, target] = arc_ends[id];
    weights[source].push_back({target, arc_weight[id]});
    predecessors[target].push_back(source);
  }
  for (auto& targets : weights) std::sort(targets.begin(), targets.end());

  // Variables the goal depends on: goal variables and their causal-graph ancestors.
  std::vector<char> goal(n, 0), needed(n, 0);
  std::vector<int> stack;
  for (const Condition& c : task.goal) {
    for (FactId f : c.positive) goal[enc.var(f)] = 1;
    for (FactId f : c.negative) goal[enc.var(f)] = 1;
  }
  for (int v = 0; v < n; ++v) {
    if (goal[v] && changing[v] && !needed[v]) {
      needed[v] = 1;
      stack.push_back(v);
    }
  }
  while (!stack.empty()) {
    const int v = stack.back();
    stack.pop_back();
    for (int p : predecessors[v]) {
      if (!needed[p]) {
        needed[p] = 1;
        stack.push_back(p);
      }
    }
  }

  // The variable order, over the variables that change (numbered as the translator
  // numbers them once constant ones are gone).
  std::vector<int> dense(n, -1), sparse;
  for (int v = 0; v < n; ++v) {
    if (changing[v]) {
      dense[v] = static_cast<int>(sparse.size());
      sparse.push_back(v);
    }
  }
  std::vector<std::vector<int>> successors(sparse.size());
  for (std::size_t d = 0; d < sparse.size(); ++d) {
    for (const auto& [target, w] : weights[sparse[d]]) successors[d].push_back(dense[target]);
    std::sort(successors[d].begin(), successors[d].end());
  }
  std::vector<int> position(n, -1);
  int next = 0;
  for (const std::vector<int>& scc : components(successors)) {
    std::vector<int> members;
    for (int d : scc) members.push_back(sparse[d]);
    const std::vector<int> ordered = members.size() > 1 ? order_component(members, weights, goal) : members;
    for (int v : ordered) {
      if (needed[v]) position[v] = next++;
    }
  }

  SuccessorOrder out;
  out.variables = sparse.size();
  out.relevant_variables = static_cast<std::size_t>(next);
  out.relevant.assign(op_count, 0);
  Ranges<Fact> keys;  // per operator: its relevant preconditions in search variables, sorted
  for (std::size_t o = 0; o < op_count; ++o) {
    for (const SasEffect* e = ops.effects.first(o); e != ops.effects.last(o); ++e) out.relevant[o] |= position[e->var] >= 0;
    const auto key_begin = static_cast<long>(keys.items.size());
    for (const Fact* p = ops.pre.first(o); p != ops.pre.last(o); ++p) {
      if (position[p->first] >= 0) keys.items.push_back({position[p->first], p->second});
    }
    std::sort(keys.items.begin() + key_begin, keys.items.end());
    keys.close();
  }
  out.search_variable.resize(task.fact_count());
  out.translator_variable.resize(task.fact_count());
  for (FactId f = 0; f < static_cast<FactId>(task.fact_count()); ++f) {
    const int v = enc.var(f);
    out.translator_variable[f] = static_cast<std::uint32_t>(v);
    out.search_variable[f] = static_cast<std::uint32_t>(position[v] >= 0 ? position[v] : n + v);
  }
  std::vector<OperatorId> sorted(op_count);
  std::iota(sorted.begin(), sorted.end(), 0);
  // The grounder names its operators in order: then the stable sort keeps ties in name
  // order without comparing names.
  const bool named_in_order = std::is_sorted(task.operators.begin(), task.operators.end(),
                                             [](const Operator& a, const Operator& b) { return a.name < b.name; });
  std::stable_sort(sorted.begin(), sorted.end(), [&](OperatorId a, OperatorId b) {
    if (left_out[a] != left_out[b]) return left_out[b] != 0;
    const auto order = std::lexicographical_compare_three_way(keys.first(a), keys.last(a), keys.first(b), keys.last(b));
    if (order != 0) return order < 0;
    return !named_in_order && task.operators[a].name < task.operators[b].name;
  });
  out.rank.resize(op_count);
  for (std::size_t k = 0; k < op_count; ++k) out.rank[sorted[k]] = static_cast<std::uint32_t>(k);
  return out;
}

}  // namespace cluttertamp::search::detail
