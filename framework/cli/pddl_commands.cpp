// `cluttertamp pddl` and `cluttertamp validate-plan`.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "cli/commands.hpp"
#include "cluttertamp/io/text_file.hpp"
#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/pddl/validator.hpp"
#include "cluttertamp/run/runner.hpp"
#include "cluttertamp/search/grounding.hpp"
#include "cluttertamp/search/planner.hpp"
#include "cluttertamp/core/free_beside.hpp"

namespace cluttertamp::cli {

namespace {
std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", v);
  return text;
}

// Writes one message to standard error in one piece. std::cerr is unbuffered: a line
// streamed part by part costs a system call per part, and a verbose search's progress
// lines made hundreds of them inside the search's measured time.
template <class... Parts>
void say(const Parts&... parts) {
  std::ostringstream line;
  (line << ... << parts);
  std::cerr << line.str();
}
}  // namespace

int pddl(const PddlArgs& args) {
  const auto start = std::chrono::steady_clock::now();
  const pddl::Domain domain = pddl::load_domain(args.domain);
  const pddl::Problem problem = pddl::load_problem(args.problem, domain);
  if (!args.plan_file.empty()) io::check_writable(args.plan_file, "plan file (--plan)");
  if (args.verbosity != Verbosity::quiet) {
    for (const Diagnostic& w : domain.warnings) say(w.str(), "\n");
  }
  // The time limit counts from the start: parsing is part of it.
  const double parsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (args.verbosity == Verbosity::verbose) {
    say("parsing: ", problem.objects.size(), " objects, ", problem.init.size(), " initial facts in ", number(parsed),
        " s\n");
  }
  search::GroundingStats grounding;
  search::Task task;
  try {
    if (parsed >= args.time_limit) throw search::TimeLimit("time limit (parsing)");
    task = search::ground(domain, problem, &grounding, args.time_limit - parsed);
  } catch (const search::TooLarge& e) {
    say("no plan: grounding: ", e.what(), "\n");
    return run::ExitCode::no_plan;
  } catch (const search::TimeLimit& e) {
    if (args.verbosity == Verbosity::verbose) {
      say("stopped after ", number(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()),
          " s\n");
    }
    say("no plan: ", e.what(), "\n");
    return run::ExitCode::no_plan;
  }
  if (args.verbosity != Verbosity::quiet) {
    say("grounding: ", grounding.reachable_facts, " reachable atoms (", grounding.static_facts, " static), ",
        task.fact_count(), " state facts, ", grounding.operators, " operators, ", grounding.axioms, " axioms in ",
        number(grounding.seconds), " s\n");
  }
  search::SearchOptions options;
  options.algorithm = args.search;
  options.landmarks = args.landmarks;
  // What is left from the start (the grounder's own teardown counts too).
  options.time_limit =
      std::max(0.0, args.time_limit - std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  options.max_expansions = args.max_expansions;
  options.weight = args.weight;
  options.anytime = args.anytime;
  const auto plan_text = [&](const search::SearchResult& r) {
    std::string text;
    for (search::OperatorId op : r.plan) text += task.operators[op].name + "\n";
    return text + "; cost = " + number(r.cost) + (task.unit_cost ? " (unit cost)" : " (general cost)") + "\n";
  };
  if (args.anytime) {
    // Each better plan is said as found and replaces the plan file: a run stopped from
    // outside keeps its best plan.
    options.on_plan = [&](const search::SearchResult& r) {
      if (args.verbosity != Verbosity::quiet) {
        say("plan ", r.plans_found, ": cost ", number(r.cost), ", ", r.plan.size(), " steps after ",
            r.statistics.expanded, " expansions, ",
            number(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()), " s\n");
      }
      if (!args.plan_file.empty()) io::write_text_file(args.plan_file, plan_text(r), "plan file");
    };
  }
  if (args.verbosity == Verbosity::verbose) {
    options.on_progress = [](const search::SearchProgress& p) {
      say("search: ", (p.evaluated == 1 ? "initial " : "new best "), p.heuristic, " ", number(p.value), " after ",
          p.expanded, " expanded, ", p.evaluated, " evaluated\n");
    };
  }
  const search::SearchResult result = search::plan(task, options);
  if (args.verbosity != Verbosity::quiet) {
    say("search: ", args.search, (args.anytime ? " then anytime" : ""), ", ", result.statistics.expanded,
        " expanded, ", result.statistics.generated, " generated, ", result.statistics.evaluated, " evaluated in ",
        number(result.statistics.seconds), " s\n");
    if (result.statistics.never_applicable > 0) {
      say("search: left out ", result.statistics.never_applicable,
          " operators whose preconditions are mutex (never applicable)\n");
    }
    if (result.statistics.irrelevant > 0) {
      say("search: left out ", result.statistics.irrelevant, " operators that change nothing the goal depends on\n");
    }
    if (const auto& s = result.statistics; s.landmarks > 0) {
      say("landmarks: ", args.landmarks, ", ", s.landmarks, " (", s.disjunctive_landmarks, " disjunctive), ",
          s.landmark_orders, " orders, ", s.variables, " finite-domain variables of several facts\n");
    }
  }
  if (!result.solved) {
    say("no plan: ", result.reason, "\n");
    if (result.reason == "time limit") free_beside(std::move(task));  // the limit left no time to free it
    return run::ExitCode::no_plan;
  }
  const std::string text = plan_text(result);
  std::cout << text;
  if (!args.plan_file.empty()) io::write_text_file(args.plan_file, text, "plan file");
  if (args.verbosity != Verbosity::quiet) {
    say("plan: ", result.plan.size(), " steps, cost ", number(result.cost), "\n");
    if (args.anytime) say("anytime: ", result.plans_found, " plans, stopped: ", result.anytime_end, "\n");
  }
  return run::ExitCode::solved;
}

int validate_plan(const ValidatePlanArgs& args) {
  const pddl::Domain domain = pddl::load_domain(args.domain);
  const pddl::Problem problem = pddl::load_problem(args.problem, domain);
  const auto plan = pddl::load_plan(args.plan, domain, problem);
  const pddl::PlanValidation v = pddl::validate_plan(domain, problem, plan);
  if (!v.valid) {
    std::cout << "plan invalid: " << v.reason << "\n";
    return run::ExitCode::no_plan;
  }
  if (args.verbosity != Verbosity::quiet) {
    std::cout << "plan valid: " << plan.size() << " steps, cost " << number(v.cost) << "\n";
  }
  return run::ExitCode::solved;
}

}  // namespace cluttertamp::cli
