// `sglab sweep KIND …`: the parent of every sweep. Each kind is an experiment in its own file
// (experiments/sweep_KIND.cpp, on the shared runner of sweep.hpp) registered with `under` "sweep".
// All sweeps take --out DIR, --shard i/N, --threads N, and resume when interrupted; sharded
// outputs are joined by `sglab merge` (merge_command.cpp).
#include "commands.hpp"
#include "constant_sets.hpp"
#include "registry.hpp"

#include <cstdio>
#include <memory>

namespace sglab::cli {

void add_sweep_command(CLI::App& app) {
  auto* sweep = app.add_subcommand(
      "sweep", "Error sweeps over a grid (parallel; --shard i/N splits a sweep, `sglab merge` joins; resumes)");
  sweep->require_subcommand(1);
  experiments::add_experiment_commands(*sweep, "sweep");
  // No specular method has a fitted constant: the set is validated (exit 2 on a bad one) and said
  // to be unused.
  if (auto* specular = sweep->get_subcommand("specular")) {
    auto paths = std::make_shared<std::vector<std::string>>();
    add_constants_option(*specular, *paths);
    specular->parse_complete_callback([paths] {
      if (paths->empty()) return;
      load_constant_sets(*paths);
      std::fprintf(stderr, "sweep specular: --constants validated; no specular method reads a fitted constant, so "
                           "every value is the published one\n");
    });
  }
}

}  // namespace sglab::cli
