// Fast Downward's finite-domain encoding as far as searches depend on it: the variables
// chosen, their causal-graph order, operators irrelevant to the goal, and the order
// successors and relaxed facts are taken in.
#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/search/grounding.hpp"
#include "cluttertamp/pddl/validator.hpp"
#include "cluttertamp/search/planner.hpp"
#include "search/mutex_groups.hpp"
#include "search/state_space.hpp"
#include "search/successor_order.hpp"

namespace cluttertamp::search {
namespace {

struct Grounded {
  pddl::Domain domain;
  pddl::Problem problem;
  Task task;

  Grounded(const std::string& domain_text, const std::string& problem_text)
      : domain(pddl::parse_domain(domain_text, "domain.pddl")),
        problem(pddl::parse_problem(problem_text, "problem.pddl", domain)),
        task(ground(domain, problem)) {}

  FactId fact(const std::string& name) const {
    const auto it = std::find(task.fact_names.begin(), task.fact_names.end(), name);
    if (it == task.fact_names.end()) throw std::logic_error("no fact " + name);
    return static_cast<FactId>(it - task.fact_names.begin());
  }
  detail::MutexGroups mutexes() const { return detail::find_mutex_groups(task, 1'000'000); }
  detail::SuccessorOrder order() const {
    return detail::successor_order(task, mutexes(), std::vector<char>(task.operators.size(), 0));
  }
  // The plan checked by the PDDL validator, on the files' own semantics.
  bool valid(const SearchResult& r) const {
    std::string text;
    for (OperatorId op : r.plan) text += task.operators[op].name + "\n";
    return pddl::validate_plan(domain, problem, pddl::parse_plan(text, "plan", domain, problem)).valid;
  }
};

// Tokens slide between neighbouring cells into empty ones.
constexpr const char* kSlideDomain = R"((define (domain slide) (:requirements :strips)
  (:predicates (pos ?o ?p) (empty ?p) (next ?p ?q))
  (:action slide :parameters (?o ?from ?to)
    :precondition (and (pos ?o ?from) (empty ?to) (next ?from ?to))
    :effect (and (pos ?o ?to) (empty ?from) (not (pos ?o ?from)) (not (empty ?to))))))";

// Tokens x and y on three cells in a row, c empty.
constexpr const char* kSlideRow = R"((define (problem row) (:domain slide) (:objects a b c x y)
  (:init (pos x a) (pos y b) (empty c) (next a b) (next b a) (next b c) (next c b))
  (:goal (pos x c))))";

TEST(PddlMutexGroups, OfEqualGroupsTheLastInAtomOrderIsTakenFirst) {
  // Six groups of three facts: per token its cells, per cell (empty c) or a token on it,
  // and the one empty cell. In atom order the tokens' groups come last, so the
  // translator takes them first; the cells' groups are then left with one fact each,
  // and the empty cell's group is taken whole (Fast Downward 5ea802478 makes these
  // three variables of this task).
  const Grounded g(kSlideDomain, kSlideRow);
  const auto variables = detail::choose_variables(g.task, g.mutexes());
  std::vector<std::set<std::string>> chosen;
  for (const auto& v : variables) {
    std::set<std::string> names;
    for (FactId f : v) names.insert(g.task.fact_names[f]);
    chosen.push_back(names);
  }
  // In the translator's order: by their facts in atom order.
  const std::vector<std::set<std::string>> expected{{"(empty a)", "(empty b)", "(empty c)"},
                                                    {"(pos x a)", "(pos x b)", "(pos x c)"},
                                                    {"(pos y a)", "(pos y b)", "(pos y c)"}};
  EXPECT_EQ(chosen, expected);
}

TEST(PddlMutexGroups, AtomsAreOrderedAsListsOfNames) {
  // As the translator sorts atoms: by predicate, then argument by argument, a name
  // before the longer names it begins and an atom before the longer atoms it begins.
  Task task;
  task.fact_names = {"(p a b)", "(p a)", "(p a!)", "(p)", "(pa b)", "(p ab)", "(p a a)", "(p-q a)"};
  EXPECT_EQ(detail::atom_order(task), (std::vector<std::uint32_t>{3, 1, 4, 0, 7, 5, 2, 6}));
}

// A porter carries parcels between rooms; a bell can be rung in the porter's room, and
// walking sets a lamp on where it arrives.
constexpr const char* kPorterDomain = R"((define (domain porter) (:requirements :strips)
  (:predicates (porter-at ?r) (parcel-at ?p ?r) (holding ?p) (empty-handed) (rung ?r) (lit ?r) (link ?x ?y))
  (:action walk :parameters (?x ?y) :precondition (and (porter-at ?x) (link ?x ?y))
           :effect (and (porter-at ?y) (not (porter-at ?x)) (lit ?y)))
  (:action ring :parameters (?r) :precondition (porter-at ?r) :effect (rung ?r))
  (:action pick :parameters (?p ?r) :precondition (and (porter-at ?r) (parcel-at ?p ?r) (empty-handed))
           :effect (and (holding ?p) (not (parcel-at ?p ?r)) (not (empty-handed))))
  (:action drop :parameters (?p ?r) :precondition (and (porter-at ?r) (holding ?p))
           :effect (and (parcel-at ?p ?r) (empty-handed) (not (holding ?p))))))";

std::string porter_problem(const std::string& goal) {
  return R"((define (problem two) (:domain porter) (:objects a b c p)
    (:init (porter-at a) (parcel-at p a) (empty-handed) (link a b) (link b a) (link b c) (link c b))
    (:goal )" + goal + "))";
}

TEST(PddlSuccessorOrder, OperatorsThatChangeNothingTheGoalDependsOnAreLeftOut) {
  const Grounded g(kPorterDomain, porter_problem("(parcel-at p c)"));
  const auto order = g.order();
  std::size_t rings = 0;
  for (OperatorId o = 0; o < static_cast<OperatorId>(g.task.operators.size()); ++o) {
    const bool ring = g.task.operators[o].name.rfind("(ring", 0) == 0;
    rings += ring;
    // Ringing changes only bells; walking also moves the porter, which picking needs.
    EXPECT_EQ(order.relevant[o] != 0, !ring) << g.task.operators[o].name;
  }
  EXPECT_EQ(rings, 3u);
  const SearchResult r = plan(g.task, {.algorithm = "lama-first"});
  ASSERT_TRUE(r.solved);
  EXPECT_EQ(r.statistics.irrelevant, rings);
  EXPECT_TRUE(g.valid(r));

  // Once the goal needs bell b rung, ringing it counts (the other bells still do not),
  // and the plan rings it.
  const Grounded bell(kPorterDomain, porter_problem("(and (parcel-at p c) (rung b))"));
  const auto bell_order = bell.order();
  for (OperatorId o = 0; o < static_cast<OperatorId>(bell.task.operators.size()); ++o) {
    const std::string& name = bell.task.operators[o].name;
    EXPECT_EQ(bell_order.relevant[o] != 0, name.rfind("(ring", 0) != 0 || name == "(ring b)") << name;
  }
  const SearchResult rung = plan(bell.task, {.algorithm = "lama-first"});
  ASSERT_TRUE(rung.solved);
  EXPECT_EQ(rung.statistics.irrelevant, 2u);
  EXPECT_TRUE(bell.valid(rung));
}

// A task's operators without those the search leaves out, by name; names kept.
Task without(const Task& task, const std::set<std::string>& left_out) {
  Task copy = task;
  std::erase_if(copy.operators, [&](const Operator& op) { return left_out.count(op.name) > 0; });
  return copy;
}

std::vector<std::string> plan_names(const Task& task, const SearchResult& r) {
  std::vector<std::string> names;
  for (OperatorId op : r.plan) names.push_back(task.operators[op].name);
  return names;
}

TEST(PddlSuccessorOrder, ASearchWithOperatorsLeftOutIsTheSearchOfATaskWithoutThem) {
  // The searches run on the grounded task with the operators they leave out marked. A
  // shortcut needs the porter in two rooms at once: never applicable, but in the delete
  // relaxation it would carry the parcel straight to c. Ringing is irrelevant and, if
  // it were searched, would add successors.
  std::string domain = kPorterDomain;
  domain.insert(domain.rfind(')'), R"(
  (:action shortcut :parameters (?p) :precondition (and (porter-at a) (porter-at c) (parcel-at ?p a))
           :effect (and (parcel-at ?p c) (not (parcel-at ?p a)))))");
  domain.insert(domain.find("(:predicates"), "(:constants a c) ");
  std::string problem = porter_problem("(parcel-at p c)");
  problem.replace(problem.find("(:objects a b c p)"), 18, "(:objects b p)");
  const Grounded g(domain, problem);
  const Task searched = without(g.task, {"(shortcut p)", "(ring a)", "(ring b)", "(ring c)"});
  ASSERT_EQ(searched.operators.size() + 4, g.task.operators.size());
  for (const std::string algorithm : {"lama-first", "lazy-gbfs-ff", "eager-gbfs-ff", "gbfs-add", "astar-lmcut", "astar-hmax"}) {
    const SearchResult marked = plan(g.task, {.algorithm = algorithm});
    const SearchResult copied = plan(searched, {.algorithm = algorithm});
    ASSERT_TRUE(marked.solved) << algorithm;
    ASSERT_TRUE(copied.solved) << algorithm;
    EXPECT_EQ(marked.statistics.never_applicable, 1u) << algorithm;
    EXPECT_EQ(marked.statistics.irrelevant, 3u) << algorithm;
    EXPECT_EQ(copied.statistics.never_applicable + copied.statistics.irrelevant, 0u) << algorithm;
    EXPECT_EQ(marked.statistics.expanded, copied.statistics.expanded) << algorithm;
    EXPECT_EQ(marked.statistics.generated, copied.statistics.generated) << algorithm;
    EXPECT_EQ(marked.statistics.evaluated, copied.statistics.evaluated) << algorithm;
    EXPECT_EQ(plan_names(g.task, marked), plan_names(searched, copied)) << algorithm;
    EXPECT_TRUE(g.valid(marked)) << algorithm;
  }
  // Relaxed, the shortcut would save picking the parcel up and dropping it.
  EXPECT_EQ(initial_heuristic(searched, "hff"), 4.0);
  EXPECT_EQ(initial_heuristic(g.task, "hff"), 3.0);
}

TEST(PddlSuccessorOrder, AVariableAPreconditionNeedsOutOfAValueMatters) {
  // The door locks only while the porter is not in room b, where it starts: walking out
  // is needed although no goal names a room, and nothing names a room positively.
  const Grounded g(R"((define (domain door) (:requirements :strips :negative-preconditions)
    (:constants b)
    (:predicates (porter-at ?r) (link ?x ?y) (locked))
    (:action walk :parameters (?x ?y) :precondition (and (porter-at ?x) (link ?x ?y))
             :effect (and (porter-at ?y) (not (porter-at ?x))))
    (:action lock :precondition (not (porter-at b)) :effect (locked))))",
                   R"((define (problem out) (:domain door) (:objects a c)
    (:init (porter-at b) (link a b) (link b a) (link b c) (link c b)) (:goal (locked))))");
  const auto order = g.order();
  for (OperatorId o = 0; o < static_cast<OperatorId>(g.task.operators.size()); ++o) {
    EXPECT_TRUE(order.relevant[o]) << g.task.operators[o].name;
  }
  const SearchResult r = plan(g.task, {.algorithm = "lama-first"});
  ASSERT_TRUE(r.solved);
  EXPECT_EQ(r.plan.size(), 2u);
  EXPECT_TRUE(g.valid(r));
}

TEST(PddlSuccessorOrder, VariablesFollowTheCausalGraphWithGoalVariablesLast) {
  const Grounded g(kPorterDomain, porter_problem("(parcel-at p c)"));
  const auto order = g.order();
  const auto place = [&](const std::string& fact) { return order.search_variable[g.fact(fact)]; };
  // The porter's room is only ever a precondition of the hand and the parcel: first.
  // The hand and the parcel depend on each other; the parcel, a goal, comes last.
  EXPECT_EQ(place("(porter-at a)"), place("(porter-at c)"));
  EXPECT_EQ(place("(parcel-at p a)"), place("(holding p)"));
  EXPECT_LT(place("(porter-at a)"), place("(empty-handed)"));
  EXPECT_LT(place("(empty-handed)"), place("(parcel-at p c)"));
  EXPECT_EQ(order.relevant_variables, 3u);
  // Bells and lamps do not matter for the goal: after every variable that does.
  EXPECT_GE(place("(rung b)"), order.relevant_variables);
  EXPECT_GE(place("(lit c)"), order.relevant_variables);
}

TEST(PddlSuccessorOrder, SuccessorsComeInTheOrderOfTheirPreconditionVariables) {
  const Grounded g(kSlideDomain, kSlideRow);
  const auto order = g.order();
  // Per operator its precondition variables' places, sorted: successors are listed by
  // these lists compared lexicographically (values break ties within one variable).
  const auto key = [&](OperatorId o) {
    std::vector<std::uint32_t> k;
    for (FactId f : g.task.operators[o].precondition.positive) k.push_back(order.search_variable[f]);
    std::sort(k.begin(), k.end());
    return k;
  };
  const detail::StateSpace space(g.task, {.successor_rank = order.rank});
  detail::State s = space.initial();
  for (int step = 0; step < 6; ++step) {
    std::vector<OperatorId> listed;
    space.applicable_operators(s, listed);
    ASSERT_GE(listed.size(), 1u);
    for (std::size_t i = 1; i < listed.size(); ++i) EXPECT_LE(key(listed[i - 1]), key(listed[i]));
    s = space.apply(s, listed.back());
  }
}

// A 4 x 4 board of twelve tokens; eight must reach given cells.
std::string slide_board() {
  std::string cells, next;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      const std::string here = "c" + std::to_string(r) + std::to_string(c);
      cells += here + " ";
      for (const auto& [dr, dc] : {std::pair{0, 1}, {1, 0}, {0, -1}, {-1, 0}}) {
        if (r + dr < 0 || r + dr > 3 || c + dc < 0 || c + dc > 3) continue;
        next += "(next " + here + " c" + std::to_string(r + dr) + std::to_string(c + dc) + ") ";
      }
    }
  }
  return "(define (problem board) (:domain slide) (:objects " + cells +
         "t0 t1 t2 t3 t4 t5 t6 t7 t8 t9 t10 t11)\n"
         "(:init (pos t0 c03) (pos t1 c32) (pos t2 c13) (pos t3 c21) (pos t4 c31) (pos t5 c23) (pos t6 c10) "
         "(pos t7 c11) (pos t8 c30) (pos t9 c20) (pos t10 c01) (pos t11 c00) (empty c33) (empty c12) (empty c02) "
         "(empty c22) " + next + ")\n"
         "(:goal (and (pos t0 c30) (pos t1 c21) (pos t2 c02) (pos t3 c22) (pos t4 c10) (pos t5 c11) (pos t6 c13) "
         "(pos t7 c23))))";
}

TEST(PddlSuccessorOrder, GreedySearchesExpandWhatFastDownwardExpands) {
  // Fast Downward (5ea802478) on this board: lazy_greedy([ff()], preferred=[ff()])
  // expands 209 states for a 47-step plan, and lama-first's search 301 for 52 steps.
  // Equal counts need its successor order, its relaxed exploration order and its
  // landmark-count updates.
  const Grounded g(kSlideDomain, slide_board());
  const SearchResult ff = plan(g.task, {.algorithm = "lazy-gbfs-ff"});
  ASSERT_TRUE(ff.solved);
  EXPECT_TRUE(g.valid(ff));
  EXPECT_EQ(ff.statistics.expanded, 209u);
  EXPECT_EQ(ff.plan.size(), 47u);
  const SearchResult lama = plan(g.task, {.algorithm = "lama-first"});
  ASSERT_TRUE(lama.solved);
  EXPECT_TRUE(g.valid(lama));
  EXPECT_EQ(lama.statistics.expanded, 301u);
  EXPECT_EQ(lama.plan.size(), 52u);
}

}  // namespace
}  // namespace cluttertamp::search
