// Stream files (PDDLStream syntax and validation) and the two stream searches on a
// pure-symbolic domain with a toy sampler: blocks on a line.

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/io/scene_io.hpp"
#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/pddl/validator.hpp"
#include "cluttertamp/stream/scene_facts.hpp"
#include "cluttertamp/stream/stream_file.hpp"
#include "cluttertamp/stream/stream_search.hpp"
#include "stream/fact_base.hpp"
#include "test_support.hpp"

namespace cluttertamp {
namespace {

using stream::StreamDecl;

std::filesystem::path blocks_line(const std::string& file) {
  return std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "domains/pddl/blocks-line" / file;
}

// ---- stream files --------------------------------------------------------------------

const char* kDomain = R"((define (domain d)
  (:requirements :strips :equality)
  (:predicates (Conf ?q) (Pose ?p) (Kin ?q ?p) (Motion ?q1 ?t ?q2) (AtConf ?q) (Safe ?t) (Collide ?t ?p))
  (:functions (Distance ?q1 ?q2))
  (:action move :parameters (?q1 ?t ?q2)
    :precondition (and (Motion ?q1 ?t ?q2) (AtConf ?q1) (not (Collide ?t ?q2)))
    :effect (and (AtConf ?q2) (not (AtConf ?q1)) (increase (total-cost) (Distance ?q1 ?q2)))))
)";

pddl::Domain domain() { return pddl::parse_domain(kDomain, "d.pddl"); }

TEST(StreamFile, ReadsEveryPddlStreamForm) {
  const pddl::Domain d = domain();
  const stream::StreamFile f = stream::parse_stream_file(R"(; comments as in PDDLStream files
(define (stream s)
  (:rule :inputs (?q ?p) :domain (Kin ?q ?p) :certified (and (Conf ?q) (Pose ?p)))
  (:function (Distance ?q1 ?q2) (and (Conf ?q1) (Conf ?q2)))
  (:predicate (Collide ?t ?p) (Pose ?p))
  (:stream sample-pose :outputs (?p) :certified (Pose ?p))
  (:stream inverse-kinematics
    :inputs (?p) :domain (Pose ?p) :outputs (?q)
    :certified (and (Conf ?q) (Kin ?q ?p)))
  (:stream plan-motion
    :inputs (?q1 ?q2) :domain (and (Conf ?q1) (Conf ?q2))
    :fluents (AtConf)
    :outputs (?t) :certified (Motion ?q1 ?t ?q2))
  (:stream test-safe :inputs (?t ?q1 ?q2) :domain (Motion ?q1 ?t ?q2) :certified (Safe ?t)))
)",
                                                         "s.pddl", nullptr);
  EXPECT_EQ(f.name, "s");
  ASSERT_EQ(f.streams.size(), 7u);
  EXPECT_EQ(f.streams[0].kind, StreamDecl::Kind::rule);
  EXPECT_EQ(f.streams[1].kind, StreamDecl::Kind::function);
  EXPECT_EQ(f.streams[1].inputs.size(), 2u);
  EXPECT_TRUE(f.streams[2].is_test());
  EXPECT_EQ(f.streams[2].certified.at(0).predicate, "collide");
  EXPECT_TRUE(f.streams[3].inputs.empty());
  EXPECT_FALSE(f.streams[4].is_test());
  EXPECT_EQ(f.find("plan-motion")->fluents, std::vector<std::string>{"atconf"});
  EXPECT_TRUE(f.find("test-safe")->is_test());
  EXPECT_EQ(f.find("inverse-kinematics")->where.line, 7u);
  (void)d;
}

TEST(StreamFile, ValidationErrorsAreLocated) {
  const pddl::Domain d = domain();
  const Diagnostics errors = test::expect_input_error([&] {
    stream::parse_stream_file(R"((define (stream s)
  (:stream a :inputs (?p) :domain (Kin ?q ?p) :outputs (?q) :certified (Conf ?q))
  (:stream b :inputs (?p) :domain (Pose ?p) :outputs (?q) :certified (Kin ?x ?p))
  (:stream c :inputs (?p) :domain (Pose ?p) :outputs (?p) :certified (Pose ?p))
  (:stream d :inputs (?p) :domain (Pose ?p) :output (?q) :certified (Pose ?p))
  (:stream e :inputs (?q) :domain (AtConf ?q) :certified (Conf ?q))
  (:stream f :inputs (?p) :domain (Pose ?p) :outputs (?q) :certified (Unknown ?q))
  (:stream g :inputs (?p) :domain (Pose ?p) :outputs (?q) :certified (Conf ?q ?p))
  (:optimizer o)
  (:stream a :inputs () :outputs (?p) :certified (Pose ?p))
  (:stream h :inputs (?p ?p) :domain (Pose ?p) :certified (Pose ?p))
  (:stream i :inputs (?p) :domain (Pose ?p) :outputs (?q)))
)",
                              "s.pddl", &d);
  });
  EXPECT_TRUE(test::has_error(errors, 2, 40, "'?q' in :domain of stream 'a' is not an input"));
  EXPECT_TRUE(test::has_error(errors, 3, 75, "'?x' in :certified of stream 'b' is neither an input nor an output"));
  EXPECT_TRUE(test::has_error(errors, 4, 55, "'?p' is both an input and an output of stream 'c'"));
  EXPECT_TRUE(test::has_error(errors, 5, 45, "unknown keyword ':output'"));
  EXPECT_TRUE(test::has_error(errors, 6, 35, "'atconf' in :domain of stream 'e' is changed by actions"));
  EXPECT_TRUE(test::has_error(errors, 8, 70, "'conf' takes 1 argument(s), not 2"));
  EXPECT_TRUE(test::has_error(errors, 9, 3, "optimizers"));
  EXPECT_TRUE(test::has_error(errors, 10, 3, "'a' is declared twice (first at line 2)"));
  EXPECT_TRUE(test::has_error(errors, 11, 26, "'?p' appears twice in :inputs of stream 'h'"));
  EXPECT_TRUE(test::has_error(errors, 12, 3, "stream 'i' has no :certified facts"));
  for (const Diagnostic& item : errors.items()) EXPECT_EQ(item.location.file, "s.pddl");
  // A predicate the domain does not declare is the streams' own, as in PDDLStream.
  for (const Diagnostic& item : errors.items()) EXPECT_EQ(item.location.line == 7, false) << item.message;
}

TEST(StreamFile, SyntaxErrorsAndTheWrongDefineAreLocated) {
  EXPECT_TRUE(test::has_error(test::expect_input_error([] { stream::parse_stream_file("(define (stream s)\n  (:stream a", "x.pddl"); }),
                              2, 3, "never closed"));
  EXPECT_TRUE(test::has_error(test::expect_input_error([] { stream::parse_stream_file("(define (domain s))", "x.pddl"); }),
                              1, 1, "expected (define (stream NAME) ...)"));
  EXPECT_TRUE(test::has_error(test::expect_input_error([] { stream::load_stream_file("/no/such/stream.pddl"); }), 0, 0,
                              "no such file"));
  EXPECT_TRUE(test::has_error(
      test::expect_input_error([] {
        stream::parse_stream_file("(define (stream s)\n  (:stream PlaceK}in :inputs () :outputs (?p) :certified (Pose ?p)))",
                                  "x.pddl");
      }),
      2, 12, "stream name 'placek}in' is not a name"));
}

TEST(StreamFile, FunctionsAndFluentsAreCheckedAgainstTheDomain) {
  const pddl::Domain d = domain();
  const Diagnostics errors = test::expect_input_error([&] {
    stream::parse_stream_file(R"((define (stream s)
  (:function (Length ?q) (Conf ?q))
  (:stream m :inputs (?q1 ?q2) :domain (and (Conf ?q1) (Conf ?q2)) :fluents (Conf Nothing) :outputs (?t)
     :certified (Motion ?q1 ?t ?q2)))
)",
                              "s.pddl", &d);
  });
  EXPECT_TRUE(test::has_error(errors, 3, 78, "'conf' in :fluents of stream 'm' is never changed by an action"));
  EXPECT_TRUE(test::has_error(errors, 3, 83, "'nothing' in :fluents of stream 'm' is not a predicate"));
  EXPECT_EQ(errors.size(), 2u) << errors.str();
  // A :function the domain does not declare is the stream file's own, as PDDLStream
  // reads it: accepted with a located warning (the domain never uses its values).
  const stream::StreamFile own = stream::parse_stream_file("(define (stream s)\n  (:function (Length ?q) (Conf ?q)))", "s.pddl", &d);
  ASSERT_EQ(own.warnings.size(), 1u);
  EXPECT_EQ(own.warnings[0].location.line, 2u);
  EXPECT_EQ(own.warnings[0].location.column, 14u);
  EXPECT_NE(own.warnings[0].message.find("function 'length' is not declared in (:functions ...)"), std::string::npos);
}

TEST(StreamFile, TheBundledStreamFilesLoadAgainstTheirDomains) {
  const pddl::Domain d = pddl::load_domain(blocks_line("domain.pddl"));
  const stream::StreamFile f = stream::load_stream_file(blocks_line("stream.pddl"), &d);
  EXPECT_EQ(f.streams.size(), 2u);
}

// ---- searches on blocks-line -----------------------------------------------------------

constexpr double kWidth = 1.0;  // blocks overlap when their centres are closer

// Positions in a region ([lo, hi] of the centre), and the overlap test.
class LineStreams final : public plugin::StreamSampler {
 public:
  std::unique_ptr<plugin::StreamGenerator> instantiate(plugin::PlanningContext& context, std::string_view stream,
                                                       const std::vector<plugin::StreamValue>& in,
                                                       const std::vector<plugin::StreamFact>& fluents) override {
    if (stream == "sample-pose") {
      const std::string region = std::get<std::string>(in.at(1));
      const auto [lo, hi] = region == "goal" ? std::pair(10.0, 11.5) : std::pair(-5.0, 9.5);
      const std::uint64_t seed = context.seed * 1000003 + std::hash<std::string>{}(std::get<std::string>(in.at(0)) + region);
      return std::make_unique<Sampler>(lo, hi, seed);
    }
    if (stream == "test-free") return free_in_state(in, fluents);
    const bool same = std::get<std::string>(in.at(0)) == std::get<std::string>(in.at(2));
    return std::make_unique<Test>(same || std::abs(std::get<double>(in.at(1)) - std::get<double>(in.at(3))) >= kWidth);
  }

  /// A call of test-free: the block, its position and the blocks standing (by AtPose).
  struct FreeCall {
    std::string block;
    double position = 0;
    std::map<std::string, double> standing;
  };
  std::vector<FreeCall> free_calls;

 private:
  // test-free (:fluents (AtPose)): ?b at ?p overlaps no other block standing in the state.
  std::unique_ptr<plugin::StreamGenerator> free_in_state(const std::vector<plugin::StreamValue>& in,
                                                         const std::vector<plugin::StreamFact>& fluents) {
    FreeCall call{std::get<std::string>(in.at(0)), std::get<double>(in.at(1)), {}};
    for (const plugin::StreamFact& f : fluents) {
      EXPECT_EQ(f.predicate, "atpose");
      call.standing[std::get<std::string>(f.args.at(0))] = std::get<double>(f.args.at(1));
    }
    bool free = true;
    for (const auto& [other, x] : call.standing) free &= other == call.block || std::abs(x - call.position) >= kWidth;
    free_calls.push_back(std::move(call));
    return std::make_unique<Test>(free);
  }

  struct Sampler final : plugin::StreamGenerator {
    Sampler(double lo, double hi, std::uint64_t seed) : rng(seed), position(lo, hi) {}
    plugin::StreamBatch next(plugin::PlanningContext&) override { return {{{position(rng)}}, false, std::nullopt}; }
    std::mt19937_64 rng;
    std::uniform_real_distribution<double> position;
  };
  struct Test final : plugin::StreamGenerator {
    explicit Test(bool free) : free(free) {}
    plugin::StreamBatch next(plugin::PlanningContext&) override {
      if (free) return {{{}}, true, std::nullopt};
      return {{}, true, Failure{"test-cfree", "the blocks overlap", {}}};
    }
    bool free;
  };
};

class BlocksLine : public ::testing::Test {
 protected:
  BlocksLine()
      : domain_(pddl::load_domain(blocks_line("domain.pddl"))),
        pddl_problem_(pddl::load_problem(blocks_line("problem.pddl"), domain_)),
        streams_(stream::load_stream_file(blocks_line("stream.pddl"), &domain_)) {
    problem_.domain = &domain_;
    problem_.problem = &pddl_problem_;
    problem_.streams = &streams_;
    const std::map<std::string, double> positions{{"pa", 0}, {"pb", 10.6}, {"pc", 2},
                                                  {"pd", 4}, {"pe", 6},     {"pf", 8}};
    for (const auto& [name, x] : positions) problem_.values[name] = x;
    problem_.bindings = {{"sample-pose", &sampler_}, {"test-cfree", &sampler_}};
  }

  stream::StreamSolution solve(stream::Algorithm algorithm, std::uint64_t seed, double seconds = 30) {
    plugin::PlanningContext context{core_problem_, plugin::Deadline::after(seconds), seed, counters_, samplers_};
    stream::StreamSearchOptions options = options_;
    options.algorithm = algorithm;
    if (std::getenv("STREAM_TRACE")) options.trace = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
    return stream::solve(problem_, context, options);
  }

  // The plan replayed on the positions: every block apart from the others after each
  // place, and a in the goal region at the end.
  void expect_geometrically_valid(const stream::StreamSolution& s) {
    std::map<std::string, double> at{{"a", 0}, {"b", 10.6}, {"c", 2}, {"d", 4}, {"e", 6}, {"f", 8}};
    std::string held;
    for (const stream::StreamPlanStep& step : s.plan) {
      if (step.action == "pick") {
        held = step.arguments.at(0);
        at.erase(held);
        continue;
      }
      const std::string& p = step.arguments.at(1);
      const double x = std::get<double>(s.values.count(p) ? s.values.at(p) : problem_.values.at(p));
      for (const auto& [other, y] : at) EXPECT_GE(std::abs(x - y), kWidth) << held << " placed onto " << other;
      at[held] = x;
    }
    ASSERT_TRUE(at.count("a"));
    EXPECT_GE(at["a"], 10.0);
    EXPECT_LE(at["a"], 11.5);
  }

  void expect_valid_pddl(const stream::StreamSolution& s) {
    const pddl::Problem with = stream::with_certified_facts(domain_, pddl_problem_, s);
    const pddl::PlanValidation v = pddl::validate_plan(domain_, with, stream::pddl_plan(s));
    EXPECT_TRUE(v.valid) << v.reason << " at step " << v.step;
  }

  pddl::Domain domain_;
  pddl::Problem pddl_problem_;
  stream::StreamFile streams_;
  stream::StreamProblem problem_;
  LineStreams sampler_;
  stream::StreamSearchOptions options_;
  Problem core_problem_;
  std::map<std::string, std::uint64_t> counters_;
  plugin::Samplers samplers_;
};

TEST_F(BlocksLine, BothAlgorithmsMoveTheBlockerOutOfTheGoalFirstWithRealValues) {
  for (stream::Algorithm algorithm : {stream::Algorithm::adaptive, stream::Algorithm::incremental}) {
    SCOPED_TRACE(stream::algorithm_name(algorithm));
    const stream::StreamSolution s = solve(algorithm, 1);
    ASSERT_TRUE(s.solved) << s.reason;
    std::string plan;
    for (const stream::StreamPlanStep& step : s.plan) plan += step.action + " " + step.arguments[0] + " " + step.arguments[1] + "; ";
    // The incremental search takes the first plan its values allow, detours and all.
    if (algorithm == stream::Algorithm::adaptive) EXPECT_EQ(s.plan.size(), 4u) << plan;
    EXPECT_EQ(s.plan[0].action, "pick");
    EXPECT_EQ(s.plan[0].arguments[0], "b");
    for (const stream::StreamPlanStep& step : s.plan) {
      for (const std::string& arg : step.arguments) EXPECT_NE(arg[0], '@') << "an optimistic object in the plan";
    }
    expect_geometrically_valid(s);
    expect_valid_pddl(s);
  }
}

TEST_F(BlocksLine, AdaptiveEvaluatesFewerStreamsThanIncremental) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const stream::StreamSolution adaptive = solve(stream::Algorithm::adaptive, seed);
    const stream::StreamSolution incremental = solve(stream::Algorithm::incremental, seed);
    ASSERT_TRUE(adaptive.solved && incremental.solved);
    EXPECT_LT(adaptive.statistics.stream_calls * 2, incremental.statistics.stream_calls)
        << "seed " << seed << ": adaptive " << adaptive.statistics.stream_calls << ", incremental "
        << incremental.statistics.stream_calls;
  }
}

TEST_F(BlocksLine, SameSeedSamePlan) {
  const stream::StreamSolution one = solve(stream::Algorithm::adaptive, 7);
  const stream::StreamSolution two = solve(stream::Algorithm::adaptive, 7);
  ASSERT_TRUE(one.solved && two.solved);
  ASSERT_EQ(one.plan.size(), two.plan.size());
  for (std::size_t i = 0; i < one.plan.size(); ++i) EXPECT_EQ(one.plan[i].arguments, two.plan[i].arguments);
  EXPECT_EQ(one.statistics.stream_calls, two.statistics.stream_calls);
}

// Optimistic bookkeeping: an instance evaluated is disabled until the level rises,
// and its real outputs stay usable: the pose sampler of b is called again only when
// its earlier positions collided, and every value in the plan is real.
TEST_F(BlocksLine, RealOutputsAreReusedAndFailedTestsAreRecorded) {
  const stream::StreamSolution s = solve(stream::Algorithm::adaptive, 2);
  ASSERT_TRUE(s.solved) << s.reason;
  EXPECT_GE(s.statistics.calls_per_stream.at("sample-pose"), 2u);
  EXPECT_GE(s.statistics.skeletons, 1u);
  EXPECT_GE(s.statistics.level, 2u);
  for (const auto& [name, value] : s.values) {
    EXPECT_EQ(name[0], '#');
    EXPECT_TRUE(std::holds_alternative<double>(value));
  }
}

TEST_F(BlocksLine, AnImpossibleGoalEndsWithAReasonNotAHang) {
  // The goal region holds no position once the sampler only draws on the table.
  pddl::Problem impossible = pddl::parse_problem(R"((define (problem p) (:domain blocks-line)
  (:objects a pa goal) (:init (Region goal) (HandEmpty) (Block a) (Pose a pa) (AtPose a pa))
  (:goal (and (In a goal) (not (Block a))))))",
                                                 "p.pddl", domain_);
  problem_.problem = &impossible;
  for (stream::Algorithm algorithm : {stream::Algorithm::adaptive, stream::Algorithm::incremental}) {
    const auto start = std::chrono::steady_clock::now();
    const stream::StreamSolution s = solve(algorithm, 1, 2.0);
    EXPECT_FALSE(s.solved);
    // The adaptive search proves it: no plan even with optimistic values. The
    // incremental one samples on until the time limit.
    EXPECT_EQ(s.reason, algorithm == stream::Algorithm::adaptive ? "no plan exists: not even with optimistic stream outputs"
                                                                 : "time limit reached");
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 2.5);
  }
}

TEST_F(BlocksLine, StreamOptionsAreCheckedAgainstTheStreamFile) {
  options_.streams["no-such-stream"] = {};
  EXPECT_TRUE(test::has_error(test::expect_input_error([&] { solve(stream::Algorithm::adaptive, 1); }), 2, 1,
                              "stream options name 'no-such-stream', which this stream file does not declare"));
  options_.streams.clear();
  options_.streams["test-cfree"].optimistic_value = 3;
  EXPECT_TRUE(test::has_error(test::expect_input_error([&] { solve(stream::Algorithm::adaptive, 1); }), 8, 3,
                              "'test-cfree' is not a function: only a function has an optimistic value"));
  // An eager test is evaluated on every pair of real poses at once: more calls, the same kind of plan.
  options_.streams.clear();
  const stream::StreamSolution lazy = solve(stream::Algorithm::adaptive, 1);
  options_.streams["test-cfree"].eager = true;
  const stream::StreamSolution eager = solve(stream::Algorithm::adaptive, 1);
  ASSERT_TRUE(lazy.solved && eager.solved) << lazy.reason << " / " << eager.reason;
  EXPECT_GT(eager.statistics.calls_per_stream.at("test-cfree"), lazy.statistics.calls_per_stream.at("test-cfree"));
  expect_geometrically_valid(eager);
  expect_valid_pddl(eager);
}

TEST_F(BlocksLine, AStreamWithoutCodeIsBadInput) {
  problem_.bindings.erase("test-cfree");
  const Diagnostics errors = test::expect_input_error([&] { solve(stream::Algorithm::adaptive, 1); });
  EXPECT_TRUE(test::has_error(errors, 8, 3, "'test-cfree' is bound to no stream_sampler"));
}

// ---- streams with :fluents ----------------------------------------------------------

using test::read_text;
using test::replaced;

// blocks-line where a place also needs (Free ?b ?p): a test with :fluents (AtPose) that
// reads the blocks standing in the state the place happens in. Free of a in the goal is
// false in the initial state (b stands there) and true once b has gone.
class BlocksLineFluents : public BlocksLine {
 protected:
  BlocksLineFluents() {
    std::string domain = read_text(blocks_line("domain.pddl"));
    domain = replaced(domain, "(Unsafe ?b ?p) (In ?b ?r))", "(Unsafe ?b ?p) (In ?b ?r) (Free ?b ?p))");
    domain = replaced(domain, "(not (Unsafe ?b ?p)))", "(not (Unsafe ?b ?p)) (Free ?b ?p))");
    domain_ = pddl::parse_domain(domain, "fluent-domain.pddl");
    pddl_problem_ = pddl::load_problem(blocks_line("problem.pddl"), domain_);
    std::string streams = read_text(blocks_line("stream.pddl"));
    streams = replaced(streams, "(CFree ?b1 ?p1 ?b2 ?p2)))", R"((CFree ?b1 ?p1 ?b2 ?p2))
  (:stream test-free
    :inputs (?b ?p)
    :domain (Pose ?b ?p)
    :fluents (AtPose)
    :certified (Free ?b ?p))))");
    streams_ = stream::parse_stream_file(streams, "fluent-stream.pddl", &domain_);
    problem_.bindings["test-free"] = &sampler_;
  }
};

// A pruner's obstacles stay where they stand: no Object, Pose or AtPose fact, so no
// action moves them and no test is asked about them; movable objects and the target
// keep theirs, and every object of the scene is still named.
TEST(SceneFacts, ObstaclesHaveNoPoseFacts) {
  const Scene scene = io::load_scene(std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "problems/stacked/scene8.yaml");
  std::vector<bool> movable(scene.objects.size(), false);
  movable[*scene.find_object("lid")] = movable[*scene.find_object("front_left")] = true;
  const stream::SceneProblem sp = stream::scene_problem(scene, movable, "clutter-streams");
  auto has = [&](const std::string& predicate, const std::string& object) {
    return std::any_of(sp.problem.init.begin(), sp.problem.init.end(), [&](const pddl::Atom& a) {
      return a.predicate == predicate && !a.args.empty() && a.args.front().name == object;
    });
  };
  for (const char* name : {"lid", "front_left", "target"}) {
    EXPECT_TRUE(has("object", name) && has("pose", name) && has("atpose", name)) << name;
  }
  for (const char* name : {"front_right", "side_1", "side_4"}) {
    EXPECT_FALSE(has("object", name) || has("pose", name) || has("atpose", name)) << name;
    EXPECT_EQ(sp.objects.count(name), 1u) << name;
  }
  EXPECT_TRUE(has("on", "lid"));  // what rests on an obstacle still says so
  const stream::SceneProblem all = stream::scene_problem(scene, {}, "clutter-streams");
  EXPECT_TRUE(std::all_of(scene.objects.begin(), scene.objects.end(),
                          [&](const SceneObject& o) { return std::any_of(all.problem.init.begin(), all.problem.init.end(),
                                                                         [&](const pddl::Atom& a) { return a.predicate == "atpose" && a.args.front().name == o.id; }); }));
}

TEST(FactBase, AFactCertifiedInAStateHoldsInThatStateOnlyAndStaysOutOfTheSearch) {
  const pddl::Domain d = domain();
  const stream::StreamFile f = stream::parse_stream_file(R"((define (stream s)
  (:stream plan-motion :inputs (?q1 ?q2) :domain (and (Conf ?q1) (Conf ?q2)) :fluents (AtConf)
    :outputs (?t) :certified (Motion ?q1 ?t ?q2))))",
                                                         "s.pddl", &d);
  stream::detail::FactBase base(d, f);
  const int q1 = base.add_object({"q1"}), q2 = base.add_object({"q2"}), t = base.add_object({"t"});
  const int at_conf = base.predicate_id("atconf"), motion = base.predicate_id("motion"), conf = base.predicate_id("conf");
  const stream::detail::State at_q1{{at_conf, q1}, {conf, q1}}, at_q2{{at_conf, q2}, {conf, q1}};
  // The instance evaluated with the robot at q1; Conf is no fluent, so not part of its state.
  const std::vector<stream::detail::FactKey> state = base.fluent_state(at_q1, 0);
  const std::vector<stream::detail::FactKey> expected{{at_conf, q1}};
  ASSERT_EQ(state, expected);
  const int in_state = base.instance(0, {q1, q2}, state);
  EXPECT_NE(in_state, base.instance(0, {q1, q2})) << "the state-free instance stands for optimistic outputs only";
  EXPECT_EQ(in_state, base.instance(0, {q1, q2}, state));
  const stream::detail::FactKey fact{motion, q1, t, q2};
  base.add_state_fact(fact, {false, 1, in_state});
  EXPECT_TRUE(base.holds_in_state(fact, at_q1));
  EXPECT_FALSE(base.holds_in_state(fact, at_q2));
  EXPECT_FALSE(base.holds_in_state(fact, {}));
  EXPECT_EQ(base.fact(fact), nullptr) << "the symbolic search must not take it for a state-free fact";
  ASSERT_NE(base.real_fact(fact), nullptr);
  EXPECT_EQ(base.real_fact(fact)->certifier, in_state);
}

TEST_F(BlocksLineFluents, AFluentTestIsEvaluatedInTheStateBeforeTheStepThatNeedsIt) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    sampler_.free_calls.clear();
    const stream::StreamSolution s = solve(stream::Algorithm::adaptive, seed);
    ASSERT_TRUE(s.solved) << s.reason;
    expect_geometrically_valid(s);
    expect_valid_pddl(s);
    // Replay: each place was tested with exactly the blocks standing before it.
    std::map<std::string, double> at{{"a", 0}, {"b", 10.6}, {"c", 2}, {"d", 4}, {"e", 6}, {"f", 8}};
    for (const stream::StreamPlanStep& step : s.plan) {
      const std::string& block = step.arguments.at(0);
      if (step.action == "pick") {
        at.erase(block);
        continue;
      }
      const std::string& p = step.arguments.at(1);
      const double x = std::get<double>(s.values.count(p) ? s.values.at(p) : problem_.values.at(p));
      const bool tested = std::any_of(sampler_.free_calls.begin(), sampler_.free_calls.end(), [&](const auto& call) {
        return call.block == block && call.position == x && call.standing == at;
      });
      EXPECT_TRUE(tested) << "place " << block << " at " << x << " was not tested in the state before it";
      at[block] = x;
    }
  }
}

TEST_F(BlocksLineFluents, TheIncrementalSearchRefusesFluentStreamsAtTheirDeclaration) {
  const Diagnostics errors = test::expect_input_error([&] { solve(stream::Algorithm::incremental, 1); });
  EXPECT_TRUE(test::has_error(errors, 12, 3, "'test-free' reads :fluents, which only the adaptive search supports"));
}

TEST_F(BlocksLineFluents, AFluentTestOfANegatedFactIsRefused) {
  // move needs (not (Collide ?t ?q2)): certified in one state, Collide could not be
  // decided false in another.
  domain_ = domain();
  pddl_problem_ = pddl::parse_problem(
      "(define (problem p) (:domain d) (:objects q0 q1) (:init (Conf q0) (Conf q1) (AtConf q0)) (:goal (AtConf q1)))",
      "p.pddl", domain_);
  streams_ = stream::parse_stream_file(R"((define (stream s)
  (:stream plan-motion :inputs (?q1 ?q2) :domain (and (Conf ?q1) (Conf ?q2)) :outputs (?t)
    :certified (Motion ?q1 ?t ?q2))
  (:stream test-collide :inputs (?t ?q) :domain (and (Pose ?t) (Conf ?q)) :fluents (AtConf)
    :certified (Collide ?t ?q))))",
                                       "s.pddl", &domain_);
  const Diagnostics errors = test::expect_input_error([&] { solve(stream::Algorithm::adaptive, 1); });
  EXPECT_TRUE(test::has_error(errors, 4, 3, "test 'test-collide' reads :fluents and certifies 'collide', which the domain uses negated"));
}

}  // namespace
}  // namespace cluttertamp

namespace cluttertamp {
namespace {

// Two generators a plan needs side by side: gen-b (declared first, so planned first)
// yields one value, gen-a none. Deferring gen-b evaluates gen-a first, and the
// skeleton it rules out never pays for gen-b.
class PairStreams final : public plugin::StreamSampler {
 public:
  std::unique_ptr<plugin::StreamGenerator> instantiate(plugin::PlanningContext&, std::string_view stream,
                                                       const std::vector<plugin::StreamValue>&,
                                                       const std::vector<plugin::StreamFact>&) override {
    struct Generator final : plugin::StreamGenerator {
      bool yields;
      explicit Generator(bool y) : yields(y) {}
      plugin::StreamBatch next(plugin::PlanningContext&) override {
        plugin::StreamBatch batch;
        if (yields) batch.outputs.push_back({1.0});
        else batch.failure = Failure{"gen-a", "never", {}};
        batch.exhausted = true;  // one output at most: every search ends with a reason
        return batch;
      }
    };
    return std::make_unique<Generator>(stream == "gen-b");
  }
};

// A symbolic stream problem solved with a fresh context each time.
struct SymbolicStreams {
  SymbolicStreams(const char* domain_text, const char* problem_text, const char* streams_text)
      : domain(pddl::parse_domain(domain_text, "domain.pddl")),
        problem(pddl::parse_problem(problem_text, "problem.pddl", domain)),
        streams(stream::parse_stream_file(streams_text, "stream.pddl", &domain)) {}

  stream::StreamSolution solve(plugin::StreamSampler& sampler, const stream::StreamSearchOptions& options) const {
    stream::StreamProblem sp{&domain, &problem, &streams, {}, {}};
    for (const StreamDecl& d : streams.streams) sp.bindings[d.name] = &sampler;
    Problem core;
    std::map<std::string, std::uint64_t> counters;
    plugin::Samplers samplers;
    plugin::PlanningContext context{core, plugin::Deadline::after(30), 0, counters, samplers};
    return stream::solve(sp, context, options);
  }

  pddl::Domain domain;
  pddl::Problem problem;
  stream::StreamFile streams;
};

// The pair problem: (finish t) needs a value of gen-b and one of gen-a.
stream::StreamSolution solve_pair(const std::map<std::string, stream::StreamOptions>& stream_options) {
  static const SymbolicStreams pair(
      "(define (domain pair) (:requirements :strips)\n"
      "  (:predicates (Thing ?x) (A ?x ?a) (B ?x ?b) (Done ?x))\n"
      "  (:action finish :parameters (?x ?a ?b) :precondition (and (Thing ?x) (A ?x ?a) (B ?x ?b)) :effect (Done ?x)))",
      "(define (problem p) (:domain pair) (:objects t) (:init (Thing t)) (:goal (Done t)))",
      "(define (stream pair)\n"
      "  (:stream gen-b :inputs (?x) :domain (Thing ?x) :outputs (?b) :certified (B ?x ?b))\n"
      "  (:stream gen-a :inputs (?x) :domain (Thing ?x) :outputs (?a) :certified (A ?x ?a)))");
  PairStreams sampler;
  stream::StreamSearchOptions options;
  options.streams = stream_options;
  return pair.solve(sampler, options);
}

TEST(StreamOptions, ADeferredStreamWaitsForTheOthersOfItsSkeleton) {
  stream::StreamOptions deferring;
  deferring.defer = true;
  const stream::StreamSolution eager = solve_pair({}), deferred = solve_pair({{"gen-b", deferring}});
  EXPECT_FALSE(eager.solved);
  EXPECT_FALSE(deferred.solved);
  EXPECT_EQ(deferred.reason, "no plan exists: not even with optimistic stream outputs");
  EXPECT_GE(eager.statistics.calls_per_stream.count("gen-b"), 1u) << "gen-b, planned first, is called";
  EXPECT_EQ(deferred.statistics.calls_per_stream.count("gen-b"), 0u) << "deferred: gen-a fails first";
  EXPECT_EQ(deferred.statistics.calls_per_stream.at("gen-a"), 1u);
}

// p_success and overhead order a skeleton's streams: gen-a (likely to fail, cheap)
// before gen-b, which the stream plan would call first. p_success 0: gen-a is never
// assumed; eager, it is called once on the real input, and with its fact missing no
// optimistic plan exists, so gen-b is never called.
TEST(StreamOptions, PSuccessOrdersTheStreamsAndZeroMeansOnlyRealFacts) {
  stream::StreamOptions likely_to_fail;
  likely_to_fail.p_success = 0.5;
  stream::StreamOptions dear_and_likely_to_fail = likely_to_fail;
  dear_and_likely_to_fail.overhead = 100;
  const stream::StreamSolution by_default = solve_pair({}), ordered = solve_pair({{"gen-a", likely_to_fail}});
  EXPECT_GE(by_default.statistics.calls_per_stream.count("gen-b"), 1u) << "gen-b, planned first, is called";
  EXPECT_EQ(ordered.statistics.calls_per_stream.count("gen-b"), 0u) << "gen-a is tried first and fails";
  EXPECT_EQ(ordered.reason, "no plan exists: not even with optimistic stream outputs");
  // Both may fail: the cheaper failure first (1 / 0.5 = 2 against 100 / 0.5 = 200).
  const stream::StreamSolution both = solve_pair({{"gen-a", likely_to_fail}, {"gen-b", dear_and_likely_to_fail}});
  EXPECT_EQ(both.statistics.calls_per_stream.count("gen-b"), 0u);
  const stream::StreamSolution reversed = solve_pair({{"gen-a", dear_and_likely_to_fail}, {"gen-b", likely_to_fail}});
  EXPECT_GE(reversed.statistics.calls_per_stream.count("gen-b"), 1u);

  stream::StreamOptions never_assumed;
  never_assumed.p_success = 0;
  const Diagnostics errors = test::expect_input_error([&] { solve_pair({{"gen-a", never_assumed}}); });
  EXPECT_TRUE(test::has_error(errors, 3, 3, "'gen-a' has p_success 0 (never assumed optimistically) and is not eager"));
  never_assumed.eager = true;
  const stream::StreamSolution real_only = solve_pair({{"gen-a", never_assumed}});
  EXPECT_FALSE(real_only.solved);
  EXPECT_EQ(real_only.reason, "no plan exists: not even with optimistic stream outputs");
  EXPECT_EQ(real_only.statistics.calls_per_stream.at("gen-a"), 1u) << "called at once on the real input";
  EXPECT_EQ(real_only.statistics.calls_per_stream.count("gen-b"), 0u);
}

// A far road costs 10 in one step, a near one 1 + 1 in two steps through a waypoint a
// stream makes. The greedy search finds the far road first; with success_cost the
// searches go on below its cost, and both algorithms return the near road (cost 2).
// Below 2 nothing cheaper exists: the search says so and keeps the best plan.
class WaypointStreams final : public plugin::StreamSampler {
 public:
  std::unique_ptr<plugin::StreamGenerator> instantiate(plugin::PlanningContext&, std::string_view,
                                                       const std::vector<plugin::StreamValue>&,
                                                       const std::vector<plugin::StreamFact>&) override {
    struct Generator final : plugin::StreamGenerator {
      plugin::StreamBatch next(plugin::PlanningContext&) override { return {{{std::string("w")}}, true, std::nullopt}; }
    };
    return std::make_unique<Generator>();
  }
};

TEST(StreamOptions, SuccessCostKeepsSearchingForACheaperPlanWithinTheWorkBudget) {
  const SymbolicStreams roads(
      "(define (domain roads) (:requirements :strips :action-costs)\n"
      "  (:predicates (Start ?x) (At ?x) (Way ?x ?w) (Done))\n"
      "  (:action far :parameters (?x) :precondition (and (Start ?x) (At ?x))\n"
      "    :effect (and (Done) (increase (total-cost) 10)))\n"
      "  (:action to-waypoint :parameters (?x ?w) :precondition (and (Way ?x ?w) (At ?x))\n"
      "    :effect (and (At ?w) (not (At ?x)) (increase (total-cost) 1)))\n"
      "  (:action from-waypoint :parameters (?x ?w) :precondition (and (Way ?x ?w) (At ?w))\n"
      "    :effect (and (Done) (increase (total-cost) 1))))",
      "(define (problem p) (:domain roads) (:objects s) (:init (Start s) (At s)) (:goal (Done)) (:metric minimize (total-cost)))",
      "(define (stream roads) (:stream waypoint :inputs (?x) :domain (Start ?x) :outputs (?w) :certified (Way ?x ?w)))");
  WaypointStreams sampler;
  auto run = [&](stream::Algorithm algorithm, double success_cost, double improve_work = 1e6) {
    stream::StreamSearchOptions o;
    o.algorithm = algorithm;
    o.polish_search.clear();  // the first plan as the search finds it
    o.success_cost = success_cost;
    o.improve_work = improve_work;
    return roads.solve(sampler, o);
  };
  for (const stream::Algorithm algorithm : {stream::Algorithm::adaptive, stream::Algorithm::incremental}) {
    SCOPED_TRACE(stream::algorithm_name(algorithm));
    const stream::StreamSolution first = run(algorithm, std::numeric_limits<double>::infinity());
    ASSERT_TRUE(first.solved) << first.reason;
    EXPECT_EQ(first.plan.size(), 1u);
    EXPECT_FALSE(first.cost.has_value()) << "not costed: no success_cost, no polish";
    EXPECT_EQ(first.statistics.plans, 1u);
    const stream::StreamSolution cheap = run(algorithm, 2);
    ASSERT_TRUE(cheap.solved) << cheap.reason;
    ASSERT_EQ(cheap.plan.size(), 2u);
    EXPECT_EQ(cheap.plan[0].action, "to-waypoint");
    ASSERT_TRUE(cheap.cost.has_value());
    EXPECT_DOUBLE_EQ(*cheap.cost, 2.0);
    EXPECT_EQ(cheap.statistics.plans, 2u);
    const stream::StreamSolution unreachable = run(algorithm, 1);
    ASSERT_TRUE(unreachable.solved) << unreachable.reason;
    ASSERT_TRUE(unreachable.cost.has_value());
    EXPECT_DOUBLE_EQ(*unreachable.cost, 2.0);
    // No work allowed after the first plan: it stands, costed.
    const stream::StreamSolution no_budget = run(algorithm, 2, 0);
    ASSERT_TRUE(no_budget.solved) << no_budget.reason;
    ASSERT_TRUE(no_budget.cost.has_value());
    EXPECT_DOUBLE_EQ(*no_budget.cost, 10.0);
    EXPECT_EQ(no_budget.statistics.plans, 1u);
  }
}

}  // namespace
}  // namespace cluttertamp
