// Fuzz target: a scene file (YAML). Read, or refused as bad input with its location.
#include "cluttertamp/io/scene_io.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fz = cluttertamp::fuzz;
  const auto file = fz::input_file(data, size, "scene.yaml");
  fz::refusing_bad_input([&] { cluttertamp::io::load_scene(file); });
  return 0;
}
