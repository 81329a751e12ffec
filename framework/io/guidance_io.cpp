#include "cluttertamp/io/guidance_io.hpp"

#include <iomanip>
#include <sstream>

#include "io/yaml_reader.hpp"

namespace cluttertamp::io {

namespace {

constexpr int kGuidanceFormatVersion = 1;

std::string xy(const Eigen::Vector2d& v) {
  std::ostringstream out;
  out << std::setprecision(4) << "(" << v.x() << ", " << v.y() << ")";
  return out.str();
}

// A YAML double-quoted scalar: any id reads back.
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

void read_guide(const detail::YamlFile& file, const YAML::Node& item, std::size_t number, const Scene& scene,
                const Eigen::AlignedBox2d& shelf, Guidance& guidance) {
  const std::string what = "guide #" + std::to_string(number);
  detail::MapReader map(file, item, what, {"object", "centre", "diameter"});
  if (!map.valid()) return;
  Guide guide;
  guide.where = file.at(item);
  bool ok = true;
  const YAML::Node object = map.required("object");
  if (object.IsDefined()) {
    if (auto id = file.string(object, what + " object")) {
      const auto found = scene.find_object(*id);
      if (!found) {
        file.error(object, what + ": unknown object '" + *id + "'");
        ok = false;
      } else if (!scene.objects[*found].movable) {
        file.error(object, what + ": object '" + *id + "' is not movable");
        ok = false;
      } else {
        guide.object = *found;
      }
    } else {
      ok = false;
    }
  } else {
    ok = false;
  }
  const YAML::Node centre = map.required("centre");
  if (centre.IsDefined()) {
    if (!centre.IsSequence() || centre.size() != 2) {
      file.error(centre, what + " centre must be [x, y] (m)");
      ok = false;
    } else {
      auto x = file.number_in(centre[0], what + " centre x", -detail::kMaxCoordinate, detail::kMaxCoordinate, "m");
      auto y = file.number_in(centre[1], what + " centre y", -detail::kMaxCoordinate, detail::kMaxCoordinate, "m");
      if (x && y) guide.centre = {*x, *y};
      ok = ok && x && y;
    }
  } else {
    ok = false;
  }
  const YAML::Node diameter = map.required("diameter");
  if (diameter.IsDefined()) {
    auto d = file.number_in(diameter, what + " diameter", detail::kMinSize, detail::kMaxSize, "m");
    if (d) guide.diameter = *d;
    ok = ok && d;
  } else {
    ok = false;
  }
  if (!ok) return;
  const Eigen::Vector2d half = Eigen::Vector2d::Constant(guide.diameter / 2);
  if (!shelf.contains(Eigen::AlignedBox2d(guide.centre - half, guide.centre + half))) {
    file.error(centre, what + ": the region about " + xy(guide.centre) + " (diameter " + std::to_string(guide.diameter) +
                           " m) is not inside the shelf, x in [" + std::to_string(shelf.min().x()) + ", " +
                           std::to_string(shelf.max().x()) + "], y in [" + std::to_string(shelf.min().y()) + ", " +
                           std::to_string(shelf.max().y()) + "] m");
    return;
  }
  guidance.push_back(guide);
}

}  // namespace

Guidance load_guidance(const std::filesystem::path& path, const Scene& scene, const Eigen::AlignedBox2d& shelf) {
  Diagnostics diagnostics;
  Guidance guidance;
  {
    detail::YamlFile file(path, diagnostics);
    if (file.loaded() && file.root().IsNull()) {
      file.error(SourceLocation{file.path().string(), 1, 1}, "the guidance file is empty");
    } else if (file.loaded()) {
      detail::MapReader top(file, file.root(), "the guidance", {"version", "guides"});
      if (top.valid()) {
        file.check_version(top.required("version"), "guidance", kGuidanceFormatVersion);
        const YAML::Node guides = top.required("guides");
        if (guides.IsDefined() && !guides.IsSequence()) {
          file.error(guides, "guides must be a list of {object, centre, diameter}");
        } else if (guides.IsDefined()) {
          for (std::size_t i = 0; i < guides.size(); ++i) read_guide(file, guides[i], i + 1, scene, shelf, guidance);
        }
      }
    }
  }
  diagnostics.throw_if_any();
  return guidance;
}

std::string guidance_to_yaml(const Scene& scene, const Guidance& guidance) {
  std::ostringstream out;
  out << std::setprecision(10);
  out << "# Guidance: push each object, in order, until its centre is in its region (docs/plugins.md, \"Guidance files\").\n";
  out << "version: " << kGuidanceFormatVersion << "\nguides:" << (guidance.empty() ? " []\n" : "\n");
  for (const Guide& g : guidance) {
    out << "  - {object: " << quoted(scene.objects.at(g.object).id) << ", centre: [" << g.centre.x() << ", " << g.centre.y()
        << "], diameter: " << g.diameter << "}\n";
  }
  return out.str();
}

}  // namespace cluttertamp::io
