// `sglab`: the command-line front of the toolkit. Parses arguments and calls core/, fit/ and the
// experiments; computes nothing itself.
#include <algorithm>
#include <cstdio>
#include <exception>

#include "commands.hpp"

namespace sglab::cli {

// One line per sub-command (each defined in its own file).
void add_all_commands(CLI::App& app) {
  add_eval_command(app);
  add_fit_command(app);
  add_error_vs_time_command(app);
  add_reproduce_command(app);
  add_stability_command(app);
  add_error_map_command(app);
  add_render_command(app);
  add_sweep_command(app);
  add_merge_command(app);
  add_filter_command(app);
  add_filter_sweep_command(app);
  add_near_wall_command(app);
  add_poster_plots_command(app);
  add_vsgl_fis_bias_command(app);
  add_envmap_command(app);
}

int run_sglab(std::vector<std::string> args) {
  CLI::App app{"sglab: spherical Gaussian lighting research toolkit"};
  app.require_subcommand(1);
  add_all_commands(app);
  try {
    std::reverse(args.begin(), args.end());  // CLI11 takes the vector form last-argument-first
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "sglab: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sglab: error: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace sglab::cli

int main(int argc, char** argv) {
  return sglab::cli::run_sglab(std::vector<std::string>(argv + 1, argv + argc));
}
