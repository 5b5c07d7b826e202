// The runner's error for bad input (a malformed file, an option value out of range, an output
// that would destroy data): the message names the value. The `sglab` command prints it and exits
// with status 2, writing nothing; the Python module raises it as a ValueError.
#pragma once

#include <stdexcept>

namespace sglab::runner {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace sglab::runner
