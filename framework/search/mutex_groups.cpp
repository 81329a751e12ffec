#include "search/mutex_groups.hpp"

#include <algorithm>
#include <deque>
#include <map>
#include <set>
#include <string>
#include <unordered_map>

namespace cluttertamp::search::detail {

namespace {

// A fact's predicate and arguments, interned.
struct GroundAtom {
  int predicate = -1;
  std::vector<int> args;
};

// "(pred a b)" -> predicate and arguments, interned in `names`.
GroundAtom parse_atom(const std::string& text, std::unordered_map<std::string, int>& predicates,
                      std::unordered_map<std::string, int>& objects) {
  GroundAtom atom;
  std::size_t i = text.empty() || text[0] != '(' ? 0 : 1;
  bool first = true;
  while (i < text.size()) {
    while (i < text.size() && (text[i] == ' ' || text[i] == ')')) ++i;
    std::size_t end = i;
    while (end < text.size() && text[end] != ' ' && text[end] != ')') ++end;
    if (end == i) break;
    const std::string word = text.substr(i, end - i);
    if (first) {
      atom.predicate = predicates.emplace(word, static_cast<int>(predicates.size())).first->second;
      first = false;
    } else {
      atom.args.push_back(objects.emplace(word, static_cast<int>(objects.size())).first->second);
    }
    i = end;
  }
  return atom;
}

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
// effect with the unconditional deletes (which happen whenever it does).
struct Scope {
  std::vector<FactId> pre;  // sorted
  const std::vector<FactId>* add;
  std::vector<FactId> del;
};

class Synthesis {
 public:
  Synthesis(const Task& task, std::uint64_t budget) : task_(task), budget_(budget) {
    std::unordered_map<std::string, int> predicates, objects;
    atoms_.resize(task.fact_count());
    for (FactId f = 0; f < static_cast<FactId>(task.fact_count()); ++f) {
      if (task.derived[f]) continue;
      atoms_[f] = parse_atom(task.fact_names[f], predicates, objects);
    }
    predicate_count_ = static_cast<int>(predicates.size());
    arity_.assign(predicate_count_, 0);
    facts_of_.resize(predicate_count_);
    for (FactId f = 0; f < static_cast<FactId>(task.fact_count()); ++f) {
      if (task.derived[f]) continue;
      arity_[atoms_[f].predicate] = static_cast<int>(atoms_[f].args.size());
      facts_of_[atoms_[f].predicate].push_back(f);
    }
    adders_.resize(predicate_count_);
    for (OperatorId o = 0; o < static_cast<OperatorId>(task.operators.size()); ++o) {
      const Operator& op = task.operators[o];
      auto note = [&](const std::vector<FactId>& add) {
        for (FactId f : add) {
          if (task.derived[f]) continue;
          auto& list = adders_[atoms_[f].predicate];
          if (list.empty() || list.back() != o) list.push_back(o);
        }
      };
      note(op.add);
      for (const ConditionalEffect& c : op.conditional) note(c.add);
    }
    part_of_.assign(predicate_count_, -1);
    op_seen_.assign(task.operators.size(), 0);
  }

  MutexGroups run() {
    MutexGroups out;
    for (int p = 0; p < predicate_count_; ++p) {
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
    for (int p : part.positions) k.push_back(atoms_[f].args[p]);
    return k;
  }

  void enqueue(Invariant inv) {
    std::sort(inv.begin(), inv.end());
    if (seen_.insert(inv).second) queue_.push_back(std::move(inv));
  }

  const Part* part_for(FactId f) const {
    if (task_.derived[f]) return nullptr;
    const int i = part_of_[atoms_[f].predicate];
    return i < 0 ? nullptr : &(*current_)[i];
  }

  std::vector<Scope> scopes(const Operator& op) const {
    std::vector<Scope> out;
    std::vector<FactId> pre = op.precondition.positive;
    std::sort(pre.begin(), pre.end());
    out.push_back({pre, &op.add, op.del});
    for (const ConditionalEffect& c : op.conditional) {
      Scope s{pre, &c.add, op.del};
      s.pre.insert(s.pre.end(), c.condition.positive.begin(), c.condition.positive.end());
      std::sort(s.pre.begin(), s.pre.end());
      // The deletes of every conditional effect that fires whenever this one does (the
      // grounder gives each literal of one `when` an effect of its own).
      for (const ConditionalEffect& other : op.conditional) {
        if (implied(other.condition, s.pre, c.condition.negative)) s.del.insert(s.del.end(), other.del.begin(), other.del.end());
      }
      out.push_back(std::move(s));
    }
    return out;
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
    struct Added {
      FactId fact;
      std::size_t scope;
      Key key;
    };
    const std::vector<Scope> all = scopes(op);
    std::vector<Added> added;
    for (std::size_t s = 0; s < all.size(); ++s) {
      for (FactId f : *all[s].add) {
        ++work_;
        const Part* part = part_for(f);
        if (!part || std::binary_search(all[s].pre.begin(), all[s].pre.end(), f)) continue;
        added.push_back({f, s, key(f, *part)});
      }
    }
    for (std::size_t i = 0; i < added.size(); ++i) {
      for (std::size_t j = i + 1; j < added.size(); ++j) {
        if (added[i].fact != added[j].fact && added[i].key == added[j].key) return false;  // too heavy
      }
    }
    for (const Added& a : added) {
      const Scope& scope = all[a.scope];
      bool matched = false;
      for (FactId d : scope.del) {
        ++work_;
        const Part* part = part_for(d);
        if (part && std::binary_search(scope.pre.begin(), scope.pre.end(), d) && key(d, *part) == a.key) {
          matched = true;
          break;
        }
      }
      if (!matched) {
        refine(inv, scope, a.key);
        return false;
      }
    }
    return true;
  }

  // New candidates: `inv` with a part for a delete of `scope` whose arguments give `key`.
  void refine(const Invariant& inv, const Scope& scope, const Key& key) {
    for (FactId d : scope.del) {
      if (task_.derived[d] || !std::binary_search(scope.pre.begin(), scope.pre.end(), d)) continue;
      const GroundAtom& atom = atoms_[d];
      if (part_of_[atom.predicate] >= 0) continue;
      const int spare = static_cast<int>(atom.args.size()) - static_cast<int>(key.size());
      if (spare < 0 || spare > 1) continue;
      std::vector<int> positions;
      std::vector<char> used(atom.args.size(), 0);
      assign(inv, atom, key, positions, used);
    }
  }

  void assign(const Invariant& inv, const GroundAtom& atom, const Key& key, std::vector<int>& positions,
              std::vector<char>& used) {
    ++work_;
    if (positions.size() == key.size()) {
      Part part{atom.predicate, positions, -1};
      for (std::size_t i = 0; i < used.size(); ++i) {
        if (!used[i]) part.counted = static_cast<int>(i);
      }
      Invariant refined = inv;
      refined.push_back(std::move(part));
      enqueue(std::move(refined));
      return;
    }
    for (std::size_t p = 0; p < atom.args.size(); ++p) {
      if (used[p] || atom.args[p] != key[positions.size()]) continue;
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
  std::vector<GroundAtom> atoms_;
  int predicate_count_ = 0;
  std::vector<int> arity_;
  std::vector<std::vector<FactId>> facts_of_;
  std::vector<std::vector<OperatorId>> adders_;
  std::deque<Invariant> queue_;
  std::set<Invariant> seen_;
  const Invariant* current_ = nullptr;
  std::vector<int> part_of_;
  std::vector<std::uint32_t> op_seen_;
  std::uint32_t stamp_ = 0;
};

}  // namespace

MutexGroups find_mutex_groups(const Task& task, std::uint64_t work_budget) {
  return Synthesis(task, work_budget).run();
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

std::vector<std::vector<FactId>> choose_variables(const Task& task, const MutexGroups& mutexes) {
  std::vector<char> negative_in_goal(task.fact_count(), 0);
  for (const Condition& c : task.goal) {
    for (FactId f : c.negative) negative_in_goal[f] = 1;
  }
  std::vector<std::vector<FactId>> open;
  for (const auto& group : mutexes.groups) {
    std::vector<FactId> kept;
    for (FactId f : group) {
      if (!negative_in_goal[f]) kept.push_back(f);
    }
    if (kept.size() > 1) open.push_back(std::move(kept));
  }
  std::vector<char> covered(task.fact_count(), 0);
  std::vector<std::vector<FactId>> variables;
  for (;;) {
    std::size_t best = open.size(), best_size = 1;
    for (std::size_t i = 0; i < open.size(); ++i) {
      std::size_t n = 0;
      for (FactId f : open[i]) n += !covered[f];
      if (n > best_size) {
        best = i;
        best_size = n;
      }
    }
    if (best == open.size()) break;
    std::vector<FactId> chosen;
    for (FactId f : open[best]) {
      if (!covered[f]) chosen.push_back(f);
      covered[f] = 1;
    }
    variables.push_back(std::move(chosen));
  }
  for (FactId f = 0; f < static_cast<FactId>(task.fact_count()); ++f) {
    if (!covered[f] && !task.derived[f]) variables.push_back({f});
  }
  std::sort(variables.begin(), variables.end());
  return variables;
}

}  // namespace cluttertamp::search::detail
