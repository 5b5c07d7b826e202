// `sglab reproduce`: the main job, run by experiments/reproduce.cpp over the experiment registry;
// each step's `sglab` command line runs in-process through run_sglab.
#include <algorithm>
#include <memory>

#include "commands.hpp"
#include "constant_sets.hpp"
#include "option_checks.hpp"
#include "registry.hpp"
#include "reproduce.hpp"

namespace sglab::cli {

void add_reproduce_command(CLI::App& app) {
  auto opts = std::make_shared<experiments::ReproduceOptions>();
  auto* sub = app.add_subcommand("reproduce",
                                 "Regenerate every table and figure (resumes: finished steps are skipped)");
  sub->add_option("--out", opts->out,
                  "directory for results and figures (default: results, or results/quick with --quick)");
  sub->add_option("--tables-dir", opts->tables_dir,
                  "directory for the tables and key figures (default: paper_tables, or OUT/tables with --quick)");
  sub->add_flag("--quick", opts->quick, "coarser grids; writes under results/quick/, never into paper_tables/");
  sub->add_flag("--list", opts->list, "print each step and its command line in this mode, run nothing");
  sub->add_flag("--force", opts->force, "redo finished steps");
  std::vector<std::string> steps;
  for (const auto& s : experiments::all_steps(experiments::reproduce_places({}))) steps.push_back(s.name);
  // The help lists every step; an unknown one gets the closest step and a pointer to --list (with
  // the whole list the message would run over a thousand characters).
  sub->add_option("--only", opts->only, "run only these steps")
      ->check(CLI::Validator(
          [steps](std::string& text) -> std::string {
            if (std::find(steps.begin(), steps.end(), text) != steps.end()) return {};
            const std::string near = runner::closest_name(text, steps);
            return "unknown step '" + clip_text(text) + "' (" + (near.empty() ? "" : "did you mean '" + near + "'?; ") +
                   "`sglab reproduce --list` lists the steps)";
          },
          "{" + runner::join_names(steps, "|") + "}"));
  frontend::add_constants_option(
      *sub, opts->constants,
      "constant set for every step but the fits (a fit record, a directory of them, or 'published'; "
      "repeatable, later sets override earlier ones)");
  sub->callback([opts] {
    experiments::run_reproduce(*opts, [](const std::vector<std::string>& args, const runner::RunContext& run) {
      return run_sglab(args, run);
    });
  });
}

}  // namespace sglab::cli
