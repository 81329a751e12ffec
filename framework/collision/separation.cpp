#include "collision/separation.hpp"

#include <algorithm>
#include <cmath>

namespace cluttertamp::collision::detail {

namespace {

// Oriented boxes, separating axis theorem (the 3 + 3 face normals and 9 edge cross
// products), in a's frame. A small epsilon keeps near-parallel edge axes from
// claiming a separation that rounding made up.
bool boxes_separated(const Eigen::Vector3d& ha, const Eigen::Isometry3d& world_T_a, const Eigen::Vector3d& hb,
                     const Eigen::Isometry3d& world_T_b) {
  const Eigen::Matrix3d R = world_T_a.linear().transpose() * world_T_b.linear();
  const Eigen::Vector3d t = world_T_a.linear().transpose() * (world_T_b.translation() - world_T_a.translation());
  const Eigen::Matrix3d A = R.cwiseAbs().array() + 1e-9;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(t[i]) > ha[i] + A.row(i).dot(hb)) return true;
  }
  for (int j = 0; j < 3; ++j) {
    if (std::abs(t.dot(R.col(j))) > A.col(j).dot(ha) + hb[j]) return true;
  }
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double ra = ha[i1] * A(i2, j) + ha[i2] * A(i1, j);
      const double rb = hb[j1] * A(i, j2) + hb[j2] * A(i, j1);
      if (std::abs(t[i2] * R(i1, j) - t[i1] * R(i2, j)) > ra + rb) return true;
    }
  }
  return false;
}

// Squared distance between segments p0p1 and q0q1 (clamped closest points).
double segment_distance_squared(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                                const Eigen::Vector3d& q1) {
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, u = 0.0;
  if (a <= 1e-18 && e <= 1e-18) return r.squaredNorm();
  if (a <= 1e-18) {
    u = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 1e-18) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 1e-18 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      u = (b * s + f) / e;
      if (u < 0.0) {
        u = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (u > 1.0) {
        u = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return (p0 + d1 * s - (q0 + d2 * u)).squaredNorm();
}

Eigen::Vector3d obb_half(const Solid& s) {
  return s.kind == Solid::Kind::box ? s.half : Eigen::Vector3d(s.half.x(), s.half.x(), s.kind == Solid::Kind::sphere ? s.half.x() : s.half.z());
}

}  // namespace

bool separated(const Solid& a, const Eigen::Isometry3d& world_T_a, const Solid& b, const Eigen::Isometry3d& world_T_b) {
  if (a.kind != Solid::Kind::box && b.kind != Solid::Kind::box) {
    // Capsules around the cylinders (a sphere is a capsule of zero length).
    auto axis = [](const Solid& s, const Eigen::Isometry3d& T) {
      const double h = s.kind == Solid::Kind::cylinder ? s.half.z() : 0.0;
      return std::pair{T * Eigen::Vector3d(0, 0, -h), T * Eigen::Vector3d(0, 0, h)};
    };
    const auto [a0, a1] = axis(a, world_T_a);
    const auto [b0, b1] = axis(b, world_T_b);
    const double reach = a.half.x() + b.half.x();
    if (segment_distance_squared(a0, a1, b0, b1) > reach * reach) return true;
  }
  return boxes_separated(obb_half(a), world_T_a, obb_half(b), world_T_b);
}

}  // namespace cluttertamp::collision::detail
