// What an experiment's own `sglab` command needs: CLI11, and the runner's input error (bad input:
// the message names the value, exit status 2). The command registers itself through the
// experiment registry (registry.hpp), not through cli/.
#pragma once

#include <CLI/CLI.hpp>

#include "input_error.hpp"
