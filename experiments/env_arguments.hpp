// The --env NAME=MAP.exr arguments of `sglab envmap lobes` and `sglab envmap bases`: one check for
// both. A name is a table label and a CSV field, so a plain word, given once.
#pragma once

#include <string>
#include <vector>

#include "input_error.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::experiments {

// Throws InputError naming the argument: no '=' or an empty NAME, a NAME that is not 1–64 letters,
// digits, '_', '.', '+' or '-' (a comma, quote or newline would break the CSV), a NAME given twice.
inline void check_env_arguments(const std::vector<std::string>& envs) {
  for (std::size_t i = 0; i < envs.size(); ++i) {
    const auto eq = envs[i].find('=');
    if (eq == std::string::npos || eq + 1 == envs[i].size())
      throw runner::InputError("--env " + quote(envs[i]) + " must be NAME=MAP.exr");
    const std::string name = envs[i].substr(0, eq);
    if (name.empty() || name.size() > 64 ||
        name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.+-") !=
            std::string::npos)
      throw runner::InputError("--env " + quote(envs[i]) + ": NAME must be 1–64 letters, digits, '_', '.', '+' or '-'");
    for (std::size_t j = 0; j < i; ++j)
      if (envs[j].substr(0, envs[j].find('=')) == name)
        throw runner::InputError("--env: the name " + quote(name) + " is given twice");
  }
}

}  // namespace sglab::experiments
