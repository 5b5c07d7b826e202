// `sglab sweep KIND …`: the parent of every sweep. Each kind is an experiment in its own file
// (experiments/sweep_KIND.cpp, on the shared runner of sweep.hpp) registered with `under` "sweep".
// All sweeps take --out DIR, --shard i/N, --threads N, and resume when interrupted; sharded
// outputs are joined by `sglab merge` (merge_command.cpp).
#include "commands.hpp"
#include "registry.hpp"

namespace sglab::cli {

void add_sweep_command(CLI::App& app, const runner::RunContext& run) {
  auto* sweep = app.add_subcommand(
      "sweep", "Error sweeps over a grid (parallel; --shard i/N splits a sweep, `sglab merge` joins; resumes)");
  sweep->require_subcommand(1);
  experiments::add_experiment_commands(*sweep, "sweep", run);
}

}  // namespace sglab::cli
