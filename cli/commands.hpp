// The `sglab` command is a thin shell: each sub-command lives in its own file and registers
// itself on the CLI11 app through one add_*_command function listed in main.cpp.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "input_error.hpp"  // UsageError: bad input, exit status 2

namespace sglab::cli {

// One registration function per sub-command, each defined in its own file.
void add_eval_command(CLI::App& app);  // eval_command.cpp: `sglab eval`
void add_fit_command(CLI::App& app);   // fit_command.cpp: `sglab fit`
void add_error_vs_time_command(CLI::App& app);  // error_vs_time.cpp: `sglab error-vs-time`
void add_reproduce_command(CLI::App& app);      // reproduce_command.cpp: `sglab reproduce`
void add_render_command(CLI::App& app);         // render_command.cpp: `sglab render`
void add_stability_command(CLI::App& app);      // stability.cpp: `sglab stability`
void add_error_map_command(CLI::App& app);      // error_map.cpp: `sglab error-map`
void add_sweep_command(CLI::App& app);          // sweep_command.cpp: `sglab sweep KIND`
void add_merge_command(CLI::App& app);          // merge_command.cpp: `sglab merge` (joins sweep shards)
void add_filter_command(CLI::App& app);         // filter_command.cpp: `sglab filter`
void add_filter_sweep_command(CLI::App& app);   // filter_sweep.cpp: `sglab filter-sweep`
void add_near_wall_command(CLI::App& app);      // near_wall.cpp: `sglab near-wall` (the 2022 poster's figure)
void add_poster_plots_command(CLI::App& app);   // poster_plots.cpp: `sglab poster-plots` (the 2022 poster's plots)
void add_vsgl_fis_bias_command(CLI::App& app);  // vsgl_fis_bias.cpp: `sglab vsgl-fis-bias`
void add_envmap_command(CLI::App& app);         // envmap_command.cpp: `sglab envmap make|render|lobes`
void add_fit_envmap_command(CLI::App& fit);     // envmap_command.cpp: `sglab fit envmap` (called by add_fit_command)
// One registration function per sweep kind, called by add_sweep_command on the `sweep` sub-command.
void add_sweep_specular(CLI::App& sweep);       // sweep_specular.cpp: `sglab sweep specular`
void add_sweep_render(CLI::App& sweep);         // sweep_render.cpp: `sglab sweep render`

// All of the above, on one app (main.cpp).
void add_all_commands(CLI::App& app);
// Runs one sglab command line (arguments without the program name) in-process, exactly as from
// the shell; returns the exit status. `sglab reproduce` runs its steps through this.
int run_sglab(std::vector<std::string> args);

}  // namespace sglab::cli
