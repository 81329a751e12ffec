#include "robot/urdf_check.hpp"

#include <tinyxml.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>
#include <vector>

#include "cluttertamp/core/diagnostics.hpp"

namespace cluttertamp::robot {

namespace fs = std::filesystem;

std::string read_urdf_text(const fs::path& file) {
  std::error_code ec;
  const fs::file_status status = fs::status(file, ec);
  if (ec && ec != std::errc::no_such_file_or_directory) {
    throw InputError({file.string(), 0, 0}, "the URDF cannot be examined: " + ec.message());  // a link loop, ...
  }
  if (!fs::exists(status)) throw InputError({file.string(), 0, 0}, "no such URDF file");
  if (!fs::is_regular_file(status)) throw InputError({file.string(), 0, 0}, "the URDF is not a regular file");
  const std::uintmax_t size = fs::file_size(file, ec);
  if (!ec && size > kMaxUrdfBytes) {
    throw InputError({file.string(), 0, 0}, "the URDF is " + std::to_string(size >> 20) + " MiB, more than the " +
                                                std::to_string(kMaxUrdfBytes >> 20) + " MiB a robot file may have");
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError({file.string(), 0, 0}, "cannot read the URDF file (no permission?)");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError({file.string(), 0, 0}, "cannot read the URDF file (an I/O error)");
  return text.str();
}

namespace {

// Line and column (from 1) of the byte `at` of `text`.
SourceLocation position(const fs::path& file, std::string_view text, std::size_t at) {
  std::size_t line = 1, line_start = 0;
  for (std::size_t i = 0; i < at && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  }
  return {file.string(), line, at - line_start + 1};
}

// A structural fault of the XML text, found without an XML parser (which recurses once
// per level, and says "Error reading Element value." without a position): where it is
// and what it is.
struct StructureFault {
  std::size_t at;
  std::string message;
};

// Elements nested deeper than kMaxUrdfNesting, a comment, declaration or tag the file
// ends inside, an end tag that closes another element, elements left open, no element.
std::optional<StructureFault> structure_fault(const fs::path& file, std::string_view text) {
  std::vector<std::pair<std::string_view, std::size_t>> open;  // name, where its tag starts
  bool any_element = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '<') continue;
    const std::size_t start = i;
    // Skips to the end of `end`; a fault when the file ends first.
    auto skip_to = [&](std::string_view end, const char* what) -> std::optional<StructureFault> {
      const std::size_t found = text.find(end, i + 1);
      if (found == std::string_view::npos) return StructureFault{start, std::string("the file ends inside this ") + what};
      i = found + end.size() - 1;
      return std::nullopt;
    };
    std::optional<StructureFault> fault;
    if (text.compare(i, 4, "<!--") == 0) {
      fault = skip_to("-->", "comment");
    } else if (text.compare(i, 9, "<![CDATA[") == 0) {
      fault = skip_to("]]>", "CDATA section");
    } else if (text.compare(i, 2, "<?") == 0) {
      fault = skip_to("?>", "declaration");
    } else if (text.compare(i, 2, "<!") == 0) {
      fault = skip_to(">", "declaration");
    } else {
      const bool closing = text.compare(i, 2, "</") == 0;
      const std::size_t name_start = i + (closing ? 2 : 1);
      std::size_t name_end = name_start;
      while (name_end < text.size() && !std::isspace(static_cast<unsigned char>(text[name_end])) &&
             text[name_end] != '/' && text[name_end] != '>' && text[name_end] != '<') {
        ++name_end;
      }
      const std::string_view name = text.substr(name_start, name_end - name_start);
      char quote = 0;
      for (i = name_end; i < text.size(); ++i) {
        if (quote) {
          if (text[i] == quote) quote = 0;
        } else if (text[i] == '"' || text[i] == '\'') {
          quote = text[i];
        } else if (text[i] == '>' || text[i] == '<') {
          break;
        }
      }
      if (i >= text.size() || text[i] == '<') return StructureFault{start, "this tag is not closed with '>'"};
      if (name.empty()) return StructureFault{start, "a tag without a name"};
      if (closing) {
        if (open.empty()) return StructureFault{start, "</" + std::string(name) + "> closes no open element"};
        if (open.back().first != name) {
          return StructureFault{start, "</" + std::string(name) + "> closes <" + std::string(open.back().first) +
                                           "> opened at line " + std::to_string(position(file, text, open.back().second).line)};
        }
        open.pop_back();
      } else if (text[i - 1] != '/') {
        if (open.size() == kMaxUrdfNesting) {
          return StructureFault{start, "elements nested more than " + std::to_string(kMaxUrdfNesting) +
                                           " deep; a URDF nests about 6"};
        }
        if (open.empty() && any_element) return StructureFault{start, "a second root element; a URDF has one <robot>"};
        open.emplace_back(name, start);
        any_element = true;
      } else {
        any_element = true;
      }
    }
    if (fault) return fault;
  }
  if (!open.empty()) return StructureFault{open.back().second, "the file ends inside this <" + std::string(open.back().first) + ">"};
  if (!any_element) return StructureFault{text.size(), "no <robot> element"};
  return std::nullopt;
}

class UrdfChecker {
 public:
  UrdfChecker(const fs::path& file, Diagnostics& diagnostics) : file_(file), d_(diagnostics) {}

  void robot(const TiXmlElement& robot) {
    for (const TiXmlElement* e = robot.FirstChildElement("link"); e; e = e->NextSiblingElement("link")) link(*e);
    for (const TiXmlElement* e = robot.FirstChildElement("joint"); e; e = e->NextSiblingElement("joint")) joint(*e);
    for (const auto& [name, where] : mimics_) {
      if (!joint_types_.contains(name)) d_.error(where, "<mimic joint='" + name + "'> names no joint of this robot");
    }
  }

 private:
  SourceLocation at(const TiXmlNode& node) const {
    return {file_.string(), static_cast<std::size_t>(std::max(node.Row(), 0)),
            static_cast<std::size_t>(std::max(node.Column(), 0))};
  }

  const char* required(const TiXmlElement& e, const char* attribute) {
    const char* value = e.Attribute(attribute);
    if (!value || !*value) d_.error(at(e), "<" + e.ValueStr() + "> needs a " + attribute + "='...'");
    return value && *value ? value : nullptr;
  }

  enum class Sign { any, positive, nonzero };

  // The attribute's numbers; an error unless there are `count` finite ones of `sign`.
  std::optional<std::vector<double>> numbers(const TiXmlElement& e, const char* attribute, std::size_t count,
                                             Sign sign) {
    const char* value = e.Attribute(attribute);
    if (!value) return std::nullopt;
    std::vector<double> out;
    std::istringstream in{std::string(value)};
    in.imbue(std::locale::classic());
    std::string token;
    bool ok = true;
    while (in >> token) {
      char* end = nullptr;
      const double x = std::strtod(token.c_str(), &end);
      ok = ok && end && *end == '\0' && std::isfinite(x) && (sign != Sign::positive || x > 0) &&
           (sign != Sign::nonzero || x != 0);
      out.push_back(x);
    }
    if (!ok || out.size() != count) {
      d_.error(at(e), "<" + e.ValueStr() + " " + attribute + "='" + value + "'> must be " +
                          (count == 1 ? std::string("one") : std::to_string(count)) + " finite number" +
                          (count == 1 ? "" : "s") +
                          (sign == Sign::positive ? " above zero" : sign == Sign::nonzero ? ", none zero" : ""));
      return std::nullopt;
    }
    return out;
  }

  void origin(const TiXmlElement& parent) {
    if (const TiXmlElement* o = parent.FirstChildElement("origin")) {
      numbers(*o, "xyz", 3, Sign::any);
      numbers(*o, "rpy", 3, Sign::any);
    }
  }

  void link(const TiXmlElement& e) {
    const char* name = required(e, "name");
    if (name && !links_.emplace(name, at(e)).second) d_.error(at(e), "a second link named '" + std::string(name) + "'");
    if (const TiXmlElement* inertial = e.FirstChildElement("inertial")) {
      origin(*inertial);
      if (const TiXmlElement* mass = inertial->FirstChildElement("mass")) numbers(*mass, "value", 1, Sign::any);
    }
    for (const char* kind : {"collision", "visual"}) {
      for (const TiXmlElement* c = e.FirstChildElement(kind); c; c = c->NextSiblingElement(kind)) shape(*c);
    }
  }

  void shape(const TiXmlElement& element) {
    origin(element);
    const TiXmlElement* geometry = element.FirstChildElement("geometry");
    if (!geometry) {
      d_.error(at(element), "<" + element.ValueStr() + "> has no <geometry>");
      return;
    }
    std::size_t shapes = 0;
    for (const TiXmlElement* g = geometry->FirstChildElement(); g; g = g->NextSiblingElement()) {
      const std::string& kind = g->ValueStr();
      ++shapes;
      if (kind == "box") {
        if (!numbers(*g, "size", 3, Sign::positive) && !g->Attribute("size")) d_.error(at(*g), "<box> needs size='x y z'");
      } else if (kind == "cylinder") {
        for (const char* a : {"radius", "length"}) {
          if (!numbers(*g, a, 1, Sign::positive) && !g->Attribute(a)) d_.error(at(*g), std::string("<cylinder> needs a ") + a);
        }
      } else if (kind == "sphere") {
        if (!numbers(*g, "radius", 1, Sign::positive) && !g->Attribute("radius")) d_.error(at(*g), "<sphere> needs a radius");
      } else if (kind == "mesh") {
        required(*g, "filename");
        numbers(*g, "scale", 3, Sign::nonzero);  // negative: mirrored
      } else {
        d_.error(at(*g), "<geometry> holds an unknown shape <" + kind + "> (box, cylinder, sphere or mesh)");
      }
    }
    if (shapes != 1) {
      d_.error(at(*geometry), "<geometry> must hold exactly one shape (box, cylinder, sphere or mesh), not " +
                                  std::to_string(shapes));
    }
  }

  void joint(const TiXmlElement& e) {
    const char* name = required(e, "name");
    const char* type = required(e, "type");
    static const std::set<std::string> known{"revolute", "continuous", "prismatic", "fixed", "floating", "planar"};
    if (type && !known.contains(type)) {
      d_.error(at(e), "joint type '" + std::string(type) + "' is none of revolute, continuous, prismatic, fixed");
    } else if (type && (std::string_view(type) == "floating" || std::string_view(type) == "planar")) {
      d_.error(at(e), "joint '" + std::string(name ? name : "") + "' is " + type +
                          "; model a mobile base as prismatic x, y and revolute yaw joints");
    }
    if (name && !joint_types_.emplace(name, type ? type : "").second) {
      d_.error(at(e), "a second joint named '" + std::string(name) + "'");
    }
    origin(e);
    const TiXmlElement* parent = e.FirstChildElement("parent");
    const TiXmlElement* child = e.FirstChildElement("child");
    if (!parent) d_.error(at(e), "joint '" + std::string(name ? name : "") + "' has no <parent link='...'/>");
    if (!child) d_.error(at(e), "joint '" + std::string(name ? name : "") + "' has no <child link='...'/>");
    for (const TiXmlElement* end : {parent, child}) {
      if (!end) continue;
      const char* l = required(*end, "link");
      if (l && !links_.contains(l)) d_.error(at(*end), "no link named '" + std::string(l) + "'");
    }
    if (child && child->Attribute("link")) {
      const std::string c = child->Attribute("link");
      if (const auto [it, fresh] = child_of_.emplace(c, at(*child)); !fresh) {
        d_.error(at(*child), "link '" + c + "' is already the child of the joint at line " +
                                 std::to_string(it->second.line) + ": a link has one parent joint");
      }
    }
    static const std::set<std::string> moving{"revolute", "continuous", "prismatic"};
    const bool moves = type && moving.contains(type);
    if (const TiXmlElement* axis = e.FirstChildElement("axis")) {
      if (!axis->Attribute("xyz")) d_.error(at(*axis), "<axis> needs xyz='x y z'");
      if (const auto xyz = numbers(*axis, "xyz", 3, Sign::any); xyz && moves && std::hypot((*xyz)[0], (*xyz)[1], (*xyz)[2]) < 1e-9) {
        d_.error(at(*axis), "a zero <axis>");
      }
    }
    const TiXmlElement* limit = e.FirstChildElement("limit");
    if (moves && !limit) {
      d_.error(at(e), "joint '" + std::string(name ? name : "") + "' needs <limit velocity=... effort=...>");
    }
    if (limit) {
      const auto lower = numbers(*limit, "lower", 1, Sign::any);
      const auto upper = numbers(*limit, "upper", 1, Sign::any);
      numbers(*limit, "effort", 1, Sign::any);
      const auto velocity = numbers(*limit, "velocity", 1, Sign::any);
      for (const char* needed : {"velocity", "effort"}) {
        if (moves && !limit->Attribute(needed)) d_.error(at(*limit), std::string("<limit> needs ") + needed + "='...'");
      }
      if (moves && velocity && !((*velocity)[0] > 0)) d_.error(at(*limit), "<limit velocity> must be above zero");
      // Either bound left out is 0, as urdfdom reads it.
      const bool readable = (lower || !limit->Attribute("lower")) && (upper || !limit->Attribute("upper"));
      const double low = lower ? (*lower)[0] : 0.0, high = upper ? (*upper)[0] : 0.0;
      if (readable && low > high && moves && std::string_view(type) != "continuous") {
        d_.error(at(*limit), "<limit lower> (" + std::to_string(low) + ") is above upper (" + std::to_string(high) +
                                 "); a bound left out is 0");
      }
    }
    if (const TiXmlElement* mimic = e.FirstChildElement("mimic")) {
      if (const char* of = required(*mimic, "joint")) mimics_.emplace_back(of, at(*mimic));
      numbers(*mimic, "multiplier", 1, Sign::any);
      numbers(*mimic, "offset", 1, Sign::any);
    }
  }

  const fs::path& file_;
  Diagnostics& d_;
  std::map<std::string, SourceLocation> links_;
  std::map<std::string, SourceLocation> child_of_;
  std::map<std::string, std::string> joint_types_;
  std::vector<std::pair<std::string, SourceLocation>> mimics_;
};

}  // namespace

void check_urdf(const fs::path& file, const std::string& text) {
  if (const auto fault = structure_fault(file, text)) throw InputError(position(file, text, fault->at), fault->message);
  TiXmlDocument document;
  document.Parse(text.c_str(), nullptr, TIXML_ENCODING_UTF8);
  if (document.Error()) {
    throw InputError({file.string(), static_cast<std::size_t>(std::max(document.ErrorRow(), 0)),
                      static_cast<std::size_t>(std::max(document.ErrorCol(), 0))},
                     std::string("malformed XML: ") + document.ErrorDesc());
  }
  const TiXmlElement* robot = document.RootElement();
  if (!robot) {
    throw InputError(position(file, text, text.find('<')), "no <robot> element could be read from here on (a malformed declaration?)");
  }
  if (robot->ValueStr() != "robot") {
    throw InputError({file.string(), static_cast<std::size_t>(std::max(robot->Row(), 0)),
                      static_cast<std::size_t>(std::max(robot->Column(), 0))},
                     "a URDF's root element is <robot>, not <" + robot->ValueStr() + ">");
  }
  Diagnostics diagnostics;
  UrdfChecker(file, diagnostics).robot(*robot);
  diagnostics.throw_if_any();
}

}  // namespace cluttertamp::robot
