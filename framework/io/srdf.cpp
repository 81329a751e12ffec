#include "cluttertamp/io/srdf.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <tinyxml.h>

#include "cluttertamp/core/diagnostics.hpp"

namespace cluttertamp::io {

namespace fs = std::filesystem;

namespace {

// Larger SRDF files are not semantic descriptions but a way to exhaust memory.
constexpr std::uintmax_t kMaxSrdfBytes = 64u << 20;

std::string read_srdf(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) throw InputError({file.string(), 0, 0}, fs::exists(file, ec) ? "the SRDF is not a regular file" : "no such SRDF file");
  if (fs::file_size(file, ec) > kMaxSrdfBytes) throw InputError({file.string(), 0, 0}, "the SRDF file is larger than 64 MiB");
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) throw InputError({file.string(), 0, 0}, "cannot read the SRDF file");
  return text.str();
}

SourceLocation at(const fs::path& file, const TiXmlNode& node) {
  return {file.string(), static_cast<std::size_t>(std::max(0, node.Row())), static_cast<std::size_t>(std::max(0, node.Column()))};
}

}  // namespace

Srdf load_srdf(const fs::path& file, const robot::RobotModel& model) {
  const std::string text = read_srdf(file);
  TiXmlDocument doc;
  doc.Parse(text.c_str(), nullptr, TIXML_ENCODING_UTF8);
  if (doc.Error()) {
    throw InputError({file.string(), static_cast<std::size_t>(std::max(0, doc.ErrorRow())), static_cast<std::size_t>(std::max(0, doc.ErrorCol()))},
                     std::string("malformed SRDF: ") + doc.ErrorDesc());
  }
  const TiXmlElement* root = doc.RootElement();
  if (!root || root->ValueStr() != "robot") {
    throw InputError(root ? at(file, *root) : SourceLocation{file.string(), 0, 0}, "an SRDF's root element must be <robot>");
  }
  Diagnostics errors;
  // An attribute every disable_collisions needs.
  const auto required = [&](const TiXmlElement& e, const char* attribute) -> std::string {
    if (const char* value = e.Attribute(attribute)) return value;
    errors.error(at(file, e), "<" + e.ValueStr() + "> needs a " + attribute + " attribute");
    return {};
  };
  Srdf out;
  out.file = file;
  for (const TiXmlElement* e = root->FirstChildElement("disable_collisions"); e; e = e->NextSiblingElement("disable_collisions")) {
    auto link = [&](const char* attribute) -> robot::LinkIndex {
      const std::string name = required(*e, attribute);
      if (name.empty()) return -1;
      if (const auto index = model.find_link(name)) return *index;
      errors.error(at(file, *e), "<disable_collisions> names link '" + name + "', which the URDF (robot '" + model.name() +
                                     "') does not have");
      return -1;
    };
    DisabledPair p{link("link1"), link("link2"), e->Attribute("reason") ? e->Attribute("reason") : ""};
    if (p.first >= 0 && p.second >= 0 && p.first != p.second) out.disabled_collisions.push_back(std::move(p));
  }
  // Groups, states and end effectors are checked when used: here only what they say.
  const auto attribute = [](const TiXmlElement& e, const char* name) { return std::string(e.Attribute(name) ? e.Attribute(name) : ""); };
  for (const TiXmlElement* e = root->FirstChildElement("group"); e; e = e->NextSiblingElement("group")) {
    SrdfGroup group{attribute(*e, "name"), at(file, *e), {}, {}, {}, {}};
    if (group.name.empty()) continue;
    for (const TiXmlElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      if (c->ValueStr() == "chain") group.chains.emplace_back(attribute(*c, "base_link"), attribute(*c, "tip_link"));
      else if (c->ValueStr() == "joint") group.joints.push_back(attribute(*c, "name"));
      else if (c->ValueStr() == "link") group.links.push_back(attribute(*c, "name"));
      else if (c->ValueStr() == "group") group.subgroups.push_back(attribute(*c, "name"));
    }
    out.groups.push_back(std::move(group));
  }
  for (const TiXmlElement* e = root->FirstChildElement("group_state"); e; e = e->NextSiblingElement("group_state")) {
    SrdfGroupState state{attribute(*e, "name"), attribute(*e, "group"), at(file, *e), {}};
    if (state.name.empty()) continue;
    for (const TiXmlElement* j = e->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
      SrdfGroupState::Value v{attribute(*j, "name"), attribute(*j, "value"), std::nullopt, at(file, *j)};
      // One number: MoveIt writes several only for planar and floating joints.
      char* end = nullptr;
      const double number = std::strtod(v.text.c_str(), &end);
      const char* rest = end;
      while (*rest == ' ' || *rest == '\t' || *rest == '\n') ++rest;
      if (end != v.text.c_str() && *rest == '\0' && std::isfinite(number)) v.value = number;
      state.values.push_back(std::move(v));
    }
    out.group_states.push_back(std::move(state));
  }
  for (const TiXmlElement* e = root->FirstChildElement("end_effector"); e; e = e->NextSiblingElement("end_effector")) {
    SrdfEndEffector effector{attribute(*e, "name"), attribute(*e, "group"), attribute(*e, "parent_link"), attribute(*e, "parent_group"),
                             at(file, *e)};
    if (!effector.name.empty()) out.end_effectors.push_back(std::move(effector));
  }
  errors.throw_if_any();
  return out;
}

std::vector<DisabledPair> load_srdf_disabled_collisions(const fs::path& file, const robot::RobotModel& model) {
  return load_srdf(file, model).disabled_collisions;
}

const SrdfGroup* Srdf::find_group(std::string_view name) const {
  for (const SrdfGroup& g : groups) {
    if (g.name == name) return &g;
  }
  return nullptr;
}

const SrdfGroupState* Srdf::find_group_state(std::string_view name) const {
  for (const SrdfGroupState& s : group_states) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

std::vector<std::string> Srdf::group_names() const {
  std::vector<std::string> out;
  for (const SrdfGroup& g : groups) out.push_back(g.name);
  return out;
}

std::vector<std::string> Srdf::group_state_names() const {
  std::vector<std::string> out;
  for (const SrdfGroupState& s : group_states) out.push_back(s.name);
  return out;
}

namespace {

// What `group` and its subgroups name, each group once (MoveIt refuses cycles; we do
// not follow a group twice).
struct Members {
  std::vector<const SrdfGroup*> seen;
  std::vector<std::pair<std::string, std::string>> chains;
  std::vector<std::string> joints;
  std::size_t links = 0;
};

void collect(const Srdf& srdf, const SrdfGroup& group, const std::string& about, Members& out) {
  if (std::find(out.seen.begin(), out.seen.end(), &group) != out.seen.end()) return;
  out.seen.push_back(&group);
  out.chains.insert(out.chains.end(), group.chains.begin(), group.chains.end());
  out.joints.insert(out.joints.end(), group.joints.begin(), group.joints.end());
  out.links += group.links.size();
  for (const std::string& name : group.subgroups) {
    const SrdfGroup* sub = srdf.find_group(name);
    if (!sub) throw InputError(group.where, about + " includes group '" + name + "', which the SRDF does not define");
    collect(srdf, *sub, about, out);
  }
}

}  // namespace

std::pair<robot::LinkIndex, robot::LinkIndex> srdf_chain(const Srdf& srdf, const SrdfGroup& group, const robot::RobotModel& model) {
  const std::string about = "group '" + group.name + "' of " + srdf.file.string();
  const auto fail = [&](const std::string& message) { return InputError(group.where, about + message); };
  const auto no_chain = [&](const std::string& why) {
    return fail(" is no single serial chain (" + why + "); name base_link and tip_link instead");
  };
  Members members;
  collect(srdf, group, about, members);
  const auto link = [&](const std::string& name) {
    if (const auto index = model.find_link(name)) return *index;
    throw fail(" names link '" + name + "', which the URDF (robot '" + model.name() + "') does not have");
  };
  const auto joint = [&](robot::JointIndex j) -> const robot::Joint& { return model.joints()[static_cast<std::size_t>(j)]; };
  const auto parent_joint = [&](robot::LinkIndex l) { return model.links()[static_cast<std::size_t>(l)].parent_joint; };
  if (members.chains.size() > 1) throw no_chain(std::to_string(members.chains.size()) + " chains");
  if (members.chains.size() == 1) {
    if (!members.joints.empty()) throw no_chain("a chain and joints");
    const auto& [base_name, tip_name] = members.chains[0];
    if (base_name.empty() || tip_name.empty()) throw fail(": its <chain> needs both base_link and tip_link");
    const robot::LinkIndex base = link(base_name), tip = link(tip_name);
    if (base == tip) throw fail(": its chain from '" + base_name + "' to itself is empty");
    try {
      model.chain(base, tip);
    } catch (const std::invalid_argument&) {
      throw fail(": tip link '" + tip_name + "' does not hang below base link '" + base_name + "'");
    }
    return {base, tip};
  }
  if (members.joints.empty()) throw no_chain(members.links > 0 ? "it lists links only" : "it lists no joints");
  std::vector<robot::JointIndex> joints;
  for (const std::string& name : members.joints) {
    const auto index = model.find_joint(name);
    if (!index) throw fail(" names joint '" + name + "', which the URDF (robot '" + model.name() + "') does not have");
    if (std::find(joints.begin(), joints.end(), *index) == joints.end()) joints.push_back(*index);
  }
  // The lowest joint (farthest from the root) ends the chain, the highest starts it;
  // every joint named must lie on the path between them.
  const auto depth = [&](robot::JointIndex j) {
    std::size_t d = 0;
    for (robot::LinkIndex l = joint(j).parent; parent_joint(l) >= 0; l = joint(parent_joint(l)).parent) ++d;
    return d;
  };
  const auto by_depth = [&](robot::JointIndex a, robot::JointIndex b) { return depth(a) < depth(b); };
  const robot::JointIndex top = *std::min_element(joints.begin(), joints.end(), by_depth);
  const robot::JointIndex bottom = *std::max_element(joints.begin(), joints.end(), by_depth);
  std::vector<robot::JointIndex> path;  // from bottom up to top
  for (robot::JointIndex j = bottom;; j = parent_joint(joint(j).parent)) {
    path.push_back(j);
    if (j == top || parent_joint(joint(j).parent) < 0) break;
  }
  if (path.back() != top) throw no_chain("joints '" + joint(top).name + "' and '" + joint(bottom).name + "' lie on two branches");
  for (robot::JointIndex j : joints) {
    if (std::find(path.begin(), path.end(), j) == path.end()) {
      throw no_chain("joint '" + joint(j).name + "' is off the chain from joint '" + joint(top).name + "' to joint '" + joint(bottom).name + "'");
    }
  }
  return {joint(top).parent, joint(bottom).child};
}

void apply_group_state(const Srdf& srdf, const SrdfGroupState& state, const robot::RobotModel& model, Eigen::VectorXd& q) {
  Diagnostics errors;
  if (state.group.empty()) {
    errors.error(state.where, "group state '" + state.name + "' has no group attribute (<group_state name=... group=...>)");
  } else if (!srdf.find_group(state.group)) {
    errors.error(state.where, "group state '" + state.name + "' is of group '" + state.group + "', which the SRDF does not define");
  }
  for (const SrdfGroupState::Value& v : state.values) {
    const auto index = model.find_joint(v.joint);
    if (!index) {
      errors.error(v.where, "group state '" + state.name + "' sets joint '" + v.joint + "', which the URDF (robot '" + model.name() +
                                "') does not have");
      continue;
    }
    const robot::Joint& j = model.joints()[static_cast<std::size_t>(*index)];
    if (j.mimicked >= 0) continue;  // follows the joint it mimics
    if (j.variable < 0) {
      errors.error(v.where, "group state '" + state.name + "' sets joint '" + v.joint + "', which is fixed");
      continue;
    }
    if (!v.value) {
      errors.error(v.where, "group state '" + state.name + "' gives joint '" + v.joint + "' the value '" + v.text +
                                "', which is not one finite number");
      continue;
    }
    q[j.variable] = *v.value;
  }
  errors.throw_if_any();
}

std::string srdf_text(const robot::RobotModel& model, const std::vector<DisabledPair>& pairs) {
  // Names are XML attribute values: escape what XML needs escaped.
  auto escaped = [](const std::string& s) {
    std::string out;
    for (const char c : s) {
      switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        default: out += c;
      }
    }
    return out;
  };
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<robot name=\"" << escaped(model.name()) << "\">\n";
  for (const DisabledPair& p : pairs) {
    out << "  <disable_collisions link1=\"" << escaped(model.links()[static_cast<std::size_t>(p.first)].name) << "\" link2=\""
        << escaped(model.links()[static_cast<std::size_t>(p.second)].name) << "\" reason=\"" << escaped(p.reason) << "\"/>\n";
  }
  out << "</robot>\n";
  return out.str();
}

}  // namespace cluttertamp::io
