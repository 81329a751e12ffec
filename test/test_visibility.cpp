// The visibility model (Tian et al., Section V-A) on a hand-built scene: which objects
// the camera sees, what hides the others, and what one removal reveals.
#include <gtest/gtest.h>

#include <stdexcept>

#include "cluttertamp/perception/visibility.hpp"

namespace cluttertamp {
namespace {

using perception::ObservedWorld;
using perception::VisibilityModel;

SceneObject cylinder(const std::string& id, double x, double y, double radius) {
  SceneObject o;
  o.id = id;
  o.shape = Cylinder{radius, 0.3};
  o.world_T_object = Eigen::Translation3d(x, y, 0.5);
  o.mass = 0.3;
  return o;
}

// A camera at (0, 0, 0.5) looking along +x at the height of the objects' centres: its
// optical z is world x, its x (right) world -y, its y (down) world -z.
//   front  at (1.0, 0)    r 5 cm: in plain view
//   behind at (1.4, 0)    r 4 cm: straight behind `front`, hidden by it
//   side   at (1.2, 0.4)  r 4 cm: in plain view
//   away   at (0.2, 1.5)  r 4 cm: 82 degrees off the axis, out of the view
//   walled at (1.5, -0.5) r 4 cm: behind a fixed panel
Scene occlusion_scene() {
  Scene s;
  s.name = "occlusion";
  s.objects = {cylinder("front", 1.0, 0.0, 0.05), cylinder("behind", 1.4, 0.0, 0.04), cylinder("side", 1.2, 0.4, 0.04),
               cylinder("away", 0.2, 1.5, 0.04), cylinder("walled", 1.5, -0.5, 0.04)};
  s.target = 1;
  s.fixed.push_back({"panel", Box{{0.02, 0.3, 0.6}}, Eigen::Isometry3d(Eigen::Translation3d(1.2, -0.4, 0.5)), {}});
  Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();
  camera.translation() = Eigen::Vector3d(0, 0, 0.5);
  camera.linear() << 0, 0, 1,  //
      -1, 0, 0,                //
      0, -1, 0;
  s.world_T_camera = camera;
  return s;
}

TEST(Visibility, TheCameraSeesWhatIsInViewAndNamesWhatHidesTheRest) {
  const Scene scene = occlusion_scene();
  const VisibilityModel model(scene);
  const auto views = model.look(WorldState::initial(scene));
  ASSERT_EQ(views.size(), 5u);
  EXPECT_TRUE(views[0].observed);
  EXPECT_DOUBLE_EQ(views[0].visible_fraction, 1.0);
  EXPECT_TRUE(views[0].occluders.empty());

  EXPECT_FALSE(views[1].observed);
  EXPECT_DOUBLE_EQ(views[1].visible_fraction, 0.0);  // wholly behind `front`: a smaller, farther cylinder
  EXPECT_EQ(views[1].occluders, std::vector<ObjectIndex>{0});

  EXPECT_TRUE(views[2].observed);
  EXPECT_FALSE(views[3].observed);  // out of the field of view: hidden by nothing
  EXPECT_DOUBLE_EQ(views[3].visible_fraction, 0.0);
  EXPECT_TRUE(views[3].occluders.empty());
  EXPECT_FALSE(views[4].observed);  // behind fixed geometry, which is no object
  EXPECT_TRUE(views[4].occluders.empty());
  EXPECT_EQ(model.observed(WorldState::initial(scene)), (std::vector<ObjectIndex>{0, 2}));
}

TEST(Visibility, RemovingTheFrontObjectRevealsWhatItHidAndOnlyThat) {
  const Scene scene = occlusion_scene();
  ObservedWorld world(scene, WorldState::initial(scene));
  EXPECT_EQ(world.known_objects(), (std::vector<bool>{true, false, true, false, false}));
  const WorldState belief = world.belief();
  EXPECT_TRUE(belief.removed[1]);  // unknown objects are not in the planner's world
  EXPECT_FALSE(belief.removed[0]);

  EXPECT_EQ(world.remove(0), std::vector<ObjectIndex>{1});
  EXPECT_TRUE(world.known(1));
  EXPECT_TRUE(world.truth().removed[0]);
  EXPECT_FALSE(world.belief().removed[1]);
  EXPECT_TRUE(world.remove(2).empty());  // `away` and `walled` stay hidden
  EXPECT_FALSE(world.known(3));
}

TEST(Visibility, PartlyHiddenObjectsCountByTheirVisibleShareAndTheThresholdDecides) {
  Scene scene = occlusion_scene();
  scene.objects[1].world_T_object = Eigen::Translation3d(1.4, 0.06, 0.5);  // peeks out to the left of `front`
  const auto views = VisibilityModel(scene).look(WorldState::initial(scene));
  EXPECT_GT(views[1].visible_fraction, 0.0);
  EXPECT_LT(views[1].visible_fraction, 1.0);
  EXPECT_EQ(views[1].occluders, std::vector<ObjectIndex>{0});
  perception::VisibilitySettings strict;
  strict.min_visible_fraction = std::min(1.0, views[1].visible_fraction + 0.01);
  EXPECT_FALSE(VisibilityModel(scene, strict).look(WorldState::initial(scene))[1].observed);
  perception::VisibilitySettings lenient;
  lenient.min_visible_fraction = views[1].visible_fraction;
  EXPECT_TRUE(VisibilityModel(scene, lenient).look(WorldState::initial(scene))[1].observed);
}

TEST(Visibility, ASceneWithoutACameraIsRefused) {
  Scene scene = occlusion_scene();
  scene.world_T_camera.reset();
  EXPECT_THROW(VisibilityModel{scene}, std::invalid_argument);
}

}  // namespace
}  // namespace cluttertamp
