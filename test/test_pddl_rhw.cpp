// Mutex groups from invariant synthesis, finite-domain variables, and RHW landmarks.
#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/search/grounding.hpp"
#include "cluttertamp/search/planner.hpp"
#include "search/landmarks.hpp"
#include "search/mutex_groups.hpp"
#include "search/state_space.hpp"

namespace cluttertamp::search {
namespace {

using detail::Landmarks;
using detail::RelaxedTask;
using detail::StateSpace;

// A porter with two hands carries parcels between rooms; a bell rings (and stays rung)
// in every room it enters; a copier puts a second parcel beside the first.
constexpr const char* kPorterDomain = R"((define (domain porter)
  (:requirements :strips :typing)
  (:types room parcel hand)
  (:predicates (porter-at ?r - room) (parcel-at ?p - parcel ?r - room) (holding ?h - hand ?p - parcel)
               (free ?h - hand) (rung ?r - room) (link ?x ?y - room))
  (:action walk :parameters (?x ?y - room) :precondition (and (porter-at ?x) (link ?x ?y))
           :effect (and (porter-at ?y) (not (porter-at ?x)) (rung ?y)))
  (:action pick :parameters (?p - parcel ?r - room ?h - hand)
           :precondition (and (porter-at ?r) (parcel-at ?p ?r) (free ?h))
           :effect (and (holding ?h ?p) (not (parcel-at ?p ?r)) (not (free ?h))))
  (:action drop :parameters (?p - parcel ?r - room ?h - hand)
           :precondition (and (porter-at ?r) (holding ?h ?p))
           :effect (and (parcel-at ?p ?r) (free ?h) (not (holding ?h ?p))))))";
constexpr const char* kPorterProblem = R"((define (problem two) (:domain porter)
  (:objects a b c - room p q - parcel left right - hand)
  (:init (porter-at a) (parcel-at p a) (parcel-at q b) (free left) (free right)
         (link a b) (link b a) (link b c) (link c b))
  (:goal (and (parcel-at p c) (parcel-at q c)))))";

struct Grounded {
  pddl::Domain domain;
  pddl::Problem problem;
  Task task;

  Grounded(const char* domain_text, const char* problem_text)
      : domain(pddl::parse_domain(domain_text, "domain.pddl")),
        problem(pddl::parse_problem(problem_text, "problem.pddl", domain)),
        task(ground(domain, problem)) {}

  std::set<std::string> names(const std::vector<FactId>& facts) const {
    std::set<std::string> out;
    for (FactId f : facts) out.insert(task.fact_names[f]);
    return out;
  }
  std::set<std::set<std::string>> groups(const std::vector<std::vector<FactId>>& list) const {
    std::set<std::set<std::string>> out;
    for (const auto& g : list) {
      if (g.size() > 1) out.insert(names(g));
    }
    return out;
  }
};

TEST(PddlMutexGroups, PorterInvariantsAreFoundAndRefined) {
  const Grounded g(kPorterDomain, kPorterProblem);
  const auto mutexes = detail::find_mutex_groups(g.task, 1'000'000);
  EXPECT_TRUE(mutexes.complete);
  const auto groups = g.groups(mutexes.groups);
  using S = std::set<std::string>;
  // Counted room: the porter is in one room.
  EXPECT_TRUE(groups.count(S{"(porter-at a)", "(porter-at b)", "(porter-at c)"}));
  // A parcel is in one room or one hand: refined from (parcel-at ?p ?r) by pick's delete.
  EXPECT_TRUE(groups.count(S{"(parcel-at p a)", "(parcel-at p b)", "(parcel-at p c)", "(holding left p)",
                             "(holding right p)"}));
  // A hand is free or holds one parcel: refined from (holding ?h ?p) by pick's (free ?h).
  EXPECT_TRUE(groups.count(S{"(free left)", "(holding left p)", "(holding left q)"}));
  // A bell once rung stays rung, and walking rings one without silencing another: no
  // group holds two bells.
  for (const auto& group : groups) {
    EXPECT_LE(std::count_if(group.begin(), group.end(), [](const std::string& f) { return f.rfind("(rung", 0) == 0; }), 1);
  }
}

TEST(PddlMutexGroups, EveryGroupIsAtMostOneInEveryReachableState) {
  const Grounded g(kPorterDomain, kPorterProblem);
  const auto mutexes = detail::find_mutex_groups(g.task, 1'000'000);
  ASSERT_FALSE(mutexes.groups.empty());
  // Breadth-first over every reachable state (a few hundred).
  const StateSpace space(g.task);
  std::set<detail::State> seen{space.initial()};
  std::vector<detail::State> open{space.initial()};
  while (!open.empty()) {
    const detail::State s = open.back();
    open.pop_back();
    for (const auto& group : mutexes.groups) {
      int n = 0;
      for (FactId f : group) n += detail::holds(s, f);
      ASSERT_LE(n, 1);
    }
    for (OperatorId o = 0; o < static_cast<OperatorId>(g.task.operators.size()); ++o) {
      if (!space.applicable(s, o)) continue;
      const detail::State next = space.apply(s, o);
      if (seen.insert(next).second) open.push_back(next);
    }
  }
  EXPECT_GT(seen.size(), 50u);
}

TEST(PddlMutexGroups, AnActionAddingTwoFactsOfOneInstanceBreaksTheInvariant) {
  const Grounded g(R"((define (domain split) (:requirements :strips)
    (:predicates (at ?x) (link ?x ?y))
    (:action move :parameters (?x ?y) :precondition (and (at ?x) (link ?x ?y)) :effect (and (at ?y) (not (at ?x))))
    (:action split :parameters (?x ?y ?z) :precondition (and (at ?x) (link ?x ?y) (link ?x ?z))
             :effect (and (at ?y) (at ?z) (not (at ?x))))))",
                   R"((define (problem p) (:domain split) (:objects a b c)
    (:init (at a) (link a b) (link a c) (link b a)) (:goal (and (at b) (at c)))))");
  const auto groups = g.groups(detail::find_mutex_groups(g.task, 1'000'000).groups);
  for (const auto& group : groups) EXPECT_FALSE(group.count("(at a)") && group.count("(at b)"));
}

TEST(PddlMutexGroups, AWhenThatMovesATokenKeepsItsInvariant) {
  // Tokens sit on places, in a box, or wait to start; a sweep moves every token on a
  // place into the box at once (one `when` deleting one fact and adding another).
  const Grounded g(R"((define (domain tokens) (:requirements :strips :conditional-effects)
    (:predicates (waiting ?t) (on ?t ?p) (boxed ?t) (token ?t) (place ?p))
    (:action start :parameters (?t ?p) :precondition (and (token ?t) (place ?p) (waiting ?t))
             :effect (and (on ?t ?p) (not (waiting ?t))))
    (:action sweep :parameters (?p) :precondition (place ?p)
             :effect (forall (?t) (when (on ?t ?p) (and (not (on ?t ?p)) (boxed ?t)))))
    (:action unbox :parameters (?t ?p) :precondition (and (boxed ?t) (place ?p))
             :effect (and (on ?t ?p) (not (boxed ?t))))))",
                   R"((define (problem p) (:domain tokens) (:objects s u a b)
    (:init (token s) (token u) (place a) (place b) (waiting s) (waiting u))
    (:goal (and (boxed s) (on u b)))))");
  const auto groups = g.groups(detail::find_mutex_groups(g.task, 1'000'000).groups);
  EXPECT_TRUE(groups.count({"(waiting s)", "(on s a)", "(on s b)", "(boxed s)"}));
  EXPECT_TRUE(groups.count({"(waiting u)", "(on u a)", "(on u b)", "(boxed u)"}));
}

TEST(PddlMutexGroups, TheWorkBudgetStopsTheSearchTheSameWayEachTime) {
  const Grounded g(kPorterDomain, kPorterProblem);
  const auto none = detail::find_mutex_groups(g.task, 0);
  EXPECT_FALSE(none.complete);
  const auto a = detail::find_mutex_groups(g.task, 40), b = detail::find_mutex_groups(g.task, 40);
  EXPECT_EQ(a.groups, b.groups);
  EXPECT_EQ(a.candidates, b.candidates);
  EXPECT_LT(a.candidates, detail::find_mutex_groups(g.task, 1'000'000).candidates);
}

TEST(PddlMutexGroups, VariablesCoverEveryFluentFactOnce) {
  const Grounded g(kPorterDomain, kPorterProblem);
  const auto variables = detail::choose_variables(g.task, detail::find_mutex_groups(g.task, 1'000'000));
  std::vector<int> times(g.task.fact_count(), 0);
  for (const auto& v : variables) {
    for (FactId f : v) ++times[f];
  }
  for (FactId f = 0; f < static_cast<FactId>(g.task.fact_count()); ++f) EXPECT_EQ(times[f], 1) << g.task.fact_names[f];
  // The largest groups are chosen first: each parcel's five places.
  const auto chosen = g.groups(variables);
  EXPECT_TRUE(chosen.count({"(parcel-at p a)", "(parcel-at p b)", "(parcel-at p c)", "(holding left p)", "(holding right p)"}));
  EXPECT_TRUE(chosen.count({"(porter-at a)", "(porter-at b)", "(porter-at c)"}));
}

// A task without the operators that achieve any fact of `atoms`.
Task without_achievers(const Task& task, const std::vector<FactId>& atoms) {
  Task out = task;
  out.operators.clear();
  for (const Operator& op : task.operators) {
    bool achieves = false;
    for (FactId f : atoms) {
      achieves |= std::find(op.add.begin(), op.add.end(), f) != op.add.end();
      for (const auto& c : op.conditional) achieves |= std::find(c.add.begin(), c.add.end(), f) != c.add.end();
    }
    if (!achieves) out.operators.push_back(op);
  }
  return out;
}

// Every landmark is one: without its achievers no plan exists (blind search proves it).
void expect_every_landmark_necessary(const Grounded& g, const Landmarks& landmarks, const StateSpace& space) {
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    const auto& atoms = landmarks.atoms(static_cast<int>(i));
    if (landmarks.holds(static_cast<int>(i), space.initial())) continue;
    std::vector<FactId> task_atoms;
    for (FactId f : atoms) {
      if (f < static_cast<FactId>(g.task.fact_count())) task_atoms.push_back(f);
    }
    if (task_atoms.size() != atoms.size()) continue;  // a complement: its achievers are deletes
    SearchOptions blind;
    blind.algorithm = "astar-blind";
    const SearchResult r = plan(without_achievers(g.task, task_atoms), blind);
    EXPECT_FALSE(r.solved) << g.task.fact_names[atoms.front()] << " is no landmark";
    EXPECT_EQ(r.reason.rfind("no plan exists", 0), 0u) << r.reason;
  }
}

// Each natural order holds on a plan: the parent is true no later than the child first is.
void expect_orders_hold_on(const Grounded& g, const Landmarks& landmarks, const StateSpace& space,
                           const std::vector<OperatorId>& plan_ops) {
  std::vector<detail::State> states{space.initial()};
  for (OperatorId o : plan_ops) states.push_back(space.apply(states.back(), o));
  auto first_true = [&](int l) {
    for (std::size_t t = 0; t < states.size(); ++t) {
      if (landmarks.holds(l, states[t])) return static_cast<int>(t);
    }
    return -1;
  };
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    const int child = first_true(static_cast<int>(i));
    ASSERT_GE(child, 0) << "landmark " << g.task.fact_names[landmarks.fact(static_cast<int>(i))] << " never holds";
    for (int p : landmarks.parents(static_cast<int>(i))) {
      const int parent = first_true(p);
      EXPECT_TRUE(parent < child || (parent == 0 && child == 0))
          << g.task.fact_names[landmarks.fact(p)] << " before " << g.task.fact_names[landmarks.fact(static_cast<int>(i))];
    }
  }
}

TEST(PddlRhwLandmarks, PorterLandmarksAreNecessaryAndTheirOrdersHold) {
  const Grounded g(kPorterDomain, kPorterProblem);
  const StateSpace space(g.task);
  const RelaxedTask relaxed(g.task, RelaxedTask::Costs::one);
  const Landmarks landmarks = Landmarks::rhw(relaxed, g.task, space.initial(), 10'000'000);
  EXPECT_TRUE(landmarks.complete());
  EXPECT_GT(landmarks.variable_count(), 0u);
  std::set<std::string> atomic;
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    if (landmarks.atoms(static_cast<int>(i)).size() == 1) atomic.insert(g.task.fact_names[landmarks.fact(static_cast<int>(i))]);
  }
  // The goals; the porter in c (to drop there), and in b on the way: the transition graph
  // of its room has no way from a to c but through b.
  for (const char* f : {"(parcel-at p c)", "(parcel-at q c)", "(porter-at c)", "(porter-at b)"}) {
    EXPECT_TRUE(atomic.count(f)) << f;
  }
  // Either hand may carry p: a disjunction of one predicate.
  bool hands = false;
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    hands |= g.names(landmarks.atoms(static_cast<int>(i))) == std::set<std::string>{"(holding left p)", "(holding right p)"};
  }
  EXPECT_TRUE(hands);
  expect_every_landmark_necessary(g, landmarks, space);
  SearchOptions optimal;
  optimal.algorithm = "astar-blind";
  const SearchResult r = plan(g.task, optimal);
  ASSERT_TRUE(r.solved);
  expect_orders_hold_on(g, landmarks, space, r.plan);
}

// A robot crosses a valley: from a it must pass x, then one of five fords, to reach c.
// The fords are too many for a disjunctive landmark (at most 4 facts), so back-chaining
// from (at c) stops; the transition graph of the robot's place still finds x.
TEST(PddlRhwLandmarks, TheTransitionGraphFindsAPlaceEveryWayPasses) {
  const Grounded g(R"((define (domain valley) (:requirements :strips)
    (:predicates (at ?x) (road ?x ?y) (fuel))
    (:action drive :parameters (?x ?y) :precondition (and (at ?x) (road ?x ?y)) :effect (and (at ?y) (not (at ?x))))
    (:action hop :parameters (?x) :precondition (and (at ?x) (fuel)) :effect (and (at ?x) (not (fuel))))))",
                   R"((define (problem p) (:domain valley) (:objects a x b d e f g c)
    (:init (at a) (fuel) (road a x) (road x a) (road b c) (road d c) (road e c) (road f c) (road g c)
           (road x b) (road x d) (road x e) (road x f) (road x g))
    (:goal (at c))))");
  const StateSpace space(g.task);
  const RelaxedTask relaxed(g.task, RelaxedTask::Costs::one);
  const Landmarks landmarks = Landmarks::rhw(relaxed, g.task, space.initial(), 10'000'000);
  std::set<std::set<std::string>> found;
  for (std::size_t i = 0; i < landmarks.size(); ++i) found.insert(g.names(landmarks.atoms(static_cast<int>(i))));
  EXPECT_TRUE(found.count({"(at x)"}));
  EXPECT_FALSE(found.count({"(at b)"}));
  // Zhu & Givan's labels find x too: both are complete for such relaxed landmarks.
  const Landmarks labels(relaxed, space.initial(), 10'000'000);
  std::set<std::string> labelled;
  for (std::size_t i = 0; i < labels.size(); ++i) labelled.insert(g.task.fact_names[labels.fact(static_cast<int>(i))]);
  EXPECT_TRUE(labelled.count("(at x)"));
  expect_every_landmark_necessary(g, landmarks, space);
}

TEST(PddlRhwLandmarks, TheWorkBudgetKeepsTheGoalLandmarks) {
  const Grounded g(kPorterDomain, kPorterProblem);
  const StateSpace space(g.task);
  const RelaxedTask relaxed(g.task, RelaxedTask::Costs::one);
  const Landmarks landmarks = Landmarks::rhw(relaxed, g.task, space.initial(), 0);
  EXPECT_FALSE(landmarks.complete());
  ASSERT_EQ(landmarks.size(), 2u);
  EXPECT_TRUE(landmarks.is_goal(0) && landmarks.is_goal(1));
}

TEST(PddlRhwLandmarks, LamaFirstSolvesWithEitherLandmarksAndRefusesAnUnknownName) {
  const Grounded g(kPorterDomain, kPorterProblem);
  for (const char* kind : {"rhw", "zhu-givan"}) {
    SearchOptions options;
    options.landmarks = kind;
    const SearchResult r = plan(g.task, options);
    ASSERT_TRUE(r.solved) << kind << ": " << r.reason;
  }
  SearchOptions odd;
  odd.landmarks = "hm";
  EXPECT_THROW(plan(g.task, odd), std::invalid_argument);
}

// The porter picks up by reaching into a room: (stretch x y ...) needs the porter in
// both rooms, which no reachable state has unless x = y.
std::string stretch_domain() {
  std::string text = kPorterDomain;
  const std::string pick = "(:action pick :parameters (?p - parcel ?r - room ?h - hand)\n"
                           "           :precondition (and (porter-at ?r) (parcel-at ?p ?r) (free ?h))\n"
                           "           :effect (and (holding ?h ?p) (not (parcel-at ?p ?r)) (not (free ?h))))";
  const std::string stretch = "(:action stretch :parameters (?x ?y - room ?p - parcel ?h - hand)\n"
                              "  :precondition (and (porter-at ?x) (porter-at ?y) (parcel-at ?p ?y) (free ?h))\n"
                              "  :effect (and (holding ?h ?p) (not (parcel-at ?p ?y)) (not (free ?h))))";
  const std::size_t at = text.find(pick);
  if (at == std::string::npos) throw std::logic_error("the porter domain has no pick action to replace");
  return text.replace(at, pick.size(), stretch);
}

TEST(PddlMutexGroups, OperatorsNeedingTwoFactsOfOneGroupAreLeftOutAndPlansNameTheGroundedOnes) {
  const std::string domain = stretch_domain();
  const Grounded g(domain.c_str(), kPorterProblem);
  const std::vector<char> never = detail::never_applicable(g.task, detail::find_mutex_groups(g.task, 1'000'000));
  std::size_t left_out = 0;
  for (OperatorId o = 0; o < static_cast<OperatorId>(g.task.operators.size()); ++o) {
    const std::string& name = g.task.operators[o].name;
    const bool two_rooms = name.rfind("(stretch ", 0) == 0 && name.substr(9, 2) != name.substr(11, 2);
    EXPECT_EQ(never[o] != 0, two_rooms) << name;
    left_out += never[o];
  }
  ASSERT_GT(left_out, 0u);
  const StateSpace space(g.task);
  for (const std::string& search : search_names()) {
    SearchOptions options;
    options.algorithm = search;
    const SearchResult r = plan(g.task, options);
    ASSERT_TRUE(r.solved) << search << ": " << r.reason;
    EXPECT_EQ(r.statistics.never_applicable, left_out) << search;
    // The plan's operators are the grounded task's: it runs there as it is.
    auto s = space.initial();
    for (OperatorId op : r.plan) {
      ASSERT_TRUE(space.applicable(s, op)) << search << ": " << g.task.operators[op].name;
      s = space.apply(s, op);
    }
    EXPECT_TRUE(space.is_goal(s)) << search;
  }
}

TEST(PddlSearchProgress, GreedySearchesSayTheirInitialAndEveryBetterValue) {
  const Grounded g(kPorterDomain, kPorterProblem);
  for (const char* search : {"lama-first", "lazy-gbfs-ff", "eager-gbfs-ff"}) {
    std::vector<SearchProgress> said;
    SearchOptions options;
    options.algorithm = search;
    options.on_progress = [&](const SearchProgress& p) { said.push_back(p); };
    const SearchResult r = plan(g.task, options);
    ASSERT_TRUE(r.solved) << search;
    ASSERT_FALSE(said.empty()) << search;
    EXPECT_EQ(said.front().heuristic, "ff") << search;
    EXPECT_EQ(said.front().evaluated, 1u) << search;
    std::map<std::string, double> best;
    for (const SearchProgress& p : said) {
      if (best.count(p.heuristic)) EXPECT_LT(p.value, best[p.heuristic]) << search << " " << p.heuristic;
      best[p.heuristic] = p.value;
      EXPECT_LE(p.expanded, r.statistics.expanded);
    }
    EXPECT_EQ(best.count("landmark count"), std::string(search) == "lama-first" ? 1u : 0u) << search;
  }
}

}  // namespace
}  // namespace cluttertamp::search
