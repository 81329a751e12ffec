// `cluttertamp observe`: what the scene's camera sees (perception::VisibilityModel),
// optionally after taking some objects away, to check an occlusion scene by hand.
#include <iomanip>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cluttertamp/io/problem_io.hpp"
#include "cluttertamp/io/scene_io.hpp"
#include "cluttertamp/perception/visibility.hpp"

namespace cluttertamp::cli {

int observe(const ObserveArgs& args) {
  const Scene scene = io::detect_file_kind(args.file) == io::FileKind::problem ? io::load_problem(args.file).scene
                                                                                 : io::load_scene(args.file);
  if (!scene.world_T_camera) throw InputError({args.file.string(), 0, 0}, "the scene has no camera (camera: in the scene file)");
  WorldState state = WorldState::initial(scene);
  for (const std::string& id : args.remove) {
    const auto o = scene.find_object(id);
    if (!o) throw InputError({"--remove", 0, 0}, "no object '" + id + "' in scene " + scene.name);
    state.removed[*o] = true;
  }
  perception::VisibilitySettings settings;
  settings.min_visible_fraction = args.min_visible_fraction;
  const perception::VisibilityModel model(scene, settings);
  const std::vector<perception::ObjectView> views = model.look(state);
  if (args.json) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const perception::ObjectView& v : views) {
      if (state.removed[v.object]) continue;
      nlohmann::ordered_json occluders = nlohmann::ordered_json::array();
      for (ObjectIndex o : v.occluders) occluders.push_back(scene.objects[o].id);
      out.push_back({{"object", scene.objects[v.object].id}, {"observed", v.observed},
                     {"visible_fraction", v.visible_fraction}, {"occluders", occluders}});
    }
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  int seen = 0;
  for (const perception::ObjectView& v : views) {
    if (state.removed[v.object]) continue;
    seen += v.observed ? 1 : 0;
    std::cout << "  " << std::left << std::setw(12) << scene.objects[v.object].id << std::setw(10)
              << (v.observed ? "observed" : "hidden") << std::right << std::fixed << std::setprecision(0) << std::setw(4)
              << 100 * v.visible_fraction << " % visible";
    if (!v.occluders.empty()) {
      std::cout << "  behind";
      for (ObjectIndex o : v.occluders) std::cout << " " << scene.objects[o].id;
    }
    if (v.object == scene.target) std::cout << "  TARGET";
    std::cout << "\n";
  }
  std::cout << seen << " of " << views.size() - std::count(state.removed.begin(), state.removed.end(), true)
            << " objects observed (at least " << std::setprecision(0) << 100 * settings.min_visible_fraction
            << " % of the surface facing the camera in view)\n";
  return 0;
}

}  // namespace cluttertamp::cli
