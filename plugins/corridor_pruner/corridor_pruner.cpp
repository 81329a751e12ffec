// corridor: a baseline object pruner. The target is pulled straight out to its exit
// pose x_s; every object whose footprint meets the corridor its footprint sweeps (and
// everything stacked on such an object) must be removed first. Cheap and exact for
// that one straight path; a planner that may go around objects (retrieval_graph)
// finds removal sets that are never larger.
#include <algorithm>
#include <cmath>
#include <set>

#include "cluttertamp/plugin/export.hpp"
#include "cluttertamp/plugin/object_pruner.hpp"

namespace {

using namespace cluttertamp;

class CorridorPruner final : public plugin::ObjectPruner {
 public:
  void configure(const Parameters& parameters) override {
    finger_thickness_ = parameters.get_double("finger_thickness", finger_thickness_,
                                              "m added to the target's radius for the corridor's half width (r_f)",
                                              Range::at_least(0));
  }

  plugin::PruneAnswer prune(plugin::PlanningContext& context, const WorldState& state) override {
    const Scene& scene = context.scene();
    const ObjectIndex target = scene.target;
    const Eigen::Vector2d start = state.world_T_objects[target].translation().head<2>();
    const Eigen::Vector2d exit = scene.world_T_exit.translation().head<2>();
    // r_b = r_g + r_f (Tian et al., Appendix B) for a gripper without a large base.
    const double r_b = footprint_radius(scene.objects[target].shape, scene.objects[target].world_T_object) + finger_thickness_;
    const Eigen::AlignedBox3d target_bounds = world_bounds(scene.objects[target].shape, state.world_T_objects[target]);

    std::vector<std::pair<double, ObjectIndex>> in_corridor;  // (distance from exit, object)
    for (ObjectIndex i = 0; i < scene.objects.size(); ++i) {
      if (i == target || state.removed[i]) continue;
      context.count(counter::collision_checks);
      const Eigen::AlignedBox3d bounds = world_bounds(scene.objects[i].shape, state.world_T_objects[i]);
      const bool same_level = bounds.min().z() < target_bounds.max().z() - 1e-6 &&
                              bounds.max().z() > target_bounds.min().z() + 1e-6;
      const Eigen::Vector2d centre = state.world_T_objects[i].translation().head<2>();
      const double r = footprint_radius(scene.objects[i].shape, scene.objects[i].world_T_object);
      if (same_level && distance_to_segment(centre, start, exit) < r_b + r) {
        in_corridor.emplace_back((centre - exit).norm(), i);
      }
    }
    std::sort(in_corridor.begin(), in_corridor.end());

    plugin::PruneAnswer answer;
    std::vector<ObjectIndex> sequence;
    std::set<ObjectIndex> placed;
    for (const auto& [distance, object] : in_corridor) add_with_load(scene, state, object, sequence, placed);
    std::vector<ObjectIndex> fixed;
    for (ObjectIndex i : sequence) {
      if (!scene.objects[i].movable) fixed.push_back(i);
    }
    if (!fixed.empty()) {
      answer.failure = Failure{"object_pruner", "fixed objects block the straight corridor to the exit", fixed};
      return answer;
    }
    answer.removal_sequences.push_back(sequence);
    return answer;
  }

 private:
  // Appends `object` after everything resting on it (which must go first).
  static void add_with_load(const Scene& scene, const WorldState& state, ObjectIndex object,
                            std::vector<ObjectIndex>& sequence, std::set<ObjectIndex>& placed) {
    if (placed.count(object)) return;
    placed.insert(object);
    for (ObjectIndex above = 0; above < scene.objects.size(); ++above) {
      const auto& supports = scene.objects[above].supports;
      if (!state.removed[above] && std::find(supports.begin(), supports.end(), object) != supports.end()) {
        add_with_load(scene, state, above, sequence, placed);
      }
    }
    sequence.push_back(object);
  }

  double finger_thickness_ = 0.012;  // m, the AG-95 finger model of domains/robots/ur10_ag95.urdf
};

}  // namespace

CLUTTERTAMP_EXPORT_OBJECT_PRUNER(CorridorPruner, corridor,
                                 "Objects in the target's straight pull-out corridor, stacked loads first", "1.0.0")
