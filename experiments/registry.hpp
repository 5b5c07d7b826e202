// The typed experiment registry: every experiment sglab runs, its one-line summary, the `sglab`
// command it registers (if it has its own), and the steps `sglab reproduce` runs for it given the
// places a run writes to. Read by `sglab reproduce` (its step list, --list) and by `sglab --help`
// (the list of experiments). Adding an experiment: one file experiments/NAME.cpp defining its
// computation, its command and NAME_experiment(), and one line X(NAME) in SGLAB_EXPERIMENTS below
// (the CMake list globs the sources; docs/architecture.md, "Adding an experiment").
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "run_context.hpp"

namespace CLI {
class App;
}  // namespace CLI

namespace sglab::experiments {

// One step of `sglab reproduce`: an ordinary `sglab` command line (or a python3 plot script),
// run in-process, so that every table it writes is headed by the very command a user can run. An
// sglab step runs in the run's places (runner::Places: a full run writes its tables and the
// figures README.md shows into paper_tables/, the rest into results/; a --quick run writes
// everything under results/quick/, tables in results/quick/tables/, and never touches
// paper_tables/): its command's --out and tables directory default to them, so its arguments name
// only its inputs and the files a general tool writes (a render's image), never a directory of
// its own outputs.
struct Step {
  std::string name;
  std::string what;
  std::vector<std::string> args;        // the sglab command line (without "sglab")
  std::vector<std::string> quick_args;  // appended with --quick
  bool python = false;                  // args are a python3 script and its arguments instead
  // The step's command takes a constant set (`sglab reproduce --constants` is passed on to it).
  bool takes_constants = false;
  // Its tables carry wall-clock times: `sglab reproduce` runs it with nothing beside it.
  bool timed = false;
  // Files the command reads that its arguments do not name (the recommendations read the tables
  // of a directory): fingerprinted in the step's marker like a file argument, so that a changed
  // one reruns the step.
  std::vector<std::string> reads = {};
};

// The step, marked as one whose tables carry wall-clock times.
Step timed(Step s);

// A step running `sglab ARGS` (with QUICK_ARGS appended in a --quick run).
Step sglab_step(std::string name, std::string what, std::vector<std::string> args,
                std::vector<std::string> quick_args = {}, bool takes_constants = false);
// A step running `python3 SCRIPT ARGS…` (a figure; QUICK_ARGS appended in a --quick run, the
// scripts' --quick: PNG only, no PDF).
Step plot_step(std::string name, std::string what, std::vector<std::string> args,
               std::vector<std::string> quick_args = {});

// The renders' directory in a run's places (runner::Places::dir), and the figures' that README.md
// does not show (those it shows go to Places::key_figures()).
inline constexpr std::string_view kRendersDir = "renders", kFiguresDir = "figures";

// `sglab render SCENE EXTRA… --out OUT/renders/BASE.exr --stats ….json --dump-csv ….csv --width W
// --height H` (it takes the constant sets).
Step render_step(const runner::Places& p, std::string name, std::string what, const std::string& scene,
                 const std::string& base, int width, int height, std::vector<std::string> quick,
                 std::vector<std::string> extra = {});

struct Experiment {
  std::string name;     // "error-vs-time"
  std::string summary;  // one line for `sglab --help`
  // Registers the experiment's own command (one sub-command) on its parent, the command named by
  // `under`, run in `run` (runner/run_context.hpp); null when general tools of cli/ (render, fit)
  // run its steps.
  void (*add_command)(CLI::App& parent, const runner::RunContext& run) = nullptr;
  std::function<std::vector<Step>(const runner::Places&)> steps;
  // The parent of its command: "" for `sglab COMMAND`, or a general tool that groups experiments
  // ("sweep": `sglab sweep KIND`, "envmap": `sglab envmap COMMAND`).
  std::string under = "";
};

// The experiments, in the order `sglab reproduce` runs them (a step may read an earlier one's
// outputs: the λ_d render sweep reads the fits). Those with timed steps come first, then the
// untimed ones, long ones (stability, sweep specular) at both ends, so that the plots have
// untimed steps to run beside; the recommendations, which read every table, last. One line per experiment:
// NAME_experiment() is defined in the experiment's own file.
#define SGLAB_EXPERIMENTS(X) \
  X(fits)                    \
  X(error_vs_time)           \
  X(sweep_render)            \
  X(envmap)                  \
  X(envmap_bases)            \
  X(stability)               \
  X(error_map)               \
  X(renders)                 \
  X(filtering)               \
  X(vsgl_fis_bias)           \
  X(near_wall)               \
  X(poster_plots)            \
  X(sweep_specular)          \
  X(own_specular)            \
  X(shader_export)           \
  X(own_method)              \
  X(recommendations)

#define SGLAB_DECLARE_EXPERIMENT(name) Experiment name##_experiment();
SGLAB_EXPERIMENTS(SGLAB_DECLARE_EXPERIMENT)
#undef SGLAB_DECLARE_EXPERIMENT

const std::vector<Experiment>& experiment_registry();

// Registers, in registry order, the command of every experiment whose `under` is `under` on
// `parent` (the app for "", else the parent's own command): the one place the CLI registers an
// experiment's command (cli/app.cpp for "", cli/sweep_command.cpp, cli/envmap_command.cpp).
void add_experiment_commands(CLI::App& parent, std::string_view under, const runner::RunContext& run);

// Every step of every experiment, in order.
std::vector<Step> all_steps(const runner::Places& places);

}  // namespace sglab::experiments
