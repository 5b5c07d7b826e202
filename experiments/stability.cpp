// `sglab stability`: the stability atlas. Every method of every registry
// quantity (the stiff cases of docs/math.md §10 among them), in float and double over the stiff
// grid (stability_atlas.hpp): counts of NaN, Inf, negative, thrown, out-of-domain and wrong by
// more than 1 % outputs, the worst approximation error (against the quantity's reference) and,
// apart from it, the worst rounding error (against the same method in 50 digits at the same input).
// Writes DIR/stability.csv (one row per quantity × method × precision), DIR/stability_cells.csv
// (the heat-map cells), DIR/stability.md and TABLES/stability.{md,csv}, all or none (without
// --tables the tables are DIR's stability.{md,csv}, the CSV headed).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "atomic_file.hpp"
#include "option_checks.hpp"
#include "constant_sets.hpp"
#include "registry.hpp"
#include "stability_atlas.hpp"
#include "table.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::experiments {
namespace {

// Its output directory in a run's places (runner::Places::dir).
constexpr std::string_view kDir = "stability";

struct Options {
  std::string out_dir = runner::Places{}.dir(kDir);  // --out: a plain run's
  std::string tables_dir;                            // --tables; empty: the --out directory
  std::vector<std::string> only;                     // quantity names; empty: all
  bool quick = false;
  frontend::Constants constants;  // --constants (constant_sets.hpp)
};

// Bad usage before anything is computed: an unknown quantity, or outputs that cannot be written
// (a directory option naming something else than a directory, an output that is a special file,
// or the same file named twice). Returns the outputs: DIR/stability_cells.csv,
// TABLES/stability.{csv,md}, DIR/stability.{csv,md} (the last two only with --tables).
std::vector<std::filesystem::path> checked_outputs(const Options& o) {
  namespace fs = std::filesystem;
  for (const auto& name : o.only)
    if (!find_quantity(name)) {
      throw runner::InputError("stability: " +
                               runner::unknown_name_message("quantity", name, frontend::quantity_names()));
    }
  for (const auto& [option, dir] :
       {std::pair{"--out", o.out_dir}, std::pair{"--tables", o.tables_dir.empty() ? o.out_dir : o.tables_dir}})
    for (fs::path p = dir; !p.empty(); p = p.parent_path()) {  // the deepest existing one must be a directory
      std::error_code ec;
      if (fs::exists(p, ec)) {
        if (!fs::is_directory(p, ec))
          throw runner::InputError(fmt::format("stability: {} '{}': '{}' is not a directory", option, dir, p.string()));
        break;
      }
      if (p == p.parent_path()) break;
    }
  const fs::path out(o.out_dir), tables = runner::tables_place(o.tables_dir, o.out_dir);
  const std::vector<runner::NamedPath> outputs{{"--out", out / "stability_cells.csv"},
                                               {"--tables", tables / "stability.csv"},
                                               {"--tables", tables / "stability.md"},
                                               {"--out", out / "stability.csv"},
                                               {"--out", out / "stability.md"}};
  runner::check_output_paths(
      o.tables_dir.empty() ? std::vector<runner::NamedPath>(outputs.begin(), outputs.begin() + 3) : outputs, {});
  std::vector<fs::path> paths;
  for (const auto& n : outputs) paths.push_back(n.path);
  return paths;
}

std::string command_line(const Options& o) {
  std::string command = "sglab stability";
  for (const auto& n : o.only) command += " --quantity " + n;
  if (o.quick) command += " --quick";
  for (const auto& a : frontend::constants_arguments(o.constants)) command += " " + a;
  return command + (o.tables_dir.empty() ? runner::option_argument("--out", o.out_dir, Options{}.out_dir)
                                         : runner::option_argument("--tables", o.tables_dir));
}

// Computes the atlas and commits its five outputs as one set: none is replaced unless all were
// written.
void write(const Options& o, const runner::RunContext& run) {
  const std::vector<std::filesystem::path> paths = checked_outputs(o);
  atlas::Options options;
  options.quick = o.quick;
  options.only = o.only;
  options.constants = o.constants.set;
  std::vector<ConstantUse> uses;
  for (const auto& q : quantities())
    for (const auto& m : q.methods) {
      const auto u = frontend::method_constant_uses(q.name + "/" + m.name, m);
      uses.insert(uses.end(), u.begin(), u.end());
    }
  const atlas::Result result = atlas::compute(options);

  const std::string command = command_line(o);
  const std::string csv = atlas::summary_csv(result);
  const runner::Provenance provenance = runner::run_provenance(run, command, o.quick);
  const std::string md = runner::markdown_header(provenance) +
                         atlas::markdown(result, frontend::constants_text(options.constants, uses, "- "));
  runner::OutputSet outputs;
  outputs.add(paths[0], atlas::cells_csv(result));
  outputs.add(paths[1], runner::csv_header(provenance) + csv);
  outputs.add(paths[2], md);
  if (!o.tables_dir.empty()) {  // the bare CSV and the Markdown beside the cells too
    outputs.add(paths[3], csv);
    outputs.add(paths[4], md);
  }
  outputs.commit();
  std::size_t methods = 0;
  for (const auto& q : result.quantities) methods += q.methods.size();
  std::fprintf(stderr,
               "stability: %zu quantities, %zu methods, %.1f s; wrote %s/stability{.csv,_cells.csv,.md} and "
               "%s/stability.{md,csv}\n",
               result.quantities.size(), methods, result.seconds, o.out_dir.c_str(), paths[1].parent_path().c_str());
}

}  // namespace

void add_stability_command(CLI::App& app, const runner::RunContext& run) {
  auto opts = std::make_shared<Options>();
  auto* sub = app.add_subcommand(
      "stability",
      "Stability atlas: NaN/Inf/negative/>1 % counts and rounding error of every method over the stiff inputs");
  frontend::add_places_options(*sub, run.places, kDir, opts->out_dir, opts->tables_dir,
                               "directory for stability.csv, stability_cells.csv, stability.md",
                               "directory for stability.{md,csv} (default: the --out directory)", "--tables");
  frontend::add_constants_option(*sub, opts->constants);
  sub->add_option("--quantity", opts->only, "only these quantities (repeatable; default: all)")
      ->check(frontend::one_of(frontend::quantity_names(), "quantity"));
  sub->add_flag("--quick", opts->quick, "coarser grids, fewer 50-digit evaluations");
  sub->callback([opts, run] { write(*opts, run); });
}

}  // namespace sglab::experiments

// ---- the experiment: its reproduce steps --------------------------------------------------------

namespace sglab::experiments {

Experiment stability_experiment() {
  return {"stability", "stability atlas: NaN/Inf/negative/>1 % counts and rounding error of every method (stability.*)",
          add_stability_command, [](const runner::Places& p) {
            return std::vector<Step>{
                sglab_step("stability",
                           "stability atlas: NaN/Inf/negative/>1 % counts and rounding error of every method "
                           "(paper_tables/stability.*)",
                           {"stability"}, {"--quick"}, true),
                plot_step("plot-stability", "stability heat map per method, float and double side by side",
                          {"plots/stability_heatmap.py", p.dir(kDir) + "/stability_cells.csv",
                           p.dir(kFiguresDir) + "/stability"},
                          {"--quick"})};
          }};
}

}  // namespace sglab::experiments
