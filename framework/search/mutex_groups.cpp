#include "search/mutex_groups.hpp"

#include <algorithm>
#include <deque>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>

namespace cluttertamp::search::detail {

namespace {

// Every fluent fact's predicate and arguments, interned, the arguments of all facts in
// one array (the synthesis reads them for every operator it checks).
class GroundAtoms {
 public:
  explicit GroundAtoms(const Task& task) : predicate_(task.fact_count(), -1), start_(task.fact_count() + 1, 0) {
    std::unordered_map<std::string_view, int> predicates, objects;  // views into the task's names
    for (FactId f = 0; f < static_cast<FactId>(task.fact_count()); ++f) {
      start_[f] = static_cast<std::uint32_t>(args_.size());
      if (!task.derived[f]) read(task.fact_names[f], f, predicates, objects);
    }
    start_.back() = static_cast<std::uint32_t>(args_.size());
    predicate_count_ = static_cast<int>(predicates.size());
  }
  /// -1 for a derived fact.
  int predicate(FactId f) const { return predicate_[f]; }
  int arity(FactId f) const { return static_cast<int>(start_[f + 1] - start_[f]); }
  int arg(FactId f, int i) const { return args_[start_[f] + static_cast<std::uint32_t>(i)]; }
  int predicate_count() const { return predicate_count_; }

 private:
  // "(pred a b)": the words between "(" and ")", split at spaces.
  void read(std::string_view text, FactId f, std::unordered_map<std::string_view, int>& predicates,
            std::unordered_map<std::string_view, int>& objects) {
    std::size_t i = text.empty() || text[0] != '(' ? 0 : 1;
    bool first = true;
    while (i < text.size()) {
      while (i < text.size() && (text[i] == ' ' || text[i] == ')')) ++i;
      std::size_t end = i;
      while (end < text.size() && text[end] != ' ' && text[end] != ')') ++end;
      if (end == i) break;
      auto& ids = first ? predicates : objects;
      const int id = ids.try_emplace(text.substr(i, end - i), static_cast<int>(ids.size())).first->second;
      if (first) predicate_[f] = id;
      else args_.push_back(id);
      first = false;
      i = end;
    }
  }

  std::vector<int> predicate_;
  std::vector<std::uint32_t> start_;
  std::vector<int> args_;
  int predicate_count_ = 0;
};

// One predicate of an invariant: which argument gives each invariant parameter, and
// which one (if any) is counted.
struct Part {
  int predicate;
  std::vector<int> positions;
  int counted = -1;
  auto operator<=>(const Part&) const = default;
};
using Invariant = std::vector<Part>;  // sorted by predicate, one part per predicate

using Key = std::vector<int>;

// One effect scope of an operator: the unconditional effects, or one conditional
// effect with the unconditional deletes (which happen whenever it does). Views into
// the operator, or into Synthesis's scratch where a scope had to be assembled.
struct Scope {
  const std::vector<FactId>* pre;  // sorted
  const std::vector<FactId>* add;
  const std::vector<FactId>* del;
};

class Synthesis {
 public:
  Synthesis(const Task& task, std::uint64_t budget) : task_(task), budget_(budget), atoms_(task) {
    const int predicates = atoms_.predicate_count();
    arity_.assign(predicates, 0);
    facts_of_.resize(predicates);
    for (FactId f = 0; f < static_cast<FactId>(task.fact_count()); ++f) {
      if (task.derived[f]) continue;
      arity_[atoms_.predicate(f)] = atoms_.arity(f);
      facts_of_[atoms_.predicate(f)].push_back(f);
    }
    adders_.resize(predicates);
    for (OperatorId o = 0; o < static_cast<OperatorId>(task.operators.size()); ++o) {
      const Operator& op = task.operators[o];
      auto note = [&](const std::vector<FactId>& add) {
        for (FactId f : add) {
          if (task.derived[f]) continue;
          auto& list = adders_[atoms_.predicate(f)];
          if (list.empty() || list.back() != o) list.push_back(o);
        }
      };
      note(op.add);
      for (const ConditionalEffect& c : op.conditional) note(c.add);
    }
    part_of_.assign(predicates, -1);
    op_seen_.assign(task.operators.size(), 0);
  }

  MutexGroups run() {
    MutexGroups out;
    for (int p = 0; p < atoms_.predicate_count(); ++p) {
      for (int counted = -1; counted < arity_[p]; ++counted) {
        Part part{p, {}, counted};
        for (int i = 0; i < arity_[p]; ++i) {
          if (i != counted) part.positions.push_back(i);
        }
        enqueue({part});
      }
    }
    std::vector<Invariant> proven;
    while (!queue_.empty()) {
      if (work_ > budget_) {
        out.complete = false;
        break;
      }
      Invariant candidate = std::move(queue_.front());
      queue_.pop_front();
      ++out.candidates;
      if (balanced(candidate)) proven.push_back(std::move(candidate));
    }
    out.invariants = proven.size();
    std::set<std::vector<FactId>> groups;
    std::vector<char> initial(task_.fact_count(), 0);
    for (FactId f : task_.initial) initial[f] = 1;
    for (const Invariant& inv : proven) {
      std::map<Key, std::pair<std::vector<FactId>, int>> instances;
      for (const Part& part : inv) {
        for (FactId f : facts_of_[part.predicate]) {
          auto& [facts, initially] = instances[key(f, part)];
          facts.push_back(f);
          initially += initial[f];
        }
      }
      for (auto& [k, instance] : instances) {
        if (instance.second != 1) continue;
        std::sort(instance.first.begin(), instance.first.end());
        groups.insert(instance.first);
      }
    }
    out.groups.assign(groups.begin(), groups.end());
    return out;
  }

 private:
  Key key(FactId f, const Part& part) const {
    Key k;
    k.reserve(part.positions.size());
    for (int p : part.positions) k.push_back(atoms_.arg(f, p));
    return k;
  }

  // An added fact of one scope, with its part of the invariant being checked.
  struct Added {
    FactId fact;
    std::size_t scope;
    const Part* part;
  };

  // Whether key(a.fact, *a.part) == key(f, part), without building either.
  bool same_key(const Added& a, FactId f, const Part& part) const {
    if (a.part->positions.size() != part.positions.size()) return false;
    for (std::size_t i = 0; i < part.positions.size(); ++i) {
      if (atoms_.arg(a.fact, a.part->positions[i]) != atoms_.arg(f, part.positions[i])) return false;
    }
    return true;
  }

  void enqueue(Invariant inv) {
    std::sort(inv.begin(), inv.end());
    if (seen_.insert(inv).second) queue_.push_back(std::move(inv));
  }

  const Part* part_for(FactId f) const {
    const int predicate = atoms_.predicate(f);
    if (predicate < 0) return nullptr;  // derived
    const int i = part_of_[predicate];
    return i < 0 ? nullptr : &(*current_)[i];
  }

  // The scopes of `op` into scopes_; most operators have one, viewed in place.
  void scopes(const Operator& op) {
    scopes_.clear();
    const std::vector<FactId>* pre = &op.precondition.positive;
    // Sized first: the scopes point into it.
    if (store_.size() < 1 + 2 * op.conditional.size()) store_.resize(1 + 2 * op.conditional.size());
    std::size_t used = 0;
    auto store = [&]() -> std::vector<FactId>& { return store_[used++]; };
    if (!std::is_sorted(pre->begin(), pre->end())) {
      std::vector<FactId>& sorted = store();
      sorted = *pre;
      std::sort(sorted.begin(), sorted.end());
      pre = &sorted;
    }
    scopes_.push_back({pre, &op.add, &op.del});
    for (const ConditionalEffect& c : op.conditional) {
      std::vector<FactId>& both = store();
      both = *pre;
      both.insert(both.end(), c.condition.positive.begin(), c.condition.positive.end());
      std::sort(both.begin(), both.end());
      std::vector<FactId>& del = store();
      del = op.del;
      // The deletes of every conditional effect that fires whenever this one does (the
      // grounder gives each literal of one `when` an effect of its own).
      for (const ConditionalEffect& other : op.conditional) {
        if (implied(other.condition, both, c.condition.negative)) del.insert(del.end(), other.del.begin(), other.del.end());
      }
      scopes_.push_back({&both, &c.add, &del});
    }
  }

  // Whether `condition` holds whenever the facts `pre` (sorted) are true and `negative` false.
  static bool implied(const Condition& condition, const std::vector<FactId>& pre, const std::vector<FactId>& negative) {
    for (FactId f : condition.positive) {
      if (!std::binary_search(pre.begin(), pre.end(), f)) return false;
    }
    for (FactId f : condition.negative) {
      if (std::find(negative.begin(), negative.end(), f) == negative.end()) return false;
    }
    return true;
  }

  bool balanced(const Invariant& inv) {
    current_ = &inv;
    for (std::size_t i = 0; i < inv.size(); ++i) part_of_[inv[i].predicate] = static_cast<int>(i);
    ++stamp_;
    bool ok = true;
    for (const Part& part : inv) {
      for (OperatorId o : adders_[part.predicate]) {
        if (op_seen_[o] == stamp_) continue;
        op_seen_[o] = stamp_;
        if (!balanced(inv, task_.operators[o])) {
          ok = false;
          break;
        }
      }
      if (!ok) break;
    }
    for (const Part& part : inv) part_of_[part.predicate] = -1;
    return ok;
  }

  // Whether `op` keeps every instance's count; when it does not only for want of a
  // matching delete, queues the refinements its deletes suggest.
  bool balanced(const Invariant& inv, const Operator& op) {
    scopes(op);
    added_.clear();
    for (std::size_t s = 0; s < scopes_.size(); ++s) {
      for (FactId f : *scopes_[s].add) {
        ++work_;
        const Part* part = part_for(f);
        if (!part || std::binary_search(scopes_[s].pre->begin(), scopes_[s].pre->end(), f)) continue;
        added_.push_back({f, s, part});
      }
    }
    for (std::size_t i = 0; i < added_.size(); ++i) {
      for (std::size_t j = i + 1; j < added_.size(); ++j) {
        if (added_[i].fact != added_[j].fact && same_key(added_[i], added_[j].fact, *added_[j].part)) return false;  // too heavy
      }
    }
    for (const Added& a : added_) {
      const Scope& scope = scopes_[a.scope];
      bool matched = false;
      for (FactId d : *scope.del) {
        ++work_;
        const Part* part = part_for(d);
        if (part && std::binary_search(scope.pre->begin(), scope.pre->end(), d) && same_key(a, d, *part)) {
          matched = true;
          break;
        }
      }
      if (!matched) {
        refine(inv, scope, key(a.fact, *a.part));
        return false;
      }
    }
    return true;
  }

  // New candidates: `inv` with a part for a delete of `scope` whose arguments give `key`.
  void refine(const Invariant& inv, const Scope& scope, const Key& key) {
    for (FactId d : *scope.del) {
      if (task_.derived[d] || !std::binary_search(scope.pre->begin(), scope.pre->end(), d)) continue;
      if (part_of_[atoms_.predicate(d)] >= 0) continue;
      const int spare = atoms_.arity(d) - static_cast<int>(key.size());
      if (spare < 0 || spare > 1) continue;
      std::vector<int> positions;
      std::vector<char> used(static_cast<std::size_t>(atoms_.arity(d)), 0);
      assign(inv, d, key, positions, used);
    }
  }

  void assign(const Invariant& inv, FactId atom, const Key& key, std::vector<int>& positions,
              std::vector<char>& used) {
    ++work_;
    if (positions.size() == key.size()) {
      Part part{atoms_.predicate(atom), positions, -1};
      for (std::size_t i = 0; i < used.size(); ++i) {
        if (!used[i]) part.counted = static_cast<int>(i);
      }
      Invariant refined = inv;
      refined.push_back(std::move(part));
      enqueue(std::move(refined));
      return;
    }
    for (std::size_t p = 0; p < used.size(); ++p) {
      if (used[p] || atoms_.arg(atom, static_cast<int>(p)) != key[positions.size()]) continue;
      used[p] = 1;
      positions.push_back(static_cast<int>(p));
      assign(inv, atom, key, positions, used);
      positions.pop_back();
      used[p] = 0;
    }
  }

  const Task& task_;
  std::uint64_t budget_;
  std::uint64_t work_ = 0;
  GroundAtoms atoms_;
  std::vector<int> arity_;
  std::vector<std::vector<FactId>> facts_of_;
  std::vector<std::vector<OperatorId>> adders_;
  std::deque<Invariant> queue_;
  std::set<Invariant> seen_;
  const Invariant* current_ = nullptr;
  std::vector<int> part_of_;
  std::vector<std::uint32_t> op_seen_;
  std::uint32_t stamp_ = 0;
  // balanced()'s, reused from operator to operator
  std::vector<Scope> scopes_;
  std::vector<std::vector<FactId>> store_;
  std::vector<Added> added_;
};

}  // namespace

MutexGroups find_mutex_groups(const Task& task, std::uint64_t work_budget) {
  MutexGroups out = Synthesis(task, work_budget).run();
  out.variables = choose_variables(task, out);
  return out;
}

std::vector<char> never_applicable(const Task& task, const MutexGroups& mutexes) {
  std::vector<std::vector<int>> groups_of(task.fact_count());
  for (std::size_t g = 0; g < mutexes.groups.size(); ++g) {
    for (FactId f : mutexes.groups[g]) groups_of[f].push_back(static_cast<int>(g));
  }
  std::vector<FactId> needed_by(mutexes.groups.size(), -1);  // per group: the fact of it the operator needs
  std::vector<OperatorId> stamp(mutexes.groups.size(), -1);
  std::vector<char> never(task.operators.size(), 0);
  for (OperatorId o = 0; o < static_cast<OperatorId>(task.operators.size()); ++o) {
    for (FactId f : task.operators[o].precondition.positive) {
      for (int g : groups_of[f]) {
        if (stamp[g] == o && needed_by[g] != f) never[o] = 1;
        stamp[g] = o;
        needed_by[g] = f;
      }
    }
  }
  return never;
}

std::vector<std::uint32_t> atom_order(const Task& task) {
  // Word by word, as lists of names compare, without splitting the names: ")" and " "
  // end a word and come before every character of one, and ")" (no more words) first.
  const auto order_of = [](char c) { return c == ')' ? 0 : c == ' ' ? 1 : 2 + static_cast<unsigned char>(c); };
  const auto before = [&](const std::string& a, const std::string& b) {
    return std::lexicographical_compare(a.begin(), a.end(), b.begin(), b.end(),
                                        [&](char x, char y) { return order_of(x) < order_of(y); });
  };
  std::vector<FactId> sorted(task.fact_count());
  for (FactId f = 0; f < static_cast<FactId>(sorted.size()); ++f) sorted[f] = f;
  std::stable_sort(sorted.begin(), sorted.end(), [&](FactId a, FactId b) { return before(task.fact_names[a], task.fact_names[b]); });
  std::vector<std::uint32_t> rank(task.fact_count());
  for (std::size_t k = 0; k < sorted.size(); ++k) rank[sorted[k]] = static_cast<std::uint32_t>(k);
  return rank;
}

namespace {

// Fast Downward's cover queue: groups listed by their current size, the last listed of
// the largest taken first; a group found smaller than its list moves to the end of the
// list of its size. Taking a group removes its facts from every group.
class GroupCoverQueue {
 public:
  GroupCoverQueue(std::vector<std::vector<FactId>> groups, std::size_t fact_count)
      : groups_(std::move(groups)), alive_(groups_.size()), size_(groups_.size()), by_fact_(fact_count) {
    std::size_t largest = 0;
    for (const auto& g : groups_) largest = std::max(largest, g.size());
    by_size_.resize(largest + 1);
    max_size_ = largest;
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      size_[g] = groups_[g].size();
      alive_[g].assign(groups_[g].size(), 1);
      by_size_[size_[g]].push_back(g);
      for (std::size_t k = 0; k < groups_[g].size(); ++k) by_fact_[groups_[g][k]].push_back({g, k});
    }
    update_top();
  }
  bool empty() const { return max_size_ <= 1; }
  std::vector<FactId> pop() {
    std::vector<FactId> taken;
    for (std::size_t k = 0; k < groups_[top_].size(); ++k) {
      if (alive_[top_][k]) taken.push_back(groups_[top_][k]);
    }
    for (FactId f : taken) {
      for (const auto& [g, k] : by_fact_[f]) {
        if (alive_[g][k]) {
          alive_[g][k] = 0;
          --size_[g];
        }
      }
    }
    update_top();
    return taken;
  }

 private:
  void update_top() {
    while (max_size_ > 1) {
      auto& list = by_size_[max_size_];
      while (!list.empty()) {
        const std::size_t candidate = list.back();
        list.pop_back();
        if (size_[candidate] == max_size_) {
          top_ = candidate;
          return;
        }
        by_size_[size_[candidate]].push_back(candidate);
      }
      --max_size_;
    }
  }

  std::vector<std::vector<FactId>> groups_;
  std::vector<std::vector<char>> alive_;
  std::vector<std::size_t> size_;
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> by_fact_;  // per fact: (group, place)
  std::vector<std::vector<std::size_t>> by_size_;
  std::size_t max_size_ = 0, top_ = 0;
};

}  // namespace

std::vector<std::vector<FactId>> choose_variables(const Task& task, const MutexGroups& mutexes) {
  const std::vector<std::uint32_t> atom = atom_order(task);
  const auto by_atom = [&](FactId a, FactId b) { return atom[a] < atom[b]; };
  const auto groups_by_atoms = [&](const std::vector<FactId>& a, const std::vector<FactId>& b) {
    return std::lexicographical_compare(a.begin(), a.end(), b.begin(), b.end(), by_atom);
  };
  std::vector<std::vector<FactId>> groups = mutexes.groups;
  for (auto& g : groups) std::sort(g.begin(), g.end(), by_atom);
  std::sort(groups.begin(), groups.end(), groups_by_atoms);
  std::vector<char> negative_in_goal(task.fact_count(), 0);
  for (const Condition& c : task.goal) {
    for (FactId f : c.negative) negative_in_goal[f] = 1;
  }
  for (auto& g : groups) std::erase_if(g, [&](FactId f) { return negative_in_goal[f] != 0; });
  GroupCoverQueue queue(std::move(groups), task.fact_count());
  std::vector<char> covered(task.fact_count(), 0);
  std::vector<std::vector<FactId>> variables;
  while (!queue.empty()) {
    std::vector<FactId> chosen = queue.pop();
    for (FactId f : chosen) covered[f] = 1;
    variables.push_back(std::move(chosen));
  }
  for (FactId f = 0; f < static_cast<FactId>(task.fact_count()); ++f) {
    if (!covered[f] && !task.derived[f]) variables.push_back({f});
  }
  for (auto& v : variables) std::sort(v.begin(), v.end(), by_atom);
  std::sort(variables.begin(), variables.end(), groups_by_atoms);
  return variables;
}

}  // namespace cluttertamp::search::detail
