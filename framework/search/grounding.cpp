#include "cluttertamp/search/grounding.hpp"

#include <algorithm>
#include <chrono>
#include <memory>
#include <numeric>

#include "cluttertamp/core/free_beside.hpp"
#include "search/grounder.hpp"
#include "search/tuple_order.hpp"
#include "search/universal.hpp"

namespace cluttertamp::search {

namespace detail {

bool Grounder::extends(const pddl::Problem& problem) const {
  const std::size_t known = object_names_.size() - constant_count_;
  if (!compiled_ || problem.objects.size() < known) return false;
  for (std::size_t k = 0; k < known; ++k) {
    const pddl::TypedName& o = problem.objects[k];
    if (o.name != object_names_[constant_count_ + k] || o.types != object_types_[constant_count_ + k]) return false;
  }
  return true;
}

// Operators in name order, as Fast Downward's translator sorts them, so that a search
// takes the task as it is: schemas by name, a schema's instances by their objects'
// names. Facts were numbered in the order instances were grounded; that stays.
void Grounder::in_name_order(std::vector<Span>& spans, std::vector<Operator>& operators) const {
  std::vector<std::uint32_t> object_rank(object_names_.size());
  {
    std::vector<std::uint32_t> by_name(object_names_.size());
    std::iota(by_name.begin(), by_name.end(), 0u);
    std::sort(by_name.begin(), by_name.end(), [&](std::uint32_t a, std::uint32_t b) { return object_names_[a] < object_names_[b]; });
    for (std::uint32_t k = 0; k < by_name.size(); ++k) object_rank[by_name[k]] = k;
  }
  // "(name " or "(name)" decides between schemas: no name holds a space or parenthesis.
  std::vector<std::string> keys;
  for (const Schema& s : schemas_) keys.push_back(s.name + (s.parameters.empty() ? ")" : " "));
  std::vector<std::uint32_t> schema_rank(schemas_.size());
  {
    std::vector<std::uint32_t> by_key(schemas_.size());
    std::iota(by_key.begin(), by_key.end(), 0u);
    std::sort(by_key.begin(), by_key.end(), [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
    for (std::uint32_t k = 0; k < by_key.size(); ++k) schema_rank[by_key[k]] = k;
  }
  // Each instance once: its schema's rank, then its objects' ranks (a schema's instances
  // all have its arity, so the zeros after a shorter tuple never decide).
  std::size_t width = 1;
  for (const Schema& s : schemas_) width = std::max(width, 1 + s.parameters.size());
  const std::vector<std::uint32_t> order = lexicographic_order(
      spans.size(), width, std::max<std::uint64_t>(schemas_.size(), object_names_.size()), [&](std::uint32_t k, std::size_t i) {
        const Span& span = spans[k];
        if (i == 0) return std::uint64_t{schema_rank[span.schema]};
        return i <= schemas_[span.schema].parameters.size() ? std::uint64_t{object_rank[span.parameters[i - 1]]} : 0;
      });
  {
    std::vector<Span> ordered;
    ordered.reserve(spans.size());
    for (std::uint32_t k : order) ordered.push_back(spans[k]);
    spans.swap(ordered);
  }
  bool sorted = true;
  for (std::size_t k = 1; k < spans.size() && sorted; ++k) sorted = spans[k - 1].end == spans[k].begin;
  if (sorted) return;
  // Permuted in place, cycle by cycle: a second vector of them all would be the
  // largest allocation of a small task.
  std::vector<std::uint32_t> source;  // per place: the operator that moves there
  source.reserve(operators.size());
  for (const Span& span : spans) {
    for (std::size_t k = span.begin; k < span.end; ++k) source.push_back(static_cast<std::uint32_t>(k));
  }
  std::vector<char> placed(operators.size(), 0);
  for (std::size_t start = 0; start < operators.size(); ++start) {
    if (placed[start] || source[start] == start) continue;
    Operator first = std::move(operators[start]);
    std::size_t at = start;
    while (source[at] != start) {
      operators[at] = std::move(operators[source[at]]);
      placed[at] = 1;
      at = source[at];
    }
    operators[at] = std::move(first);
    placed[at] = 1;
  }
}

Task Grounder::run(const pddl::Problem& problem, GroundingStats* stats, double time_limit) {
  const auto start = std::chrono::steady_clock::now();
  problem_ = &problem;
  deadline_ = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(std::min(time_limit, 1e9)));
  if (!compiled_) compile();
  add_objects(problem);
  function_values_.clear();
  for (const pddl::NumericFact& f : problem.numeric_init) {
    std::vector<int> key{function_ids_.at(f.function.predicate)};
    for (const pddl::Term& t : f.function.args) key.push_back(object_index(t.name));
    function_values_[key] = f.value;
  }
  const bool unit_cost = !problem.minimize_total_cost;
  if (unit_cost_ != unit_cost) ++generation_;  // every cost changes meaning
  unit_cost_ = unit_cost;
  task_.unit_cost = unit_cost;
  explore();

  Task out;
  out.unit_cost = unit_cost;
  std::size_t instances = 0;  // one operator each, unless a precondition splits
  for (std::size_t i = 0; i < schemas_.size(); ++i) instances += schemas_[i].axiom ? 0 : instances_[i].size();
  out.operators.reserve(instances);
  std::size_t reused = 0;
  std::vector<Span> spans;  // each instance's operators
  Cached unkept;  // outside a session: nothing is recorded, and operators go straight out
  for (std::size_t i = 0; i < schemas_.size(); ++i) {
    InstanceSet& found = instances_[i];
    for (std::uint32_t k : found.sorted()) {
      check_deadline();  // millions of operators are made here too
      const std::span<const int> parameters = found[k];
      const std::size_t first = out.operators.size();
      if (!keep_) {
        ground_instance(i, parameters, unkept, out.operators, out.axioms);
      } else {
        std::unique_ptr<Cached>& cached = found.cached(k);
        if (!cached) cached = std::make_unique<Cached>();
        if (still_valid(*cached)) {
          ++reused;
        } else {
          cached->operators.clear();
          cached->axioms.clear();
          ground_instance(i, parameters, *cached, cached->operators, cached->axioms);
        }
        out.operators.insert(out.operators.end(), cached->operators.begin(), cached->operators.end());
        out.axioms.insert(out.axioms.end(), cached->axioms.begin(), cached->axioms.end());
      }
      if (out.operators.size() > first) spans.push_back({i, parameters.data(), first, out.operators.size()});
    }
  }
  in_name_order(spans, out.operators);
  std::stable_sort(out.axioms.begin(), out.axioms.end(), [](const Axiom& a, const Axiom& b) { return a.stratum < b.stratum; });
  for (int id : init_atoms_) {
    if (fluent_[atoms_[id].first]) out.initial.push_back(fact(id));
  }
  std::sort(out.initial.begin(), out.initial.end());
  out.initial.erase(std::unique(out.initial.begin(), out.initial.end()), out.initial.end());
  int goal_slots = 0;
  const CFormula goal = formula(problem.goal, {}, goal_slots);
  std::vector<int> goal_binding(static_cast<std::size_t>(std::max(1, goal_slots)), -1);
  Dnf goal_dnf;
  try {
    goal_dnf = dnf(goal, goal_binding, false);
  } catch (const TooManyDisjuncts&) {
    too_many(problem.goal.where, "the goal");
  }
  for (const auto& conjunction : goal_dnf) out.goal.push_back(condition(conjunction));
  out.fact_names = task_.fact_names;
  out.derived = task_.derived;

  if (stats) {
    stats->reachable_facts = static_cast<std::size_t>(std::count(reached_.begin(), reached_.end(), true));
    stats->operators = out.operators.size();
    stats->axioms = out.axioms.size();
    stats->reused_instances = reused;
    std::size_t statics = 0;
    for (std::size_t a = 0; a < atoms_.size(); ++a) statics += reached_[a] && !fluent_[atoms_[a].first];
    stats->static_facts = statics;
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return out;
}

}  // namespace detail

using detail::Grounder;

Task ground(const pddl::Domain& domain, const pddl::Problem& problem, GroundingStats* stats, double time_limit) {
  // Foralls that would multiply out in disjunctive normal form become derived predicates.
  const std::optional<pddl::Domain> compiled = detail::with_universal_axioms(domain);
  auto grounder = std::make_unique<Grounder>(compiled ? *compiled : domain, false);
  try {
    return grounder->run(problem, stats, time_limit);
  } catch (const TimeLimit&) {
    free_beside(std::move(grounder));
    throw;
  }
}

struct Grounding::Impl {
  explicit Impl(const pddl::Domain& d) : domain(d), compiled(detail::with_universal_axioms(d)) {}
  const pddl::Domain& domain;
  const std::optional<pddl::Domain> compiled;
  std::unique_ptr<Grounder> grounder;
};

Grounding::Grounding(const pddl::Domain& domain) : impl_(std::make_unique<Impl>(domain)) {}
Grounding::~Grounding() = default;

Task Grounding::ground(const pddl::Problem& problem, GroundingStats* stats, double time_limit) {
  if (!impl_->grounder || !impl_->grounder->extends(problem)) {
    if (impl_->grounder) free_beside(std::move(impl_->grounder));
    impl_->grounder = std::make_unique<Grounder>(impl_->compiled ? *impl_->compiled : impl_->domain, true);
  }
  const bool incremental = !impl_->grounder->fresh();
  const auto start = std::chrono::steady_clock::now();
  try {
    return impl_->grounder->run(problem, stats, time_limit);
  } catch (const InputError&) {
    // An instance only an earlier problem reached may read a cost this problem does not
    // give (ground() would not make it): grounded afresh, the problem decides alone.
    free_beside(std::move(impl_->grounder));
    if (!incremental) throw;
    return ground(problem, stats, time_limit - std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  } catch (...) {
    // Half-updated: the next problem starts afresh.
    free_beside(std::move(impl_->grounder));
    throw;
  }
}

}  // namespace cluttertamp::search
