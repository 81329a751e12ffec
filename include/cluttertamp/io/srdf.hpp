#pragma once
// MoveIt's semantic robot description (SRDF): the link pairs never checked for
// collision, read from and written to the file MoveIt users already have.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "cluttertamp/export.hpp"
#include "cluttertamp/robot/robot_model.hpp"

namespace cluttertamp::io {

/// A <disable_collisions link1=... link2=... reason=...> element.
struct DisabledPair {
  robot::LinkIndex first = -1;
  robot::LinkIndex second = -1;
  std::string reason;  ///< as MoveIt writes it: "Adjacent", "Never", "Default", ...
};

/// The disable_collisions pairs of an SRDF file, their links looked up in `model`. Other
/// elements (groups, group states, end effectors, virtual joints) are not used and not
/// checked. Throws InputError at the element's line and column for malformed XML, a
/// root that is not <robot>, a missing link1 or link2 attribute, or a link the model does
/// not have; every such error of the file is reported at once.
CLUTTERTAMP_API std::vector<DisabledPair> load_srdf_disabled_collisions(const std::filesystem::path& file,
                                                                        const robot::RobotModel& model);

/// An SRDF document holding only `pairs` as disable_collisions elements, for `model`.
CLUTTERTAMP_API std::string srdf_text(const robot::RobotModel& model, const std::vector<DisabledPair>& pairs);

}  // namespace cluttertamp::io
