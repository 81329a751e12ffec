#pragma once

#include <filesystem>
#include <vector>

#include "cluttertamp/export.hpp"
#include "cluttertamp/robot/robot_description.hpp"

namespace cluttertamp::io {

/// Reads a robot description file (docs/file-formats.md, "Robot description files")
/// and the URDF it names; relative paths are taken relative to the file.
/// Throws InputError with file:line:column for a bad description and with the URDF's
/// file and element for a bad model.
CLUTTERTAMP_API robot::RobotDescription load_robot_description(const std::filesystem::path& file);

/// Directories searched for a URDF's package:// meshes before a description's own
/// `package_paths` and ROS_PACKAGE_PATH: the command line's --package-path. For the
/// whole process (every description loaded after the call).
CLUTTERTAMP_API void set_command_line_package_paths(std::vector<std::filesystem::path> directories);

}  // namespace cluttertamp::io
