// Fuzz target: a sweep file (YAML), naming the project's problems by relative paths.
// Read, or refused as bad input.
#include "cluttertamp/io/sweep_file.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fz = cluttertamp::fuzz;
  const auto file = fz::input_file(data, size, "sweep.yaml");
  fz::refusing_bad_input([&] { cluttertamp::io::load_sweep_file(file); });
  return 0;
}
