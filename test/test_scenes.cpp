// Generated shelf scenes and the scene writer: round trips through the validator.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>

#include <gtest/gtest.h>

#include "cluttertamp/io/scene_io.hpp"
#include "cluttertamp/perception/visibility.hpp"
#include "cluttertamp/scenes/shelf_generator.hpp"
#include "test_support.hpp"

namespace cluttertamp {
namespace {

void expect_same(const Scene& a, const Scene& b) {
  ASSERT_EQ(a.objects.size(), b.objects.size());
  ASSERT_EQ(a.fixed.size(), b.fixed.size());
  ASSERT_EQ(a.regions.size(), b.regions.size());
  EXPECT_EQ(a.target, b.target);
  EXPECT_EQ(a.name, b.name);
  for (std::size_t i = 0; i < a.objects.size(); ++i) {
    EXPECT_EQ(a.objects[i].id, b.objects[i].id);
    EXPECT_TRUE(a.objects[i].world_T_object.isApprox(b.objects[i].world_T_object, 1e-9));
    EXPECT_EQ(a.objects[i].shape.index(), b.objects[i].shape.index());
    EXPECT_NEAR(a.objects[i].mass, b.objects[i].mass, 1e-12);
    EXPECT_EQ(a.objects[i].supports, b.objects[i].supports);
    EXPECT_EQ(a.objects[i].movable, b.objects[i].movable);
  }
  for (std::size_t i = 0; i < a.fixed.size(); ++i) {
    EXPECT_TRUE(a.fixed[i].world_T_body.isApprox(b.fixed[i].world_T_body, 1e-9));
  }
  EXPECT_TRUE(a.world_T_exit.isApprox(b.world_T_exit, 1e-9));
  ASSERT_EQ(a.world_T_camera.has_value(), b.world_T_camera.has_value());
  if (a.world_T_camera) EXPECT_TRUE(a.world_T_camera->isApprox(*b.world_T_camera, 1e-9));
}

TEST(ShelfGenerator, ScenesPassValidationAndRoundTrip) {
  const auto dir = std::filesystem::temp_directory_path() / "cluttertamp_scenes";
  for (int objects : {12, 16, 20}) {
    for (std::uint64_t seed : {1u, 2u, 3u}) {
      scenes::ShelfSpec spec;
      spec.objects = objects;
      const Scene scene = scenes::generate_shelf_scene(spec, seed);
      ASSERT_EQ(scene.objects.size(), static_cast<std::size_t>(objects));
      const auto file = dir / (scene.name + ".yaml");
      io::write_scene(file, scene);
      Scene loaded;
      ASSERT_NO_THROW(loaded = io::load_scene(file)) << io::scene_to_yaml(scene);
      expect_same(scene, loaded);
      // Writing what was read gives the same text.
      EXPECT_EQ(io::scene_to_yaml(loaded), io::scene_to_yaml(scene));
    }
  }
  std::filesystem::remove_all(dir);
}

// The paper's recipe keeps no gap: any collision-free placement, so that over a few
// 20-object shelves some neighbours stand closer than the 1 cm --min-gap 0.01 keeps;
// none overlaps, none reaches into a wall.
TEST(ShelfGenerator, WithoutAMinimumGapNeighboursMayStandCloseButNeverOverlap) {
  double closest = 1.0;
  for (std::uint64_t seed : {1u, 2u, 3u, 4u}) {
    scenes::ShelfSpec spec;
    spec.objects = 20;
    ASSERT_EQ(spec.min_gap, 0.0);
    const Scene scene = scenes::generate_shelf_scene(spec, seed);
    const Eigen::Vector3d size = scenes::cabinet_size(spec);
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
      const Eigen::Vector2d a = scene.objects[i].world_T_object.translation().head<2>();
      const double ra = std::get<Cylinder>(scene.objects[i].shape).radius;
      EXPECT_LE(std::abs(a.y()) + ra, size.y() / 2 + 1e-9);
      EXPECT_GE(a.x() - ra, spec.front - 1e-9);
      EXPECT_LE(a.x() + ra, spec.front + size.x() + 1e-9);
      for (std::size_t j = 0; j < i; ++j) {
        const double gap = (a - scene.objects[j].world_T_object.translation().head<2>()).norm() - ra -
                           std::get<Cylinder>(scene.objects[j].shape).radius;
        EXPECT_GE(gap, 0.0);
        closest = std::min(closest, gap);
      }
    }
  }
  EXPECT_LT(closest, 0.01);
}

TEST(ShelfGenerator, SameSeedSameSceneOtherSeedOtherScene) {
  scenes::ShelfSpec spec;
  spec.objects = 16;
  EXPECT_EQ(io::scene_to_yaml(scenes::generate_shelf_scene(spec, 5)), io::scene_to_yaml(scenes::generate_shelf_scene(spec, 5)));
  EXPECT_NE(io::scene_to_yaml(scenes::generate_shelf_scene(spec, 5)), io::scene_to_yaml(scenes::generate_shelf_scene(spec, 6)));
}

TEST(ShelfGenerator, CabinetSizesFollowThePaper) {
  scenes::ShelfSpec spec;
  spec.objects = 12;
  EXPECT_TRUE(scenes::cabinet_size(spec).isApprox(Eigen::Vector3d(0.6, 0.9, 0.5)));
  spec.objects = 20;
  EXPECT_TRUE(scenes::cabinet_size(spec).isApprox(Eigen::Vector3d(0.7, 1.2, 0.5)));
}

// x_s stands exit_distance in front of the opening, on the centre line, at the
// cylinders' mid-height.
TEST(ShelfGenerator, TheExitStandsInFrontOfTheOpening) {
  scenes::ShelfSpec spec;
  for (const double distance : {0.2, 0.1}) {
    spec.exit_distance = distance;
    const Scene scene = scenes::generate_shelf_scene(spec, 1);
    EXPECT_TRUE(scene.world_T_exit.translation().isApprox(
        Eigen::Vector3d(spec.front - distance, 0, spec.floor_height + (spec.height_min + spec.height_max) / 4), 1e-12))
        << scene.world_T_exit.translation().transpose();
  }
}

// Occlusion shelves drawn as Table I's (the paper's Table II scenes): the camera at the
// front cannot see the target, which is the hidden object nearest the middle of the back
// wall; the scene round-trips and the seed decides it.
TEST(OcclusionGenerator, RandomLayoutHidesTheTargetNearestTheBackMiddle) {
  for (int objects : {12, 20}) {
    for (std::uint64_t seed : {1u, 2u, 3u}) {
      scenes::OcclusionSpec spec;
      spec.layout = scenes::OcclusionLayout::random;
      spec.objects = objects;
      const Scene scene = scenes::generate_occlusion_scene(spec, seed);
      const std::string where = scene.name;
      ASSERT_EQ(scene.objects.size(), static_cast<std::size_t>(objects)) << where;
      EXPECT_EQ(scene.objects[scene.target].id, "target") << where;
      const std::vector<ObjectIndex> seen = perception::VisibilityModel(scene).observed(WorldState::initial(scene));
      EXPECT_FALSE(seen.empty()) << where;
      EXPECT_EQ(std::count(seen.begin(), seen.end(), scene.target), 0) << where;
      const Eigen::Vector2d back(spec.front + scenes::cabinet_size({.objects = objects}).x(), 0.0);
      auto distance = [&](ObjectIndex o) { return (scene.objects[o].world_T_object.translation().head<2>() - back).norm(); };
      for (ObjectIndex o = 0; o < scene.objects.size(); ++o) {
        if (std::count(seen.begin(), seen.end(), o) == 0) EXPECT_LE(distance(scene.target), distance(o)) << where;
      }
      std::set<std::string> ids;
      for (const SceneObject& o : scene.objects) ids.insert(o.id);
      EXPECT_EQ(ids.size(), scene.objects.size()) << where;
      expect_same(scene, scenes::generate_occlusion_scene(spec, seed));
      const auto file = std::filesystem::temp_directory_path() / (where + ".yaml");
      io::write_scene(file, scene);
      expect_same(scene, io::load_scene(file));
      std::filesystem::remove(file);
    }
  }
}

// The columns layout: the camera sees the front row and nothing behind it.
TEST(OcclusionGenerator, ColumnsLayoutShowsOnlyTheFrontRow) {
  scenes::OcclusionSpec spec;
  spec.columns = 4;
  const Scene scene = scenes::generate_occlusion_scene(spec, 7);
  ASSERT_EQ(scene.objects.size(), 16u);
  const std::vector<ObjectIndex> seen = perception::VisibilityModel(scene).observed(WorldState::initial(scene));
  EXPECT_EQ(seen, (std::vector<ObjectIndex>{0, 4, 8, 12}));
}

TEST(SceneWriter, RoundTripsStackedBoxesAndRotations) {
  const Scene scene = io::load_scene(test::data("scenes/good.yaml"));
  const auto file = std::filesystem::temp_directory_path() / "cluttertamp_good_roundtrip.yaml";
  io::write_scene(file, scene);
  expect_same(scene, io::load_scene(file));
  const Scene lying = io::load_scene(test::data("scenes/good_lying_cylinder.yaml"));
  io::write_scene(file, lying);
  expect_same(lying, io::load_scene(file));
  std::filesystem::remove(file);
}


// The mobile manipulation table (Tian et al., Fig. 9): every object on the top, none
// overlapping, the target in the middle; the same seed gives the same table.
TEST(TableGenerator, ObjectsStandOnTheTopApartWithTheTargetInTheMiddle) {
  scenes::TableSpec spec;
  const Scene scene = scenes::generate_table_scene(spec, 4);
  ASSERT_EQ(scene.objects.size(), 20u);
  const Eigen::Vector2d centre(spec.distance + spec.size / 2, 0.0);
  EXPECT_TRUE(scene.objects[scene.target].world_T_object.translation().head<2>().isApprox(centre));
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const Eigen::AlignedBox3d b = world_bounds(scene.objects[i].shape, scene.objects[i].world_T_object);
    EXPECT_NEAR(b.min().z(), spec.top_height, 1e-9);
    EXPECT_GE(b.min().x(), spec.distance - 1e-9);
    EXPECT_LE(b.max().x(), spec.distance + spec.size + 1e-9);
    EXPECT_LE(std::abs(b.min().y()), spec.size / 2 + 1e-9);
    EXPECT_LE(std::abs(b.max().y()), spec.size / 2 + 1e-9);
    for (std::size_t j = 0; j < i; ++j) {
      const double gap = (scene.objects[i].world_T_object.translation() - scene.objects[j].world_T_object.translation()).head<2>().norm() -
                         footprint_radius(scene.objects[i].shape, scene.objects[i].world_T_object) -
                         footprint_radius(scene.objects[j].shape, scene.objects[j].world_T_object);
      EXPECT_GE(gap, spec.min_gap - 1e-9) << scene.objects[i].id << " " << scene.objects[j].id;
    }
  }
  const auto file = std::filesystem::temp_directory_path() / "cluttertamp_table.yaml";
  io::write_scene(file, scene);
  EXPECT_NO_THROW(io::load_scene(file));
  EXPECT_EQ(io::scene_to_yaml(scene), io::scene_to_yaml(scenes::generate_table_scene(spec, 4)));
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace cluttertamp
