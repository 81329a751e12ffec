#include "cluttertamp/io/srdf.hpp"

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

std::vector<DisabledPair> load_srdf_disabled_collisions(const fs::path& file, const robot::RobotModel& model) {
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
  std::vector<DisabledPair> pairs;
  for (const TiXmlElement* e = root->FirstChildElement("disable_collisions"); e; e = e->NextSiblingElement("disable_collisions")) {
    auto link = [&](const char* attribute) -> robot::LinkIndex {
      const char* name = e->Attribute(attribute);
      if (!name) {
        errors.error(at(file, *e), std::string("<disable_collisions> needs a ") + attribute + " attribute");
        return -1;
      }
      if (const auto index = model.find_link(name)) return *index;
      errors.error(at(file, *e), std::string("<disable_collisions> names link '") + name + "', which the URDF (robot '" + model.name() +
                                     "') does not have");
      return -1;
    };
    DisabledPair p{link("link1"), link("link2"), e->Attribute("reason") ? e->Attribute("reason") : ""};
    if (p.first >= 0 && p.second >= 0 && p.first != p.second) pairs.push_back(std::move(p));
  }
  errors.throw_if_any();
  return pairs;
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
