#include "cluttertamp/io/srdf.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

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
  // An attribute every element of its kind needs.
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
  for (const TiXmlElement* e = root->FirstChildElement("group"); e; e = e->NextSiblingElement("group")) {
    SrdfGroup group{required(*e, "name"), at(file, *e), {}, {}, {}, {}};
    for (const TiXmlElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      if (c->ValueStr() == "chain") group.chains.emplace_back(required(*c, "base_link"), required(*c, "tip_link"));
      else if (c->ValueStr() == "joint") group.joints.push_back(required(*c, "name"));
      else if (c->ValueStr() == "link") group.links.push_back(required(*c, "name"));
      else if (c->ValueStr() == "group") group.subgroups.push_back(required(*c, "name"));
    }
    out.groups.push_back(std::move(group));
  }
  for (const TiXmlElement* e = root->FirstChildElement("group_state"); e; e = e->NextSiblingElement("group_state")) {
    SrdfGroupState state{required(*e, "name"), required(*e, "group"), at(file, *e), {}};
    for (const TiXmlElement* j = e->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
      const std::string name = required(*j, "name"), value = required(*j, "value");
      if (value.empty()) continue;
      // One number: MoveIt writes several only for planar and floating joints.
      char* end = nullptr;
      const double number = std::strtod(value.c_str(), &end);
      const char* rest = end;
      while (*rest == ' ' || *rest == '\t' || *rest == '\n') ++rest;
      if (end == value.c_str() || *rest != '\0' || !std::isfinite(number)) {
        errors.error(at(file, *j), "<joint name='" + name + "'> of group state '" + state.name + "' has value '" + value +
                                       "', which is not one finite number");
        continue;
      }
      state.values.push_back({name, number, at(file, *j)});
    }
    out.group_states.push_back(std::move(state));
  }
  for (const TiXmlElement* e = root->FirstChildElement("end_effector"); e; e = e->NextSiblingElement("end_effector")) {
    out.end_effectors.push_back({required(*e, "name"), required(*e, "group"), required(*e, "parent_link"),
                                 e->Attribute("parent_group") ? e->Attribute("parent_group") : "", at(file, *e)});
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

// The joints of `group` and of its subgroups (each group once: MoveIt refuses cycles,
// and so do we by not following a group twice).
void collect_joints(const Srdf& srdf, const SrdfGroup& group, std::vector<const SrdfGroup*>& seen,
                    std::vector<std::string>& joints, std::size_t& chains, std::size_t& links) {
  if (std::find(seen.begin(), seen.end(), &group) != seen.end()) return;
  seen.push_back(&group);
  joints.insert(joints.end(), group.joints.begin(), group.joints.end());
  chains += group.chains.size();
  links += group.links.size();
  for (const std::string& name : group.subgroups) {
    if (const SrdfGroup* sub = srdf.find_group(name)) collect_joints(srdf, *sub, seen, joints, chains, links);
  }
}

}  // namespace

std::pair<robot::LinkIndex, robot::LinkIndex> srdf_chain(const Srdf& srdf, const SrdfGroup& group, const robot::RobotModel& model) {
  const std::string about = "group '" + group.name + "' of " + srdf.file.string();
  const auto link = [&](const std::string& name) {
    if (const auto index = model.find_link(name)) return *index;
    throw InputError(group.where, about + " names link '" + name + "', which the URDF (robot '" + model.name() + "') does not have");
  };
  if (group.chains.size() == 1 && group.joints.empty() && group.subgroups.empty()) {
    const robot::LinkIndex base = link(group.chains[0].first), tip = link(group.chains[0].second);
    for (robot::LinkIndex l = tip; l != base; l = model.joints()[static_cast<std::size_t>(model.links()[static_cast<std::size_t>(l)].parent_joint)].parent) {
      if (model.links()[static_cast<std::size_t>(l)].parent_joint < 0) {
        throw InputError(group.where, about + ": tip link '" + group.chains[0].second + "' does not hang below base link '" +
                                          group.chains[0].first + "'");
      }
    }
    return {base, tip};
  }
  for (const std::string& name : group.subgroups) {
    if (!srdf.find_group(name)) throw InputError(group.where, about + " includes group '" + name + "', which the SRDF does not define");
  }
  std::vector<const SrdfGroup*> seen;
  std::vector<std::string> names;
  std::size_t chains = 0, links = 0;
  collect_joints(srdf, group, seen, names, chains, links);
  const auto no_chain = [&](const std::string& why) {
    return InputError(group.where, about + " is no single serial chain (" + why + "); name base_link and tip_link instead");
  };
  if (chains > 0) throw no_chain(std::to_string(chains) + " <chain> elements beside other elements");
  if (names.empty()) throw no_chain(links > 0 ? "it lists links only" : "it lists no joints");
  std::vector<robot::JointIndex> joints;
  for (const std::string& name : names) {
    const auto index = model.find_joint(name);
    if (!index) throw InputError(group.where, about + " names joint '" + name + "', which the URDF (robot '" + model.name() + "') does not have");
    if (std::find(joints.begin(), joints.end(), *index) == joints.end()) joints.push_back(*index);
  }
  // Serial: every joint's parent link is the child link of exactly one other, but one's.
  const auto joint = [&](robot::JointIndex j) -> const robot::Joint& { return model.joints()[static_cast<std::size_t>(j)]; };
  const robot::Joint* first = nullptr;
  for (robot::JointIndex j : joints) {
    const bool below_another = std::any_of(joints.begin(), joints.end(), [&](robot::JointIndex k) { return joint(k).child == joint(j).parent; });
    if (below_another) continue;
    if (first) throw no_chain("joints '" + first->name + "' and '" + joint(j).name + "' both start it");
    first = &joint(j);
  }
  if (!first) throw no_chain("its joints form a loop");
  const robot::Joint* last = first;
  for (std::size_t taken = 1; taken < joints.size(); ++taken) {
    const robot::Joint* next = nullptr;
    for (robot::JointIndex k : joints) {
      if (joint(k).parent != last->child) continue;
      if (next) throw no_chain("it branches below joint '" + last->name + "'");
      next = &joint(k);
    }
    if (!next) throw no_chain("its joints are not connected");
    last = next;
  }
  return {first->parent, last->child};
}

void apply_group_state(const Srdf& srdf, const SrdfGroupState& state, const robot::RobotModel& model, Eigen::VectorXd& q) {
  Diagnostics errors;
  if (!srdf.find_group(state.group)) {
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
    q[j.variable] = v.value;
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
