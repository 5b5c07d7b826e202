#include "registry.hpp"

#include <utility>

namespace sglab::experiments {

const std::vector<Experiment>& experiment_registry() {
#define SGLAB_LIST_EXPERIMENT(name) name##_experiment(),
  static const std::vector<Experiment> all = {SGLAB_EXPERIMENTS(SGLAB_LIST_EXPERIMENT)};
#undef SGLAB_LIST_EXPERIMENT
  return all;
}

void add_experiment_commands(CLI::App& parent, std::string_view under, const runner::RunContext& run) {
  for (const auto& e : experiment_registry())
    if (e.add_command && e.under == under) e.add_command(parent, run);
}

Step sglab_step(std::string name, std::string what, std::vector<std::string> args, std::vector<std::string> quick_args,
                bool takes_constants) {
  return {std::move(name), std::move(what), std::move(args), std::move(quick_args), false, takes_constants};
}

Step timed(Step s) {
  s.timed = true;
  return s;
}

Step plot_step(std::string name, std::string what, std::vector<std::string> args, std::vector<std::string> quick_args) {
  return {std::move(name), std::move(what), std::move(args), std::move(quick_args), true, false};
}

// `sglab render SCENE` with its stats JSON and pixel CSV under OUT/renders/BASE.*.
Step render_step(const runner::Places& p, std::string name, std::string what, const std::string& scene,
                 const std::string& base, int width, int height, std::vector<std::string> quick,
                 std::vector<std::string> extra) {
  const std::string path = p.dir(kRendersDir) + "/" + base;
  std::vector<std::string> args = {"render", scene};
  args.insert(args.end(), extra.begin(), extra.end());
  args.insert(args.end(), {"--out", path + ".exr", "--stats", path + ".json", "--dump-csv", path + ".csv", "--width",
                           std::to_string(width), "--height", std::to_string(height)});
  return sglab_step(std::move(name), std::move(what), std::move(args), std::move(quick), true);
}

std::vector<Step> all_steps(const runner::Places& places) {
  std::vector<Step> out;
  for (const auto& e : experiment_registry()) {
    const auto steps = e.steps(places);
    out.insert(out.end(), steps.begin(), steps.end());
  }
  return out;
}

}  // namespace sglab::experiments
