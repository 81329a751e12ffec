#include "cluttertamp/io/scene_io.hpp"

#include <cmath>
#include <cstdio>
#include <map>

#include "cluttertamp/collision/shape_distance.hpp"
#include "io/readers.hpp"
#include "io/yaml_reader.hpp"

namespace cluttertamp::io {

namespace {

using detail::MapReader;
using detail::YamlFile;
using detail::kMaxCoordinate;
using detail::kMaxSize;
using detail::kMinSize;

// Overlaps deeper than this are interpenetration; shallower ones are resting contact.
constexpr double kPenetrationTolerance = kContactTolerance;  // m
// How far a stacked object's bottom may be from its supports' tops.
constexpr double kRestingTolerance = 5e-3;  // m
// How far a shape may reach past the workspace box (rounding of rotated poses).
constexpr double kWorkspaceTolerance = 1e-3;  // m

struct ObjectDraft {
  SceneObject object;
  bool target = false;
  std::vector<std::pair<std::string, YAML::Node>> on;  // support names as written
  bool complete = false;                              // shape and pose were read
};

std::optional<Shape> read_shape(const YamlFile& file, const MapReader& map, const std::string& what) {
  const int given = int(map.has("box")) + int(map.has("cylinder")) + int(map.has("sphere"));
  if (given != 1) {
    file.error(map.node(), what + (given == 0 ? " needs a shape: 'box', 'cylinder' or 'sphere'"
                                              : " has more than one shape; give one of 'box', 'cylinder', 'sphere'"));
    return std::nullopt;
  }
  if (map.has("box")) {
    MapReader box(file, map.optional("box"), what + " box", {"size"});
    if (!box.valid()) return std::nullopt;
    const YAML::Node size = box.required("size");
    if (!size.IsDefined()) return std::nullopt;
    auto v = file.vec3(size, what + " box size");
    if (!v) return std::nullopt;
    if ((v->array() <= 0).any()) {
      file.error(size, what + " box size must be positive in every axis");
      return std::nullopt;
    }
    if (!file.vec3_in(size, what + " box size", kMinSize, kMaxSize, "m")) return std::nullopt;
    return Box{*v};
  }
  if (map.has("sphere")) {
    MapReader sphere(file, map.optional("sphere"), what + " sphere", {"radius"});
    if (!sphere.valid()) return std::nullopt;
    const YAML::Node r = sphere.required("radius");
    auto radius = r.IsDefined() ? file.positive(r, what + " sphere radius") : std::nullopt;
    if (radius) radius = file.number_in(r, what + " sphere radius", kMinSize, kMaxSize, "m");
    if (!radius) return std::nullopt;
    return Sphere{*radius};
  }
  MapReader cylinder(file, map.optional("cylinder"), what + " cylinder", {"radius", "height"});
  if (!cylinder.valid()) return std::nullopt;
  const YAML::Node r = cylinder.required("radius");
  const YAML::Node h = cylinder.required("height");
  auto radius = r.IsDefined() ? file.positive(r, what + " cylinder radius") : std::nullopt;
  auto height = h.IsDefined() ? file.positive(h, what + " cylinder height") : std::nullopt;
  if (radius) radius = file.number_in(r, what + " cylinder radius", kMinSize, kMaxSize, "m");
  if (height) height = file.number_in(h, what + " cylinder height", kMinSize, kMaxSize, "m");
  if (!radius || !height) return std::nullopt;
  return Cylinder{*radius, *height};
}

class SceneReader {
 public:
  SceneReader(const std::filesystem::path& path, Diagnostics& diagnostics)
      : file_(path, diagnostics) {}

  Scene read();

 private:
  void read_workspace(const YAML::Node& node);
  void read_fixed(const YAML::Node& node);
  void read_objects(const YAML::Node& node);
  void read_regions(const YAML::Node& node);
  void claim_id(const std::string& id, const YAML::Node& where);
  void resolve_target_and_supports(const YAML::Node& objects_node);
  void check_geometry();
  /// False (and reported) when `bounds` leaves the workspace by more than the tolerance.
  bool check_inside(const Eigen::AlignedBox3d& bounds, const SourceLocation& where, const std::string& what);

  YamlFile file_;
  Scene scene_;
  bool workspace_ok_ = false;
  std::vector<ObjectDraft> drafts_;
  std::map<std::string, SourceLocation> ids_;
};

Scene SceneReader::read() {
  scene_.source_file = file_.path().string();
  scene_.name = file_.path().stem().string();
  if (!file_.loaded()) return scene_;
  if (file_.root().IsNull()) {
    file_.error(SourceLocation{file_.path().string(), 1, 1}, "the scene file is empty");
    return scene_;
  }
  MapReader top(file_, file_.root(), "the scene",
                {"version", "name", "workspace", "robot_base", "exit", "camera", "fixed", "objects", "regions"});
  if (!top.valid()) return scene_;

  file_.check_version(top.required("version"), "scene", kSceneFormatVersion);
  if (top.has("name")) {
    if (auto name = file_.string(top.optional("name"), "name")) scene_.name = *name;
  }
  read_workspace(top.required("workspace"));
  if (const YAML::Node n = top.required("robot_base"); n.IsDefined()) {
    if (auto pose = file_.pose(n, "robot_base")) scene_.world_T_robot_base = *pose;
  }
  const YAML::Node exit_node = top.required("exit");
  if (exit_node.IsDefined()) {
    if (auto pose = file_.pose(exit_node, "exit")) {
      scene_.world_T_exit = *pose;
      if (workspace_ok_ && !scene_.workspace.contains(pose->translation())) {
        file_.error(exit_node, "exit pose x_s lies outside the workspace");
      }
    }
  }
  if (top.has("camera")) scene_.world_T_camera = file_.pose(top.optional("camera"), "camera");
  if (top.has("fixed")) read_fixed(top.optional("fixed"));
  const YAML::Node objects = top.required("objects");
  if (objects.IsDefined()) read_objects(objects);
  if (top.has("regions")) read_regions(top.optional("regions"));
  if (objects.IsDefined()) resolve_target_and_supports(objects);
  check_geometry();
  return scene_;
}

void SceneReader::read_workspace(const YAML::Node& node) {
  if (!node.IsDefined()) return;
  MapReader map(file_, node, "workspace", {"min", "max"});
  if (!map.valid()) return;
  const YAML::Node min_node = map.required("min");
  const YAML::Node max_node = map.required("max");
  auto lo = min_node.IsDefined() ? file_.vec3_in(min_node, "workspace min", -kMaxCoordinate, kMaxCoordinate, "m") : std::nullopt;
  auto hi = max_node.IsDefined() ? file_.vec3_in(max_node, "workspace max", -kMaxCoordinate, kMaxCoordinate, "m") : std::nullopt;
  if (!lo || !hi) return;
  if (((*hi - *lo).array() <= 0).any()) {
    file_.error(node, "workspace max must exceed min in every axis");
    return;
  }
  scene_.workspace = Eigen::AlignedBox3d(*lo, *hi);
  workspace_ok_ = true;
}

void SceneReader::claim_id(const std::string& id, const YAML::Node& where) {
  auto [it, inserted] = ids_.emplace(id, file_.at(where));
  if (!inserted) file_.error(where, "duplicate id '" + id + "' (first declared at " + it->second.str() + ")");
}

void SceneReader::read_fixed(const YAML::Node& node) {
  if (!node.IsSequence()) {
    file_.error(node, "fixed must be a list of bodies");
    return;
  }
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node item = node[i];
    MapReader map(file_, item, "fixed body #" + std::to_string(i + 1), {"id", "box", "cylinder", "sphere", "pose", "friction"});
    if (!map.valid()) continue;
    FixedBody body;
    body.where = file_.at(item);
    const YAML::Node id = map.required("id");
    if (id.IsDefined()) {
      if (auto s = file_.string(id, "id")) { body.id = *s; claim_id(*s, id); }
    }
    const std::string what = "fixed body '" + body.id + "'";
    auto shape = read_shape(file_, map, what);
    const YAML::Node pose_node = map.required("pose");
    auto pose = pose_node.IsDefined() ? file_.pose(pose_node, what + " pose") : std::nullopt;
    if (map.has("friction")) body.friction = file_.number_in(map.optional("friction"), what + " friction", 0, 10, "").value_or(1.0);
    if (!shape || !pose) continue;
    body.shape = *shape;
    body.world_T_body = *pose;
    scene_.fixed.push_back(body);
  }
}

void SceneReader::read_objects(const YAML::Node& node) {
  if (!node.IsSequence() || node.size() == 0) {
    file_.error(node, "objects must be a non-empty list");
    return;
  }
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node item = node[i];
    ObjectDraft draft;
    draft.object.where = file_.at(item);
    MapReader map(file_, item, "object #" + std::to_string(i + 1),
                  {"id", "box", "cylinder", "sphere", "pose", "mass", "friction", "movable", "target", "on"});
    if (map.valid()) {
      const YAML::Node id = map.required("id");
      if (id.IsDefined()) {
        if (auto s = file_.string(id, "id")) { draft.object.id = *s; claim_id(*s, id); }
      }
      const std::string what = "object '" + draft.object.id + "'";
      auto shape = read_shape(file_, map, what);
      const YAML::Node pose_node = map.required("pose");
      auto pose = pose_node.IsDefined() ? file_.pose(pose_node, what + " pose") : std::nullopt;
      const YAML::Node mass = map.required("mass");
      if (mass.IsDefined()) {
        if (auto m = file_.positive(mass, what + " mass")) draft.object.mass = file_.number_in(mass, what + " mass", 0, 1e4, "kg").value_or(0.0);
      }
      draft.object.friction = 0.5;
      if (map.has("friction")) {
        draft.object.friction = file_.number_in(map.optional("friction"), what + " friction", 0, 10, "").value_or(0.5);
      }
      if (map.has("movable")) draft.object.movable = file_.boolean(map.optional("movable"), what + " movable").value_or(true);
      if (map.has("target")) draft.target = file_.boolean(map.optional("target"), what + " target").value_or(false);
      if (map.has("on")) {
        const YAML::Node on = map.optional("on");
        if (!on.IsSequence()) {
          file_.error(on, what + " 'on' must be a list of object ids");
        } else {
          for (const YAML::Node& support : on) {
            if (auto s = file_.string(support, what + " 'on' entry")) draft.on.emplace_back(*s, support);
          }
        }
      }
      if (shape && pose) {
        draft.object.shape = *shape;
        draft.object.world_T_object = *pose;
        draft.complete = true;
      }
    }
    drafts_.push_back(std::move(draft));
  }
}

void SceneReader::read_regions(const YAML::Node& node) {
  if (!node.IsSequence()) {
    file_.error(node, "regions must be a list");
    return;
  }
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node item = node[i];
    MapReader map(file_, item, "region #" + std::to_string(i + 1), {"id", "size", "pose"});
    if (!map.valid()) continue;
    Region region;
    region.where = file_.at(item);
    const YAML::Node id = map.required("id");
    if (id.IsDefined()) {
      if (auto s = file_.string(id, "id")) { region.id = *s; claim_id(*s, id); }
    }
    const std::string what = "region '" + region.id + "'";
    const YAML::Node size_node = map.required("size");
    auto size = size_node.IsDefined() ? file_.vec3(size_node, what + " size") : std::nullopt;
    if (size && (size->array() <= 0).any()) {
      file_.error(size_node, what + " size must be positive in every axis");
      size.reset();
    }
    if (size) size = file_.vec3_in(size_node, what + " size", kMinSize, kMaxSize, "m");
    const YAML::Node pose_node = map.required("pose");
    auto pose = pose_node.IsDefined() ? file_.pose(pose_node, what + " pose") : std::nullopt;
    if (!size || !pose) continue;
    region.size = *size;
    region.world_T_region = *pose;
    check_inside(world_bounds(Box{region.size}, region.world_T_region), region.where, what);
    scene_.regions.push_back(region);
  }
}

void SceneReader::resolve_target_and_supports(const YAML::Node& objects_node) {
  std::vector<const ObjectDraft*> targets;
  for (const ObjectDraft& d : drafts_) {
    if (d.target) targets.push_back(&d);
  }
  if (targets.empty() && !drafts_.empty()) {
    file_.error(objects_node, "no object is marked 'target: true'; exactly one must be");
  }
  for (std::size_t i = 1; i < targets.size(); ++i) {
    file_.error(targets[i]->object.where, "object '" + targets[i]->object.id + "' is a second target (the first is '" +
                                              targets[0]->object.id + "'); exactly one object must be the target");
  }
  if (targets.size() == 1 && !targets[0]->object.movable) {
    file_.error(targets[0]->object.where, "the target '" + targets[0]->object.id + "' must be movable");
  }
  // Only complete objects enter the scene; indices are final from here on.
  std::map<std::string, ObjectIndex> index;
  for (const ObjectDraft& d : drafts_) {
    if (!d.complete) continue;
    index[d.object.id] = static_cast<ObjectIndex>(scene_.objects.size());
    if (d.target) scene_.target = static_cast<ObjectIndex>(scene_.objects.size());
    scene_.objects.push_back(d.object);
  }
  for (const ObjectDraft& d : drafts_) {
    if (!d.complete) continue;
    SceneObject& object = scene_.objects[index.at(d.object.id)];
    for (const auto& [name, node] : d.on) {
      auto it = index.find(name);
      if (name == d.object.id) {
        file_.error(node, "object '" + name + "' cannot rest on itself");
      } else if (it == index.end()) {
        const bool is_other = ids_.count(name) > 0;
        file_.error(node, "object '" + d.object.id + "' is 'on' '" + name + "', which " +
                              (is_other ? "is not an object (only objects can be listed in 'on')"
                                        : "is not declared in this scene"));
      } else {
        object.supports.push_back(it->second);
      }
    }
  }
}

bool SceneReader::check_inside(const Eigen::AlignedBox3d& bounds, const SourceLocation& where, const std::string& what) {
  if (!workspace_ok_) return true;
  const Eigen::AlignedBox3d padded(scene_.workspace.min().array() - kWorkspaceTolerance,
                                   scene_.workspace.max().array() + kWorkspaceTolerance);
  if (!padded.contains(bounds)) {
    file_.error(where, what + " lies (partly) outside the workspace");
    return false;
  }
  return true;
}

void SceneReader::check_geometry() {
  struct Placed {
    const Shape* shape;
    const Eigen::Isometry3d* pose;
    Eigen::AlignedBox3d bounds;
    std::string what;
    SourceLocation where;
    bool measurable;  // inside the workspace: distances are meaningful
  };
  std::vector<Placed> objects;
  for (const SceneObject& o : scene_.objects) {
    const Eigen::AlignedBox3d bounds = world_bounds(o.shape, o.world_T_object);
    const std::string what = "object '" + o.id + "'";
    objects.push_back({&o.shape, &o.world_T_object, bounds, what, o.where, check_inside(bounds, o.where, what)});
  }
  std::vector<Placed> fixed;
  const double workspace_size = workspace_ok_ ? scene_.workspace.diagonal().norm() : 0.0;
  for (const FixedBody& f : scene_.fixed) {
    // Fixed bodies may reach past the workspace (a floor); absurd sizes are not measured.
    const Eigen::AlignedBox3d bounds = world_bounds(f.shape, f.world_T_body);
    const bool sane = bounds.diagonal().allFinite() && (!workspace_ok_ || bounds.diagonal().norm() < 100 * workspace_size);
    if (!sane) file_.error(f.where, "fixed body '" + f.id + "' is far larger than the workspace");
    fixed.push_back({&f.shape, &f.world_T_body, bounds, "fixed body '" + f.id + "'", f.where, sane});
  }
  auto report_overlap = [&](const Placed& a, const Placed& b) {
    // Bounding boxes that do not even touch cannot interpenetrate.
    if (!a.measurable || !b.measurable || !a.bounds.intersects(b.bounds)) return;
    collision::Overlap o;
    try {
      o = collision::overlap(*a.shape, *a.pose, *b.shape, *b.pose, kPenetrationTolerance);
    } catch (const std::exception& e) {
      file_.error(a.where, "cannot measure whether " + a.what + " overlaps " + b.what + ": " + e.what());
      return;
    }
    if (!o.beyond_tolerance) return;
    if (o.depth) {
      char depth[32];
      std::snprintf(depth, sizeof depth, "%.1f mm", *o.depth * 1e3);
      file_.error(a.where, a.what + " interpenetrates " + b.what + " (by " + depth + ")");
    } else {
      file_.error(a.where, a.what + " interpenetrates " + b.what + " (by more than 1 mm)");
    }
  };
  for (std::size_t i = 0; i < objects.size(); ++i) {
    for (std::size_t j = i + 1; j < objects.size(); ++j) report_overlap(objects[j], objects[i]);
    for (const Placed& f : fixed) report_overlap(objects[i], f);
  }
  // A stacked object's bottom lies on the tops of its supports and above them.
  for (std::size_t i = 0; i < scene_.objects.size(); ++i) {
    for (ObjectIndex s : scene_.objects[i].supports) {
      const Eigen::AlignedBox3d& top = objects[i].bounds;
      const Eigen::AlignedBox3d& below = objects[s].bounds;
      const double gap = top.min().z() - below.max().z();
      const bool above = (top.min().head<2>().cwiseMax(below.min().head<2>()).array() <
                          top.max().head<2>().cwiseMin(below.max().head<2>()).array())
                             .all();
      if (std::abs(gap) > kRestingTolerance || !above) {
        char text[96];
        std::snprintf(text, sizeof text, "its bottom is %.1f mm %s the top of", std::abs(gap) * 1e3,
                      gap >= 0 ? "above" : "below");
        file_.error(objects[i].where, objects[i].what + " does not rest on object '" + scene_.objects[s].id + "': " +
                                          (above ? std::string(text) + " it"
                                                 : std::string("it is not above it")));
      }
    }
  }
}

}  // namespace

Scene detail::read_scene(const std::filesystem::path& file, Diagnostics& diagnostics) {
  SceneReader reader(file, diagnostics);
  return reader.read();
}

Scene load_scene(const std::filesystem::path& file) {
  Diagnostics diagnostics;
  Scene scene = detail::read_scene(file, diagnostics);
  diagnostics.throw_if_any();
  return scene;
}

}  // namespace cluttertamp::io
