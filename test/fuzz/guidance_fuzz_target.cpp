// Fuzz target: a guidance file (YAML), against the scene of problems/push/shelf10/p01.
// Read, or refused as bad input.
#include "cluttertamp/core/world_state.hpp"
#include "cluttertamp/io/guidance_io.hpp"
#include "cluttertamp/io/scene_io.hpp"
#include "cluttertamp/physics/push_world.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fz = cluttertamp::fuzz;
  namespace ct = cluttertamp;
  static const ct::Scene scene = ct::io::load_scene(std::filesystem::path(CLUTTERTAMP_SOURCE_DIR) / "problems/push/shelf10/p01-scene.yaml");
  static const Eigen::AlignedBox2d region = ct::physics::support_region(scene, ct::WorldState::initial(scene));
  const auto file = fz::input_file(data, size, "guidance.yaml");
  fz::refusing_bad_input([&] { ct::io::load_guidance(file, scene, region); });
  return 0;
}
