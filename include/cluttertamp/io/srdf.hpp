#pragma once
// MoveIt's semantic robot description (SRDF): the link pairs never checked for
// collision, the planning groups, their named states and the end effectors, read from
// the file MoveIt users already have; disable_collisions written to one.

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cluttertamp/core/diagnostics.hpp"
#include "cluttertamp/export.hpp"
#include "cluttertamp/robot/robot_model.hpp"

namespace cluttertamp::io {

/// A <disable_collisions link1=... link2=... reason=...> element.
struct DisabledPair {
  robot::LinkIndex first = -1;
  robot::LinkIndex second = -1;
  std::string reason;  ///< as MoveIt writes it: "Adjacent", "Never", "Default", ...
};

/// A <group>: what it names, as written (names are looked up only when the group is
/// used, so an SRDF may describe parts the URDF at hand does not have).
struct SrdfGroup {
  std::string name;
  SourceLocation where;
  std::vector<std::pair<std::string, std::string>> chains;  ///< <chain base_link tip_link>
  std::vector<std::string> joints;                          ///< <joint name>
  std::vector<std::string> links;                           ///< <link name>
  std::vector<std::string> subgroups;                       ///< <group name>
};

/// A <group_state>: named joint values of a group ("ready", "open", ...).
struct SrdfGroupState {
  struct Value {
    std::string joint;
    std::string text;             ///< the value attribute as written
    std::optional<double> value;  ///< rad or m; none when `text` is not one finite number
    SourceLocation where;
  };
  std::string name;
  std::string group;
  SourceLocation where;
  std::vector<Value> values;
};

/// An <end_effector>: the group that acts, and where it is attached.
struct SrdfEndEffector {
  std::string name;
  std::string group;
  std::string parent_link;
  std::string parent_group;  ///< empty when not given
  SourceLocation where;
};

/// What an SRDF file says. Only the disable_collisions pairs are checked while reading;
/// a group or group state is checked when it is used (an SRDF often describes more of a
/// robot than one URDF has, and joints no single number sets). Elements without a name
/// are left out.
struct Srdf {
  std::filesystem::path file;
  std::vector<DisabledPair> disabled_collisions;
  std::vector<SrdfGroup> groups;
  std::vector<SrdfGroupState> group_states;
  std::vector<SrdfEndEffector> end_effectors;

  const SrdfGroup* find_group(std::string_view name) const;
  const SrdfGroupState* find_group_state(std::string_view name) const;
  std::vector<std::string> group_names() const;
  std::vector<std::string> group_state_names() const;
};

/// Reads an SRDF file; the disable_collisions links are looked up in `model`. Throws
/// InputError at the element's line and column for malformed XML, a root that is not
/// <robot>, a disable_collisions without link1 or link2, or with a link the model does
/// not have; every such error of the file is reported at once.
CLUTTERTAMP_API Srdf load_srdf(const std::filesystem::path& file, const robot::RobotModel& model);

/// The disable_collisions pairs of an SRDF file (load_srdf's, the rest unused).
CLUTTERTAMP_API std::vector<DisabledPair> load_srdf_disabled_collisions(const std::filesystem::path& file,
                                                                        const robot::RobotModel& model);

/// The serial chain group `group` of `srdf` moves in `model`, as (base link, tip link):
/// the one <chain> of the group and its subgroups, or else the chain their <joint>s lie
/// on, from the highest joint's parent link to the lowest one's child link (joints left
/// out between them, fixed ones, are on it too). Throws InputError at the group's line
/// for a subgroup the SRDF does not define, a link or joint `model` does not have, a
/// chain without base_link or tip_link, with its tip not below its base or empty, or a
/// group that is no single serial chain (several chains, chains and joints, joints on
/// two branches, links only).
CLUTTERTAMP_API std::pair<robot::LinkIndex, robot::LinkIndex> srdf_chain(const Srdf& srdf, const SrdfGroup& group,
                                                                         const robot::RobotModel& model);

/// `q` with the values of group state `state` set: one configuration value per named
/// joint; a joint that mimics another is skipped (it follows). Throws InputError at the
/// value's line for a joint `model` does not have, a fixed joint, or a value that is not
/// one finite number, and at the state's line for a group `srdf` does not have; every
/// such error at once. Joint limits are the caller's to check.
CLUTTERTAMP_API void apply_group_state(const Srdf& srdf, const SrdfGroupState& state, const robot::RobotModel& model,
                                       Eigen::VectorXd& q);

/// An SRDF document holding only `pairs` as disable_collisions elements, for `model`.
CLUTTERTAMP_API std::string srdf_text(const robot::RobotModel& model, const std::vector<DisabledPair>& pairs);

}  // namespace cluttertamp::io
