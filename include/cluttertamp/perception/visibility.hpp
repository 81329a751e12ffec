#pragma once
// What the scene's camera sees (Tian et al., Section V-A): an object is observed when
// enough of its surface facing the camera is in plain view, by rays cast from the
// camera against every other body.

#include <vector>

#include <Eigen/Geometry>

#include "cluttertamp/core/scene.hpp"
#include "cluttertamp/core/world_state.hpp"
#include "cluttertamp/export.hpp"

namespace cluttertamp::perception {

/// How the camera looks.
struct VisibilitySettings {
  /// An object is observed when at least this fraction of its surface samples that
  /// face the camera can be seen (not blocked by another body, within the view).
  double min_visible_fraction = 0.3;
  double horizontal_fov = 1.5;  ///< rad, full angle about the optical axis (+z)
  double vertical_fov = 1.2;    ///< rad
  double max_range = 5.0;       ///< m
  int samples_around = 24;      ///< surface samples around a cylinder (and on each cap ring); a sphere has around x up
  int samples_up = 8;           ///< rows of samples up a cylinder; a box face has up x up
};

/// What the camera sees of one object.
struct ObjectView {
  ObjectIndex object = 0;
  double visible_fraction = 0.0;        ///< of its camera-facing samples; 0 when out of view
  bool observed = false;                ///< visible_fraction >= min_visible_fraction
  std::vector<ObjectIndex> occluders;   ///< objects that block some of its rays (sorted)
};

/// Ray casting from `world_T_camera` (optical frame: +z looks, +x right, +y down)
/// against the scene's fixed bodies and the objects present in a world state. Exact
/// for boxes, cylinders and spheres. Deterministic; const members are thread-safe.
/// Keeps a reference to the scene, which must outlive it.
class CLUTTERTAMP_API VisibilityModel {
 public:
  /// Throws std::invalid_argument when the scene has no camera (`camera:` in its file).
  explicit VisibilityModel(const Scene& scene, VisibilitySettings settings = {});

  /// Every object of the scene (index order): what the camera sees of it in `state`.
  /// Objects removed in `state` neither are seen nor block the view.
  std::vector<ObjectView> look(const WorldState& state) const;

  /// The objects observed in `state`, by index.
  std::vector<ObjectIndex> observed(const WorldState& state) const;

  const VisibilitySettings& settings() const { return settings_; }
  const Eigen::Isometry3d& world_T_camera() const { return world_T_camera_; }

 private:
  const Scene& scene_;
  VisibilitySettings settings_;
  Eigen::Isometry3d world_T_camera_;
};

/// The ground truth of an occlusion run: every object where the scene puts it, of which
/// the planner is told only what the camera has seen so far. Removing an object (it
/// was taken away) may reveal what it hid. Seen once, an object stays known.
class CLUTTERTAMP_API ObservedWorld {
 public:
  /// Looks once from the start. Throws std::invalid_argument without a camera.
  ObservedWorld(const Scene& scene, const WorldState& initial, VisibilitySettings settings = {});

  /// Takes `object` out of the scene and looks again; returns the objects seen for the
  /// first time (sorted).
  std::vector<ObjectIndex> remove(ObjectIndex object);

  /// The robot acted: the known objects are where `after` has them (a state planned on
  /// belief(), in which unknown objects do not count), what the hand holds and the
  /// robot's joints too; then looks again. Returns the objects seen for the first time.
  std::vector<ObjectIndex> update(const WorldState& after);

  /// Objects the robot found by touching them (a motion planned without them met them):
  /// known from now on. Returns those not known before.
  std::vector<ObjectIndex> touch(const std::vector<ObjectIndex>& objects);

  bool known(ObjectIndex object) const { return known_.at(object); }
  const std::vector<bool>& known_objects() const { return known_; }
  /// The truth: every object, removed ones marked.
  const WorldState& truth() const { return truth_; }
  /// The truth as the planner may know it: objects not yet seen are marked removed
  /// (their poses are the truth's and must not be read).
  WorldState belief() const;

 private:
  std::vector<ObjectIndex> look();

  VisibilityModel model_;
  WorldState truth_;
  std::vector<bool> known_;
};

}  // namespace cluttertamp::perception
