#pragma once
// What urdfdom accepts silently or reports without a position, checked before it reads
// the text: every error with its line and column.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

namespace cluttertamp::robot {

/// Deepest element nesting a URDF may have. Real robot files nest about 6 deep (robot,
/// link, collision, geometry, mesh); XML parsers recurse once per level, so a file of
/// 50,000 nested elements would end the process.
inline constexpr std::size_t kMaxUrdfNesting = 100;

/// Largest URDF file read, bytes (the largest robot makers' files are about 1 MB).
inline constexpr std::uintmax_t kMaxUrdfBytes = 64u << 20;

/// The text of the URDF `file`. Throws InputError when it is missing, not a regular
/// file (a device, a directory), larger than kMaxUrdfBytes or unreadable.
std::string read_urdf_text(const std::filesystem::path& file);

/// Throws InputError listing every problem found in the URDF `text` of `file`, each at
/// its line and column: nesting deeper than kMaxUrdfNesting, a tag, comment or element
/// the file ends inside, an end tag closing another element (found before any XML
/// parser runs); other malformed XML; a link or
/// joint without a name, or a name used twice; a <collision> or <visual> without
/// exactly one shape in its <geometry>; sizes, radii, lengths and scales that are not
/// finite and positive; an origin, axis or scale without exactly three finite numbers
/// (a scale's none zero);
/// a joint of an unknown type, of a type we cannot plan for (planar, floating), naming
/// a link that does not exist, making a link the child of two joints, without a usable
/// <limit> (velocity above zero, lower at most upper), with a zero axis, or mimicking a
/// joint that does not exist.
void check_urdf(const std::filesystem::path& file, const std::string& text);

}  // namespace cluttertamp::robot
