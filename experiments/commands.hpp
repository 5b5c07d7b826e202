// The `sglab` command is a thin shell: each sub-command lives in its own file and registers
// itself on the CLI11 app through one add_*_command function listed in main.cpp.
#pragma once

#include <CLI/CLI.hpp>

namespace sglab::cli {

// Thrown by a command for bad input: main prints the message and exits with status 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace sglab::cli
