// The `sglab` command is a thin shell: each general tool's sub-command lives in its own file in
// cli/ and registers itself on the CLI11 app through one add_*_command function listed in
// app.cpp; each experiment's own command comes from the experiment registry
// (experiments/registry.hpp).
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "input_error.hpp"  // runner::InputError: bad input, exit status 2
#include "run_context.hpp"
#include "run_sglab.hpp"  // run_sglab: one command line, in-process

namespace sglab::cli {

// One registration function per general tool, each defined in its own file.
void add_eval_command(CLI::App& app);                                  // eval_command.cpp: `sglab eval`
void add_fit_command(CLI::App& app, const runner::RunContext& run);    // fit_command.cpp: `sglab fit`
void add_reproduce_command(CLI::App& app);                             // reproduce_command.cpp: `sglab reproduce`
void add_render_command(CLI::App& app);                                // render_command.cpp: `sglab render`
void add_sweep_command(CLI::App& app, const runner::RunContext& run);  // sweep_command.cpp: `sglab sweep KIND`
void add_merge_command(CLI::App& app);   // merge_command.cpp: `sglab merge` (joins sweep shards)
void add_filter_command(CLI::App& app);  // filter_command.cpp: `sglab filter`
void add_envmap_command(
    CLI::App& app,
    const runner::RunContext& run);          // envmap_command.cpp: `sglab envmap make|render` (+ its experiments)
void add_export_command(CLI::App& app);      // export_command.cpp: `sglab export` (methods as shader code)
void add_fit_envmap_command(CLI::App& fit);  // envmap_command.cpp: `sglab fit envmap` (called by add_fit_command)

// All of the above and every registered experiment's command, on one app, each run in `run`; the
// help lists the experiments (app.cpp).
void add_all_commands(CLI::App& app, const runner::RunContext& run);

}  // namespace sglab::cli
