#include "cluttertamp/core/scene.hpp"

#include <algorithm>

#include "cluttertamp/core/problem.hpp"
#include "cluttertamp/core/world_state.hpp"

namespace cluttertamp {

std::optional<ObjectIndex> Scene::find_object(std::string_view id) const {
  for (std::size_t i = 0; i < objects.size(); ++i) {
    if (objects[i].id == id) return static_cast<ObjectIndex>(i);
  }
  return std::nullopt;
}

const Region* Scene::find_region(std::string_view id) const {
  for (const Region& region : regions) {
    if (region.id == id) return &region;
  }
  return nullptr;
}

void Scene::mark_what_rests_on(std::vector<bool>& marked) const {
  for (bool grew = true; grew;) {
    grew = false;
    for (ObjectIndex o = 0; o < objects.size(); ++o) {
      const auto& below = objects[o].supports;
      if (!marked[o] && std::any_of(below.begin(), below.end(), [&](ObjectIndex b) { return marked[b]; })) {
        marked[o] = grew = true;
      }
    }
  }
}

WorldState WorldState::initial(const Scene& scene) {
  WorldState state;
  state.world_T_objects.reserve(scene.objects.size());
  for (const SceneObject& object : scene.objects) state.world_T_objects.push_back(object.world_T_object);
  state.removed.assign(scene.objects.size(), false);
  return state;
}

}  // namespace cluttertamp
