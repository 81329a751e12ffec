#include "cli/command_line/command.hpp"

namespace cluttertamp::cli {

Command declare_self_collisions(CLI::App& app, CommonOptions& common) {
  auto args = std::make_shared<SelfCollisionArgs>();
  auto* self = app.add_subcommand(
      "self-collisions",
      "Count which pairs of a robot's links touch over random configurations; list those that never do, for disabled_collisions");
  add_package_paths(*self, common);
  self->add_option("robot", args->robot, "Robot description file")->required()->check(CLI::ExistingFile);
  self->add_option("--samples", args->samples, "Random configurations")->capture_default_str()->check(CLI::Range(100, 10000000));
  self->add_option("--seed", args->seed, "Seed of the configurations")->capture_default_str();
  self->add_option("--srdf", args->srdf,
                   "Also write an SRDF (MoveIt's format) whose disable_collisions are the adjacent pairs, the description's "
                   "disabled pairs and those that never touched; a description's srdf: key reads it back");
  add_verbosity(*self, args->verbosity, "Also list the pairs that never touched with their counts");
  return {self, [args] { return cli::self_collisions(*args); }};
}

}  // namespace cluttertamp::cli
