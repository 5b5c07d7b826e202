// `sglab sweep KIND …`: the parent of every sweep. Each kind lives in its own file
// (sweep_KIND.cpp) on the shared runner of sweep.hpp and registers itself here with one line.
// All sweeps take --out DIR, --shard i/N, --threads N, and resume when interrupted; sharded
// outputs are joined by `sglab merge` (merge_command.cpp).
#include "commands.hpp"

namespace sglab::cli {

void add_sweep_command(CLI::App& app, const runner::RunContext& run) {
  auto* sweep = app.add_subcommand(
      "sweep", "Error sweeps over a grid (parallel; --shard i/N splits a sweep, `sglab merge` joins; resumes)");
  sweep->require_subcommand(1);
  // One line per sweep kind.
  add_sweep_specular(*sweep, run);
  add_sweep_render(*sweep, run);
}

}  // namespace sglab::cli
