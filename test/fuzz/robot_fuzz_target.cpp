// Fuzz target: a robot description (YAML) naming a URDF among the project's data.
// Read (kinematics, collision shapes, IK set up), or refused as bad input.
#include "cluttertamp/io/robot_description_io.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fz = cluttertamp::fuzz;
  const auto file = fz::input_file(data, size, "robot.yaml");
  fz::refusing_bad_input([&] { cluttertamp::io::load_robot_description(file); });
  return 0;
}
