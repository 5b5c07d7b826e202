// The --env NAME=MAP.exr arguments of `sglab envmap lobes` and `sglab envmap bases`: one check and
// one reader for both. A name is a table label and a CSV field, so a plain word, given once.
#pragma once

#include <string>
#include <vector>

#include "input_error.hpp"
#include "sglab/envmap.hpp"
#include "sglab/render/environment.hpp"
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

// One --env argument read: its name, its map's path and the map.
struct LoadedEnv {
  std::string name, path;
  EnvMap map;
};

// One --env NAME=MAP.exr argument (checked by check_env_arguments) with its map read (InputError
// naming the file when it is not a readable environment map).
inline LoadedEnv load_env_argument(const std::string& env) {
  const auto eq = env.find('=');
  try {
    return {env.substr(0, eq), env.substr(eq + 1), render::load_environment(env.substr(eq + 1))};
  } catch (const render::EnvironmentError& err) {
    throw runner::InputError(err.what());
  }
}

}  // namespace sglab::experiments
