// Fuzz target: a URDF, read through a fixed robot description that names it (base
// link "base", tip link "tip", numeric IK). Read, or refused as bad input.
#include <fstream>

#include "cluttertamp/io/robot_description_io.hpp"
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fz = cluttertamp::fuzz;
  static const auto description = [] {
    const auto file = fz::workspace() / "urdf-robot.yaml";
    std::ofstream(file) << "version: 1\nurdf: robot.urdf\nbase_link: base\ntip_link: tip\nik: numeric\n"
                           "gripper: {finger_thickness: 0.01, base_half_length: 0.05, stroke: 0.08}\n";
    return file;
  }();
  fz::input_file(data, size, "robot.urdf");
  fz::refusing_bad_input([&] { cluttertamp::io::load_robot_description(description); });
  return 0;
}
