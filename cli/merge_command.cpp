// `sglab merge --out DIR SHARD_DIR…`: joins the shards of a sweep (`sglab sweep KIND --shard i/N`,
// run anywhere, e.g. as a Slurm job array) into the per-point CSV an unsharded run would have
// written, after checking that the shards belong to one sweep, that their headers match and that
// every point appears exactly once (sweep.hpp, merge_sweep_shards). It then runs the sweep's own
// command on DIR, which finds every point finished and derives the summary and the paper tables
// from the merged per-point CSV — the same code path, and the same tables, as an unsharded run.
// The manifests are data, never commands: their sweep command line is checked to be a sweep's,
// and the sweep it defines here must match the merged output exactly (nothing is recomputed).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "sglab/text_limits.hpp"
#include "sweep.hpp"

namespace sglab::cli {
namespace {

struct MergeOptions {
  std::string out;
  std::string tables_dir;  // empty: the --out directory
  std::vector<std::string> inputs;
};

void summarize(const MergeOptions& o, const std::vector<runner::MergedSweep>& merged);

void run_merge(const MergeOptions& o) {
  const std::vector<std::filesystem::path> inputs(o.inputs.begin(), o.inputs.end());
  // The sweep's own command line, and nothing else: `sweep specular|render …`.
  const auto sweep_command = [](const std::vector<std::string>& args, const std::filesystem::path& manifest) {
    if (args.size() < 2 || args[0] != "sweep" || (args[1] != "specular" && args[1] != "render")) {
      std::string text;
      for (const auto& a : args) text += (text.empty() ? "" : " ") + a;
      throw runner::InputError("merge: " + manifest.string() + ": 'args' \"" + clip_text(text) +
                               "\" is not a `sweep specular` or `sweep render` command line");
    }
  };
  const std::vector<runner::MergedSweep> merged = runner::merge_sweep_shards(inputs, o.out, sweep_command);
  try {
    summarize(o, merged);
  } catch (...) {
    runner::undo_merge(merged);  // a refused summary leaves no merged output behind
    throw;
  }
  runner::keep_merge(merged);
}

void summarize(const MergeOptions& o, const std::vector<runner::MergedSweep>& merged) {
  for (const runner::MergedSweep& m : merged) {
    std::fprintf(stderr, "merge: sweep %s: %zu points from %zu shards -> %s\n", m.name.c_str(), m.points, m.shards,
                 m.points_csv.string().c_str());
    // m.args was checked to be a `sweep specular|render` command line without output options
    // (merge_sweep_shards). It is run only to rebuild the sweep's definition here; in a
    // summary-only run (RunContext::summary_only) the runner computes nothing, and refuses if the merged output is not
    // exactly that definition's finished output.
    std::vector<std::string> args = m.args;
    args.insert(args.end(), {"--out", o.out});
    if (!o.tables_dir.empty()) args.insert(args.end(), {"--tables-dir", o.tables_dir});
    const int status = run_sglab(args, {.summary_only = true});
    if (status == 2) throw runner::InputError("merge: the summary of sweep '" + m.name + "' was refused (see above)");
    if (status != 0) throw std::runtime_error("merge: the summary of sweep '" + m.name + "' failed");
  }
}

}  // namespace

void add_merge_command(CLI::App& app) {
  auto o = std::make_shared<MergeOptions>();
  auto* sub = app.add_subcommand("merge", "Join the shards of a sweep (--shard i/N outputs) and derive its summary");
  sub->add_option("--out", o->out, "directory for the merged per-point CSV and summary")->required();
  sub->add_option("--tables-dir", o->tables_dir, "directory for the sweep's tables (default: the --out directory)");
  sub->add_option("inputs", o->inputs, "shard directories (or NAME_sweep.shard-i-of-N.json manifests)")->required();
  sub->callback([o] { run_merge(*o); });
}

}  // namespace sglab::cli
