#include "cluttertamp/perception/visibility.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <utility>

namespace cluttertamp::perception {

namespace {

// Segments may touch a body within this (m) of their end without counting as blocked:
// a sample on an object's surface is where two bodies may meet.
constexpr double kEndMargin = 1e-3;

struct Interval {
  double lo = 0.0, hi = 1.0;
  bool empty() const { return lo > hi; }
  void clip(double a, double b) { lo = std::max(lo, std::min(a, b)), hi = std::min(hi, std::max(a, b)); }
};

// Where a + t d (t in [0, 1]) is inside |x_i| <= half_i along one axis.
void slab(Interval& in, double a, double d, double half) {
  if (std::abs(d) < 1e-12) {
    if (std::abs(a) > half) in = {1.0, 0.0};
    return;
  }
  in.clip((-half - a) / d, (half - a) / d);
}

// Where a + t d is inside the quadric |P (a + t d)|^2 <= r^2 (P: the components used).
void disc(Interval& in, double aa, double ad, double dd, double r) {
  // dd t^2 + 2 ad t + (aa - r^2) <= 0
  if (dd < 1e-18) {
    if (aa > r * r) in = {1.0, 0.0};
    return;
  }
  const double disc = ad * ad - dd * (aa - r * r);
  if (disc < 0) {
    in = {1.0, 0.0};
    return;
  }
  const double s = std::sqrt(disc);
  in.clip((-ad - s) / dd, (-ad + s) / dd);
}

// The part of the segment from `a` to `b` (world) inside the shape, as fractions of it.
Interval inside(const Shape& shape, const Eigen::Isometry3d& world_T_shape, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Isometry3d shape_T_world = world_T_shape.inverse();
  const Eigen::Vector3d p = shape_T_world * a;
  const Eigen::Vector3d d = shape_T_world.linear() * (b - a);
  Interval in;
  if (const auto* box = std::get_if<Box>(&shape)) {
    for (int i = 0; i < 3 && !in.empty(); ++i) slab(in, p[i], d[i], box->size[i] / 2);
  } else if (const auto* c = std::get_if<Cylinder>(&shape)) {
    slab(in, p.z(), d.z(), c->height / 2);
    if (!in.empty()) disc(in, p.head<2>().squaredNorm(), p.head<2>().dot(d.head<2>()), d.head<2>().squaredNorm(), c->radius);
  } else {
    disc(in, p.squaredNorm(), p.dot(d), d.squaredNorm(), std::get<Sphere>(shape).radius);
  }
  return in;
}

struct Sample {
  Eigen::Vector3d point;
  Eigen::Vector3d normal;
};

// Points on the shape's surface with their outward normals (world frame), evenly spread.
std::vector<Sample> surface(const Shape& shape, const Eigen::Isometry3d& pose, const VisibilitySettings& s) {
  std::vector<Sample> local;
  const int around = std::max(4, s.samples_around), up = std::max(1, s.samples_up);
  if (const auto* c = std::get_if<Cylinder>(&shape)) {
    for (int j = 0; j < up; ++j) {
      const double z = -c->height / 2 + (j + 0.5) * c->height / up;
      for (int k = 0; k < around; ++k) {
        const double a = 2 * M_PI * k / around;
        const Eigen::Vector3d n(std::cos(a), std::sin(a), 0.0);
        local.push_back({c->radius * n + Eigen::Vector3d(0, 0, z), n});
      }
    }
    for (int k = 0; k < around; ++k) {  // a ring on each cap
      const double a = 2 * M_PI * (k + 0.5) / around;
      const Eigen::Vector2d xy(0.6 * c->radius * std::cos(a), 0.6 * c->radius * std::sin(a));
      local.push_back({Eigen::Vector3d(xy.x(), xy.y(), c->height / 2), Eigen::Vector3d::UnitZ()});
      local.push_back({Eigen::Vector3d(xy.x(), xy.y(), -c->height / 2), -Eigen::Vector3d::UnitZ()});
    }
  } else if (const auto* b = std::get_if<Box>(&shape)) {
    const Eigen::Vector3d h = b->size / 2;
    for (int axis = 0; axis < 3; ++axis) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (const double side : {-1.0, 1.0}) {
        for (int i = 0; i < up; ++i) {
          for (int j = 0; j < up; ++j) {
            Eigen::Vector3d p;
            p[axis] = side * h[axis];
            p[u] = -h[u] + (i + 0.5) * 2 * h[u] / up;
            p[v] = -h[v] + (j + 0.5) * 2 * h[v] / up;
            Eigen::Vector3d n = Eigen::Vector3d::Zero();
            n[axis] = side;
            local.push_back({p, n});
          }
        }
      }
    }
  } else {
    const double r = std::get<Sphere>(shape).radius;
    const int n = around * up;
    for (int i = 0; i < n; ++i) {  // a Fibonacci sphere
      const double z = 1 - 2 * (i + 0.5) / n;
      const double a = M_PI * (3 - std::sqrt(5.0)) * i;
      const Eigen::Vector3d u(std::sqrt(1 - z * z) * std::cos(a), std::sqrt(1 - z * z) * std::sin(a), z);
      local.push_back({r * u, u});
    }
  }
  std::vector<Sample> world;
  world.reserve(local.size());
  for (const Sample& l : local) world.push_back({pose * l.point, pose.linear() * l.normal});
  return world;
}

}  // namespace

VisibilityModel::VisibilityModel(const Scene& scene, VisibilitySettings settings) : scene_(scene), settings_(settings) {
  if (!scene.world_T_camera) throw std::invalid_argument("scene '" + scene.name + "' has no camera (camera: in its file)");
  world_T_camera_ = *scene.world_T_camera;
}

std::vector<ObjectView> VisibilityModel::look(const WorldState& state) const {
  const Eigen::Vector3d eye = world_T_camera_.translation();
  const Eigen::Isometry3d camera_T_world = world_T_camera_.inverse();
  auto in_view = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d c = camera_T_world * p;
    return c.z() > 0 && c.norm() <= settings_.max_range && std::abs(std::atan2(c.x(), c.z())) <= settings_.horizontal_fov / 2 &&
           std::abs(std::atan2(c.y(), c.z())) <= settings_.vertical_fov / 2;
  };
  std::vector<ObjectView> views;
  for (ObjectIndex i = 0; i < scene_.objects.size(); ++i) {
    ObjectView view{i, 0.0, false, {}};
    if (state.removed.at(i)) {
      views.push_back(view);
      continue;
    }
    std::set<ObjectIndex> occluders;
    int facing = 0, visible = 0;
    for (const Sample& s : surface(scene_.objects[i].shape, state.world_T_objects.at(i), settings_)) {
      if (s.normal.dot(eye - s.point) <= 0) continue;  // faces away: hidden by the object itself
      ++facing;
      if (!in_view(s.point)) continue;
      const double length = (s.point - eye).norm();
      const double end = 1.0 - kEndMargin / std::max(length, kEndMargin);
      auto blocks = [&](const Shape& shape, const Eigen::Isometry3d& pose) {
        const Interval in = inside(shape, pose, eye, s.point);
        return !in.empty() && in.lo < end && in.hi > 0.0;
      };
      bool blocked = false;
      for (const FixedBody& f : scene_.fixed) blocked = blocked || blocks(f.shape, f.world_T_body);
      for (ObjectIndex o = 0; o < scene_.objects.size(); ++o) {
        if (o == i || state.removed.at(o) || !blocks(scene_.objects[o].shape, state.world_T_objects.at(o))) continue;
        blocked = true;
        occluders.insert(o);
      }
      if (!blocked) ++visible;
    }
    view.visible_fraction = facing > 0 ? double(visible) / facing : 0.0;
    view.observed = facing > 0 && view.visible_fraction >= settings_.min_visible_fraction;
    view.occluders.assign(occluders.begin(), occluders.end());
    views.push_back(std::move(view));
  }
  return views;
}

std::vector<ObjectIndex> VisibilityModel::observed(const WorldState& state) const {
  std::vector<ObjectIndex> out;
  for (const ObjectView& v : look(state)) {
    if (v.observed) out.push_back(v.object);
  }
  return out;
}

ObservedWorld::ObservedWorld(const Scene& scene, const WorldState& initial, VisibilitySettings settings)
    : model_(scene, settings), truth_(initial), known_(scene.objects.size(), false) {
  look();
}

std::vector<ObjectIndex> ObservedWorld::look() {
  std::vector<ObjectIndex> seen;
  for (ObjectIndex o : model_.observed(truth_)) {
    if (!known_[o]) {
      known_[o] = true;
      seen.push_back(o);
    }
  }
  return seen;
}

std::vector<ObjectIndex> ObservedWorld::remove(ObjectIndex object) {
  truth_.removed.at(object) = true;
  known_.at(object) = true;  // whatever was taken away was known by then
  return look();
}

std::vector<ObjectIndex> ObservedWorld::update(const WorldState& after) {
  for (std::size_t i = 0; i < known_.size(); ++i) {
    if (!known_[i]) continue;
    truth_.world_T_objects[i] = after.world_T_objects.at(i);
    truth_.removed[i] = after.removed.at(i);
  }
  truth_.held = after.held;
  truth_.robot_configuration = after.robot_configuration;
  return look();
}

std::vector<ObjectIndex> ObservedWorld::touch(const std::vector<ObjectIndex>& objects) {
  std::vector<ObjectIndex> found;
  for (ObjectIndex o : objects) {
    if (!known_.at(o) && !truth_.removed.at(o)) {
      known_[o] = true;
      found.push_back(o);
    }
  }
  std::sort(found.begin(), found.end());
  return found;
}

WorldState ObservedWorld::belief() const {
  WorldState belief = truth_;
  for (std::size_t i = 0; i < known_.size(); ++i) belief.removed[i] = belief.removed[i] || !known_[i];
  return belief;
}

}  // namespace cluttertamp::perception
