// run_sglab alone, for main.cpp: the whole app is behind it, and the CLI11 headers (about 5 CPU s
// of compilation per unit that includes them) stay in the units that build the app (commands.hpp).
#pragma once

#include <string>
#include <vector>

#include "run_context.hpp"

namespace sglab::cli {

// Runs one sglab command line (arguments without the program name) in-process, exactly as from
// the shell, in `run` (main: a plain run); returns the exit status. `sglab reproduce` runs its
// steps through this in its mode, `sglab merge` a sweep's summary.
int run_sglab(std::vector<std::string> args, const runner::RunContext& run = {});

}  // namespace sglab::cli
