// Fuzz target: a result.json as `view` reads it (optionally followed by a line ";;;;"
// and a drawings.json), against the default problem. Drawn, or refused as bad input.
#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/viewer/plan_html.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fz = cluttertamp::fuzz;
  namespace ct = cluttertamp;
  static const ct::Problem problem = ct::io::load_problem(std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "problems/default.yaml");
  const std::string input = fz::text(data, size);
  const std::size_t split = input.find("\n;;;;\n");
  const std::string result = input.substr(0, split);
  const std::string drawings = split == std::string::npos ? std::string() : input.substr(split + 6);
  fz::refusing_bad_input([&] { ct::viewer::replay_json(problem, {result, drawings, "fuzz-result.json"}); });
  return 0;
}
