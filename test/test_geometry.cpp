#include <cmath>

#include <gtest/gtest.h>

#include "cluttertamp/core/geometry.hpp"

namespace cluttertamp {
namespace {

Eigen::Isometry3d pose(Eigen::Vector3d xyz, double roll = 0, double pitch = 0, double yaw = 0) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = xyz;
  p.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return p;
}

TEST(Geometry, UprightCylinderBoundsAreExact) {
  const auto b = world_bounds(Cylinder{0.04, 0.2}, pose({1, 2, 0.1}));
  EXPECT_TRUE(b.min().isApprox(Eigen::Vector3d(0.96, 1.96, 0.0)));
  EXPECT_TRUE(b.max().isApprox(Eigen::Vector3d(1.04, 2.04, 0.2)));
}

TEST(Geometry, LyingCylinderBoundsSwapAxes) {
  // Rolled 90 degrees: the axis lies along y.
  const auto b = world_bounds(Cylinder{0.04, 0.2}, pose({0, 0, 0}, M_PI / 2));
  EXPECT_NEAR(b.max().x(), 0.04, 1e-12);
  EXPECT_NEAR(b.max().y(), 0.1, 1e-12);
  EXPECT_NEAR(b.max().z(), 0.04, 1e-12);
}

TEST(Geometry, BoxBoundsContainEveryCorner) {
  const Box box{{0.3, 0.1, 0.05}};
  const auto p = pose({0.5, -0.2, 0.3}, 0.3, -0.7, 1.1);
  const auto b = world_bounds(box, p);
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d local((corner & 1 ? 0.5 : -0.5) * 0.3, (corner & 2 ? 0.5 : -0.5) * 0.1,
                                (corner & 4 ? 0.5 : -0.5) * 0.05);
    const Eigen::Vector3d world = p * local;
    EXPECT_TRUE(b.contains(world)) << world.transpose();
  }
}

}  // namespace
}  // namespace cluttertamp

#include "cluttertamp/collision/shape_distance.hpp"

namespace cluttertamp {
namespace {

TEST(Overlap, UprightPrismsHaveExactDepths) {
  const Box box{{0.2, 0.1, 0.3}};
  // Two equal boxes turned 45 degrees, moved apart along x: their long faces meet first,
  // when the centres are 2 * 0.05 / sin(45 deg) apart; the depth shrinks along that normal.
  const double touching = 0.1 / std::sqrt(0.5);
  auto yawed = [](double x) { return pose({x, 0, 0.15}, 0, 0, M_PI / 4); };
  EXPECT_NEAR(*collision::overlap(box, yawed(0), box, yawed(touching), 1e-3).depth, 0.0, 1e-12);
  EXPECT_NEAR(*collision::overlap(box, yawed(0), box, yawed(touching - 0.002 / std::sqrt(0.5)), 1e-3).depth, 0.002, 1e-12);
  // A cylinder 2 mm into a box's side, and 0.5 mm: only the first is beyond 1 mm.
  const Cylinder cylinder{0.04, 0.3};
  const auto deep = collision::overlap(cylinder, pose({0.138, 0, 0.15}), box, pose({0, 0, 0.15}), 1e-3);
  EXPECT_NEAR(*deep.depth, 0.002, 1e-12);
  EXPECT_TRUE(deep.beyond_tolerance);
  EXPECT_FALSE(collision::overlap(cylinder, pose({0.1395, 0, 0.15}), box, pose({0, 0, 0.15}), 1e-3).beyond_tolerance);
  // Stacked: a box resting on a cylinder's top is vertical contact, depth 0.
  EXPECT_NEAR(*collision::overlap(box, pose({0, 0, 0.45}), cylinder, pose({0, 0, 0.15}), 1e-3).depth, 0.0, 1e-12);
}

TEST(Overlap, TiltedShapesUseShrunkBooleanTests) {
  const Cylinder lying{0.04, 0.3};
  const Box floor{{1.0, 1.0, 0.02}};
  const auto on_floor = pose({0, 0, 0.04}, M_PI / 2);
  EXPECT_FALSE(collision::overlap(lying, on_floor, floor, pose({0, 0, -0.01}), 1e-3).beyond_tolerance);
  EXPECT_TRUE(collision::overlap(lying, pose({0, 0, 0.035}, M_PI / 2), floor, pose({0, 0, -0.01}), 1e-3).beyond_tolerance);
  EXPECT_FALSE(collision::overlap(lying, on_floor, floor, pose({0, 0, -0.01}), 1e-3).depth.has_value());
}

}  // namespace
}  // namespace cluttertamp

#include <random>

#include "collision/separation.hpp"

namespace cluttertamp {
namespace {

// The separation filter runs before FCL in every validity check: it must never call
// touching shapes separated, and must decide most separated pairs (else it is useless).
TEST(Separation, NeverSeparatesTouchingShapesAndDecidesMostOthers) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0), angle(-M_PI, M_PI);
  auto random_shape = [&](Shape& shape, collision::detail::Solid& solid) {
    const int kind = static_cast<int>(rng() % 3);
    const Eigen::Vector3d size(0.02 + 0.2 * unit(rng), 0.02 + 0.2 * unit(rng), 0.02 + 0.4 * unit(rng));
    using Kind = collision::detail::Solid::Kind;
    if (kind == 0) {
      shape = Box{size};
      solid = {Kind::box, size / 2};
    } else if (kind == 1) {
      shape = Cylinder{size.x() / 2, size.z()};
      solid = {Kind::cylinder, {size.x() / 2, size.x() / 2, size.z() / 2}};
    } else {
      shape = Sphere{size.x() / 2};
      solid = {Kind::sphere, Eigen::Vector3d::Constant(size.x() / 2)};
    }
  };
  int touching = 0, apart = 0, decided = 0, box_pairs_apart = 0, box_pairs_decided = 0;
  for (int i = 0; i < 20000; ++i) {
    Shape sa = Sphere{0.1}, sb = Sphere{0.1};
    collision::detail::Solid a{}, b{};
    random_shape(sa, a);
    random_shape(sb, b);
    // Tilted poses (the exact upright path of overlap() is not the reference here).
    const auto pa = pose({0, 0, 0}, angle(rng), angle(rng), angle(rng));
    const auto pb = pose({0.5 * unit(rng) - 0.25, 0.5 * unit(rng) - 0.25, 0.6 * unit(rng) - 0.3}, angle(rng), angle(rng), angle(rng));
    const bool overlaps = collision::overlap(sa, pa, sb, pb, 0.0).beyond_tolerance;
    const bool separated = collision::detail::separated(a, pa, b, pb);
    if (overlaps) {
      ++touching;
      EXPECT_FALSE(separated) << "pair " << i;
      continue;
    }
    ++apart;
    decided += separated;
    if (a.kind == collision::detail::Solid::Kind::box && b.kind == collision::detail::Solid::Kind::box) {
      ++box_pairs_apart;
      box_pairs_decided += separated;
    }
  }
  ASSERT_GT(touching, 1000);
  ASSERT_GT(apart, 1000);
  EXPECT_GT(decided, 0.8 * apart);
  // Two boxes: the separating axis test is exact, up to rounding at contact.
  EXPECT_GE(box_pairs_decided, box_pairs_apart - 2);
}

}  // namespace
}  // namespace cluttertamp
