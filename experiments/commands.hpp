// The `sglab` command is a thin shell: each sub-command lives in its own file and registers
// itself on the CLI11 app through one add_*_command function listed in main.cpp.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace sglab::cli {

// Thrown by a command for bad input: main prints the message and exits with status 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// One registration function per sub-command, each defined in its own file.
void add_eval_command(CLI::App& app);  // eval_command.cpp: `sglab eval`
void add_fit_command(CLI::App& app);   // fit_command.cpp: `sglab fit` (issue 3)
void add_error_vs_time_command(CLI::App& app);  // error_vs_time.cpp: `sglab error-vs-time`
void add_reproduce_command(CLI::App& app);      // reproduce_command.cpp: `sglab reproduce`

// All of the above, on one app (main.cpp).
void add_all_commands(CLI::App& app);
// Runs one sglab command line (arguments without the program name) in-process, exactly as from
// the shell; returns the exit status. `sglab reproduce` runs its steps through this.
int run_sglab(std::vector<std::string> args);

}  // namespace sglab::cli
