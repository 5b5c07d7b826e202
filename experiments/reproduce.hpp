// `sglab reproduce`: the main job. Runs the steps of the experiment registry in order and records
// a marker per finished step so that an interrupted run resumes where it stopped (a step's outputs
// are written atomically, so a step without its marker is simply redone). The marker records the
// fingerprint of every file the step names (and of the files it reads without naming them,
// Step::reads: the recommendations' tables) and of every file it wrote under OUT/ and the tables
// directory, so a changed input or a deleted or altered output also reruns it.
// The plot steps (python3) run one at a time beside the sglab steps, which run one at a time in
// order; a step whose tables carry wall-clock times (Step::timed) runs with nothing beside it.
// The plot scripts share one interpreter (plots/_serve.py), each run as `python3 SCRIPT ARGS`
// would run it. A step's CPU seconds include the programs it runs (shader-export's compilers).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "registry.hpp"

namespace sglab::experiments {

struct ReproduceOptions {
  std::string out;         // default: results, or results/quick with --quick
  std::string tables_dir;  // default: paper_tables, or OUT/tables with --quick
  bool quick = false;
  bool force = false;
  bool list = false;
  std::vector<std::string> only;
  std::vector<std::string> constants;  // --constants: appended to every step whose command takes a constant set
};

// Where a run with these options writes: OUT (default results, or results/quick with --quick) and
// TABLES (default paper_tables, or OUT/tables with --quick). Every sglab step runs in them.
runner::Places reproduce_places(const ReproduceOptions& o);

// The command line of step `s` in this mode (without "sglab" / "python3"): its arguments, its
// quick arguments with --quick, and the constant sets.
std::vector<std::string> step_args(const Step& s, const ReproduceOptions& o);

// The line that runs step `s` alone where this mode runs it: "python3 ARGS", or "sglab PLACES
// ARGS" with the places as `sglab` takes them before the command (runner::places_arguments).
// Printed by --list and recorded in the step's marker.
std::string step_line(const Step& s, const ReproduceOptions& o, const runner::Places& p);

// Runs `sglab ARGS` in-process in `run` and returns its exit status (the CLI's run_sglab).
using SglabRunner = std::function<int(const std::vector<std::string>& args, const runner::RunContext& run)>;

// Runs (or with --list prints) the registry's steps.
void run_reproduce(const ReproduceOptions& o, const SglabRunner& run_sglab);

}  // namespace sglab::experiments
