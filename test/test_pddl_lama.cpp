// Landmarks, the landmark count, LAMA's first iteration and the anytime mode.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "cluttertamp/io/text_file.hpp"
#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/pddl/validator.hpp"
#include "cluttertamp/search/grounding.hpp"
#include "cluttertamp/search/planner.hpp"
#include "search/landmarks.hpp"
#include "search/state_space.hpp"
#include "test_support.hpp"

namespace cluttertamp::search {
namespace {

using detail::holds;
using detail::LandmarkCount;
using detail::Landmarks;
using detail::RelaxedTask;
using detail::State;
using detail::StateSpace;

// A key in room k opens the door of room b, behind which lies room c.
constexpr const char* kKeysDomain = R"((define (domain keys)
  (:requirements :strips)
  (:predicates (at ?r) (key-at ?r) (have-key) (open) (link ?x ?y) (door ?x) (beyond ?x ?y))
  (:action move :parameters (?x ?y) :precondition (and (at ?x) (link ?x ?y)) :effect (and (at ?y) (not (at ?x))))
  (:action take :parameters (?r) :precondition (and (at ?r) (key-at ?r)) :effect (and (have-key) (not (key-at ?r))))
  (:action unlock :parameters (?x) :precondition (and (at ?x) (have-key) (door ?x)) :effect (open))
  (:action enter :parameters (?x ?y) :precondition (and (at ?x) (open) (beyond ?x ?y))
           :effect (and (at ?y) (not (at ?x))))))";
constexpr const char* kKeysProblem = R"((define (problem fetch) (:domain keys)
  (:objects a b c k)
  (:init (at a) (key-at k) (link a b) (link b a) (link a k) (link k a) (door b) (beyond b c))
  (:goal (at c))))";

struct Keys {
  pddl::Domain domain = pddl::parse_domain(kKeysDomain, "keys-domain.pddl");
  pddl::Problem problem = pddl::parse_problem(kKeysProblem, "keys-problem.pddl", domain);
  Task task = ground(domain, problem);
  StateSpace space{task};
  RelaxedTask relaxed{task, RelaxedTask::Costs::one};

  FactId fact(const std::string& name) const {
    const auto at = std::find(task.fact_names.begin(), task.fact_names.end(), name);
    return at == task.fact_names.end() ? -1 : static_cast<FactId>(at - task.fact_names.begin());
  }
  OperatorId op(const std::string& name) const {
    for (OperatorId i = 0; i < static_cast<OperatorId>(task.operators.size()); ++i) {
      if (task.operators[i].name == name) return i;
    }
    return -1;
  }
};

int index_of(const Landmarks& l, FactId f) {
  for (std::size_t i = 0; i < l.size(); ++i) {
    if (l.fact(static_cast<int>(i)) == f) return static_cast<int>(i);
  }
  return -1;
}

bool has(const std::vector<int>& v, int x) { return std::find(v.begin(), v.end(), x) != v.end(); }

TEST(PddlLandmarks, LabelsFindEveryFactOnTheWayAndTheirOrders) {
  const Keys k;
  const Landmarks landmarks(k.relaxed, k.space.initial(), 1'000'000);
  ASSERT_TRUE(landmarks.complete());
  std::vector<std::string> names;
  for (std::size_t i = 0; i < landmarks.size(); ++i) names.push_back(k.task.fact_names[landmarks.fact(static_cast<int>(i))]);
  std::sort(names.begin(), names.end());
  // Every fact on the only way, (key-at k) included: true initially, and taking needs it.
  EXPECT_EQ(names, (std::vector<std::string>{"(at a)", "(at b)", "(at c)", "(at k)", "(have-key)", "(key-at k)", "(open)"}));
  const int open = index_of(landmarks, k.fact("(open)"));
  const int key = index_of(landmarks, k.fact("(have-key)"));
  const int at_b = index_of(landmarks, k.fact("(at b)"));
  const int at_c = index_of(landmarks, k.fact("(at c)"));
  const int at_k = index_of(landmarks, k.fact("(at k)"));
  ASSERT_GE(std::min({open, key, at_b, at_c, at_k}), 0);
  // Natural orders: what must have been true before.
  EXPECT_TRUE(has(landmarks.parents(open), key));
  EXPECT_TRUE(has(landmarks.parents(open), at_b));
  EXPECT_TRUE(has(landmarks.parents(at_c), open));
  EXPECT_TRUE(has(landmarks.parents(key), at_k));
  EXPECT_FALSE(has(landmarks.parents(key), open));
  // Greedy-necessary: the preconditions of the one first achiever.
  EXPECT_TRUE(has(landmarks.needed_by(key), open));
  EXPECT_TRUE(has(landmarks.needed_by(at_k), key));
  EXPECT_TRUE(has(landmarks.needed_by(open), at_c));
  EXPECT_TRUE(landmarks.is_goal(at_c));
  EXPECT_FALSE(landmarks.is_goal(open));
}

TEST(PddlLandmarks, TheCountFollowsThePathAndCountsWhatIsNeededAgain) {
  const Keys k;
  const Landmarks landmarks(k.relaxed, k.space.initial(), 1'000'000);
  LandmarkCount count(landmarks);
  const State s0 = k.space.initial();
  count.start(0, s0);
  // Future: (at k), (have-key), (at b), (open), (at c), not yet true.
  EXPECT_DOUBLE_EQ(count.value(0, s0), 5.0);
  // In k: (at k) past; (at a), past, is false and needed again to reach b.
  const State s1 = k.space.apply(s0, k.op("(move a k)"));
  count.reach(0, 1, s0, s1, true);
  EXPECT_DOUBLE_EQ(count.value(1, s1), 4.0 + 1.0);
  // Back in a without the key: (at k) is needed again, for (have-key).
  const State s2 = k.space.apply(s1, k.op("(move k a)"));
  count.reach(1, 2, s1, s2, true);
  EXPECT_DOUBLE_EQ(count.value(2, s2), 4.0 + 1.0);
  // The key taken: (have-key) past; (key-at k), gone, is needed by nothing left.
  const State s3 = k.space.apply(s1, k.op("(take k)"));
  count.reach(1, 3, s1, s3, true);
  EXPECT_DOUBLE_EQ(count.value(3, s3), 3.0 + 1.0);
  // A landmark made true is past, its parents past or not (Fast Downward's status): a
  // made-up state reached from s0 that holds the key has (have-key) past.
  State odd = s0;
  detail::set(odd, k.fact("(have-key)"));
  count.reach(0, 4, s0, odd, true);
  EXPECT_DOUBLE_EQ(count.value(4, odd), 4.0);
  // What is future on one path into a state stays future: reaching s2 again from s0
  // (as if in one step) leaves (at k) needed again.
  count.reach(0, 2, s0, s2, false);
  EXPECT_DOUBLE_EQ(count.value(2, s2), 4.0 + 1.0);
}

TEST(PddlLandmarks, TheWorkBudgetLeavesTheGoalFacts) {
  const Keys k;
  const Landmarks landmarks(k.relaxed, k.space.initial(), 0);
  EXPECT_FALSE(landmarks.complete());
  ASSERT_EQ(landmarks.size(), 1u);
  EXPECT_EQ(k.task.fact_names[landmarks.fact(0)], "(at c)");
  EXPECT_EQ(landmarks.order_count(), 0u);
}

struct Loaded {
  pddl::Domain domain;
  pddl::Problem problem;
  Task task;
};

Loaded load(const std::string& domain, const std::string& problem) {
  Loaded l{pddl::load_domain(test::data("pddl/" + domain)), {}, {}};
  l.problem = pddl::load_problem(test::data("pddl/" + problem), l.domain);
  l.task = ground(l.domain, l.problem);
  return l;
}

pddl::PlanValidation validate(const Loaded& l, const SearchResult& r) {
  std::string text;
  for (OperatorId op : r.plan) text += l.task.operators[op].name + "\n";
  return pddl::validate_plan(l.domain, l.problem, pddl::parse_plan(text, "plan", l.domain, l.problem));
}

// Visit every cell of an n x n grid: every cell is a landmark, which h_FF's one relaxed
// plan at a time does not keep track of.
Loaded tour(int n) {
  std::string problem = "(define (problem tour) (:domain tour) (:objects";
  auto cell = [](int i, int j) { return "c" + std::to_string(i) + "-" + std::to_string(j); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) problem += " " + cell(i, j);
  }
  problem += ") (:init (at c0-0) (seen c0-0)";
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (i + 1 < n) problem += " (link " + cell(i, j) + " " + cell(i + 1, j) + ") (link " + cell(i + 1, j) + " " + cell(i, j) + ")";
      if (j + 1 < n) problem += " (link " + cell(i, j) + " " + cell(i, j + 1) + ") (link " + cell(i, j + 1) + " " + cell(i, j) + ")";
    }
  }
  problem += ") (:goal (and";
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) problem += " (seen " + cell(i, j) + ")";
  }
  problem += ")))";
  Loaded l{pddl::parse_domain(R"((define (domain tour) (:requirements :strips)
    (:predicates (at ?c) (link ?x ?y) (seen ?c))
    (:action go :parameters (?x ?y) :precondition (and (at ?x) (link ?x ?y)) :effect (and (at ?y) (not (at ?x)) (seen ?y)))))",
                                   "tour-domain.pddl"),
           {}, {}};
  l.problem = pddl::parse_problem(problem, "tour.pddl", l.domain);
  l.task = ground(l.domain, l.problem);
  return l;
}

TEST(PddlSearch, LamaFirstFollowsTheLandmarksWhereFfAloneWanders) {
  const Loaded l = tour(8);
  SearchOptions lama, ff;
  lama.algorithm = "lama-first";
  ff.algorithm = "lazy-gbfs-ff";
  const SearchResult a = plan(l.task, lama), b = plan(l.task, ff);
  ASSERT_TRUE(a.solved) << a.reason;
  ASSERT_TRUE(b.solved) << b.reason;
  EXPECT_TRUE(validate(l, a).valid);
  EXPECT_TRUE(validate(l, b).valid);
  EXPECT_LT(a.statistics.expanded * 5, b.statistics.expanded);
  EXPECT_LT(a.plan.size(), b.plan.size());
  EXPECT_GE(a.plan.size(), 63u);  // 64 cells, one step each but the first
}

TEST(PddlSearch, AnytimeImprovesUntilNoCheaperPlanExists) {
  for (const auto& [domain, problem, optimal] :
       {std::tuple{"gripper/domain-untyped.pddl", "gripper/p6.pddl", 17.0}, std::tuple{"blocks/domain.pddl", "blocks/p6-3.pddl", 12.0},
        std::tuple{"logistics/domain.pddl", "logistics/p2-3-2.pddl", 10.0}}) {
    const Loaded l = load(domain, problem);
    SearchOptions options;
    options.algorithm = "lama-first";
    options.anytime = true;
    options.max_expansions = 2'000'000;
    std::vector<double> costs;
    options.on_plan = [&](const SearchResult& r) {
      EXPECT_TRUE(validate(l, r).valid) << problem;
      EXPECT_EQ(r.plans_found, static_cast<int>(costs.size()) + 1);
      costs.push_back(r.cost);
    };
    const SearchResult r = plan(l.task, options);
    ASSERT_TRUE(r.solved) << problem;
    EXPECT_EQ(r.anytime_end, "no cheaper plan exists") << problem;
    ASSERT_EQ(costs.size(), static_cast<std::size_t>(r.plans_found));
    EXPECT_DOUBLE_EQ(costs.back(), r.cost);
    for (std::size_t i = 1; i < costs.size(); ++i) EXPECT_LT(costs[i], costs[i - 1]) << problem;
    SearchOptions optimum;
    optimum.algorithm = "astar-lmcut";
    EXPECT_DOUBLE_EQ(r.cost, plan(l.task, optimum).cost) << problem;
    EXPECT_DOUBLE_EQ(r.cost, optimal) << problem;
  }
}

TEST(PddlSearch, AnytimeWithAnExpansionBudgetEndsAlikeEveryTime) {
  const Loaded l = load("gripper/domain-untyped.pddl", "gripper/p10.pddl");
  SearchOptions options;
  options.algorithm = "lama-first";
  options.anytime = true;
  options.max_expansions = 3000;
  const SearchResult a = plan(l.task, options), b = plan(l.task, options);
  ASSERT_TRUE(a.solved);
  EXPECT_EQ(a.anytime_end, "expansion limit");
  EXPECT_EQ(a.statistics.expanded, 3000u);
  EXPECT_EQ(a.plan, b.plan);
  EXPECT_EQ(a.plans_found, b.plans_found);
  EXPECT_TRUE(validate(l, a).valid);
}

TEST(TextFile, AFileIsReplacedWholeAndAFailedWriteLeavesTheOldOne) {
  const auto dir = std::filesystem::temp_directory_path() / "cluttertamp_text_file";
  std::filesystem::remove_all(dir);
  const auto file = dir / "plan";
  io::write_text_file(file, "old\n");
  io::write_text_file(file, "new\n");
  EXPECT_EQ(test::read_text(file), "new\n");
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 1u);  // no partial copy left beside it
  if (std::filesystem::exists("/dev/full")) {
    EXPECT_THROW(io::write_text_file("/dev/full", std::string(1 << 16, 'x'), "plan file"), io::WriteError);
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cluttertamp::search

namespace cluttertamp::search {
namespace {

// Lights to switch off, each only from beside it: the goal and a precondition are
// negative, which the relaxation counts through complement facts.
TEST(PddlHeuristics, NegativeGoalsAndPreconditionsCount) {
  const pddl::Domain domain = pddl::parse_domain(R"((define (domain lights)
    (:requirements :strips :negative-preconditions)
    (:predicates (on ?l) (at ?p) (beside ?l ?p) (link ?x ?y) (blocked ?p))
    (:action go :parameters (?x ?y) :precondition (and (at ?x) (link ?x ?y) (not (blocked ?y)))
             :effect (and (at ?y) (not (at ?x))))
    (:action off :parameters (?l ?p) :precondition (and (on ?l) (at ?p) (beside ?l ?p)) :effect (not (on ?l)))))",
                                                 "lights-domain.pddl");
  const pddl::Problem problem = pddl::parse_problem(R"((define (problem three) (:domain lights)
    (:objects l1 l2 l3 a b c d)
    (:init (at a) (on l1) (on l2) (on l3) (beside l1 b) (beside l2 c) (beside l3 d)
           (link a b) (link b c) (link c d) (link b a) (link c b) (link d c))
    (:goal (and (not (on l1)) (not (on l2)) (not (on l3))))))",
                                                    "lights.pddl", domain);
  const Task task = ground(domain, problem);
  // Three switches and three steps at least: a -> b -> c -> d.
  EXPECT_DOUBLE_EQ(initial_heuristic(task, "hmax"), 4.0);
  EXPECT_DOUBLE_EQ(initial_heuristic(task, "lmcut"), 6.0);
  EXPECT_DOUBLE_EQ(initial_heuristic(task, "hff"), 6.0);
  for (const char* algorithm : {"lama-first", "astar-lmcut"}) {
    SearchOptions options;
    options.algorithm = algorithm;
    const SearchResult r = plan(task, options);
    ASSERT_TRUE(r.solved) << algorithm;
    EXPECT_DOUBLE_EQ(r.cost, 6.0) << algorithm;
    EXPECT_LE(r.statistics.expanded, 10u) << algorithm;  // guided, not blind
  }
}

}  // namespace
}  // namespace cluttertamp::search
