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
