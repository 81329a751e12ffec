// Fuzz target: a problem file (YAML) with the files it names (scenes, robots, PDDL,
// streams) among the project's data. Read, or refused as bad input.
#include "cluttertamp/io/problem_io.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fz = cluttertamp::fuzz;
  const auto file = fz::input_file(data, size, "problem.yaml");
  fz::refusing_bad_input([&] { cluttertamp::io::load_problem(file); });
  return 0;
}
