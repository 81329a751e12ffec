// Fuzz target for the PDDL reader: any input must end in a parsed domain and problem
// (then grounded and searched within small limits) or in an InputError; never in a
// crash, a hang or another exception. The input is a domain, optionally followed by a
// line ";;;;" and a problem.
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <string>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/pddl/parser.hpp"
#include "cluttertamp/pddl/validator.hpp"
#include "cluttertamp/search/grounding.hpp"
#include "cluttertamp/search/planner.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::size_t split = input.find("\n;;;;\n");
  const std::string domain_text = input.substr(0, split);
  const std::string problem_text = split == std::string::npos ? std::string() : input.substr(split + 6);
  try {
    const cluttertamp::pddl::Domain domain = cluttertamp::pddl::parse_domain(domain_text, "fuzz-domain.pddl");
    if (problem_text.empty()) return 0;
    const cluttertamp::pddl::Problem problem = cluttertamp::pddl::parse_problem(problem_text, "fuzz-problem.pddl", domain);
    if (problem.objects.size() + domain.constants.size() > 12) return 0;  // keep grounding small
    const cluttertamp::search::Task task = cluttertamp::search::ground(domain, problem);
    cluttertamp::search::SearchOptions options;
    options.max_expansions = 200;
    options.time_limit = 1.0;
    const auto result = cluttertamp::search::plan(task, options);
    if (result.solved) {
      std::string plan;
      for (auto op : result.plan) plan += task.operators[op].name + "\n";
      const auto steps = cluttertamp::pddl::parse_plan(plan, "fuzz.plan", domain, problem);
      if (!cluttertamp::pddl::validate_plan(domain, problem, steps).valid) {
        std::fprintf(stderr, "a plan the search returned does not validate\n");
        std::abort();
      }
    }
  } catch (const cluttertamp::InputError&) {
    // Bad input, reported: the expected outcome for most inputs.
  }
  return 0;
}
