#include "cluttertamp/stream/scene_facts.hpp"

#include "cluttertamp/pddl/sexpr.hpp"

#include <algorithm>

namespace cluttertamp::stream {

namespace {

pddl::Atom atom(const std::string& predicate, std::vector<std::string> args) {
  pddl::Atom a;
  a.predicate = predicate;
  for (std::string& name : args) a.args.push_back({std::move(name), false, {}});
  return a;
}

}  // namespace

SceneProblem scene_problem(const Scene& scene, const std::vector<bool>& movable, const std::string& domain_name) {
  SceneProblem out;
  pddl::Problem& p = out.problem;
  p.name = pddl::lower_name(scene.name.empty() ? "scene" : scene.name);
  p.domain_name = domain_name;
  p.file = "(derived from scene '" + scene.name + "')";
  auto declare = [&](const std::string& name) {
    if (std::any_of(p.objects.begin(), p.objects.end(), [&](const pddl::TypedName& o) { return o.name == name; })) {
      throw InputError({p.file, 0, 0}, "two names of the scene become '" + name + "' in PDDL, which ignores case");
    }
    p.objects.push_back({name, {"object"}, {}});
  };
  std::vector<std::string> names;
  for (ObjectIndex i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    const std::string name = pddl::lower_name(o.id), pose = "p0-" + name;
    names.push_back(name);
    declare(name);
    declare(pose);
    out.objects[name] = i;
    out.values[pose] = o.world_T_object;
    if (i != scene.target && i < movable.size() && !movable[i]) continue;  // an obstacle: fixed geometry to the streams
    p.init.push_back(atom("object", {name}));
    p.init.push_back(atom("pose", {name, pose}));
    p.init.push_back(atom("atpose", {name, pose}));
  }
  for (ObjectIndex i = 0; i < scene.objects.size(); ++i) {
    for (ObjectIndex s : scene.objects[i].supports) p.init.push_back(atom("on", {names[i], names[s]}));
  }
  for (const Region& r : scene.regions) {
    declare(pddl::lower_name(r.id));
    p.init.push_back(atom("region", {pddl::lower_name(r.id)}));
  }
  p.init.push_back(atom("handempty", {}));
  p.goal.kind = pddl::Formula::Kind::atom;
  p.goal.atom = atom("holding", {names.at(scene.target)});
  return out;
}

}  // namespace cluttertamp::stream
