// `sglab sweep specular --out DIR [--quick] [--shard i/N] [--threads N] [--tables-dir DIR] [--fresh]`:
// every method of the registry's `specular` quantity — enumerated, never
// named here — against the quantity's reference method, over
//   roughness α (9 values log-spaced over [0.01, 1]) × light sharpness λ ∈ {1, 10, 100, 1e3, 1e4}
//   × view_cos ∈ {1, 0.7, 0.3, 0.1} × up to 6 light positions above the horizon (sweep_specular.hpp), f0 = 0.04.
// A point of the sweep is one (α, λ, view_cos); its rows are its light positions × methods, so
// that the point knows its own scale (the largest reference among its positions) and near-zero
// references are classified within the point.
// Outputs: DIR/specular_points.csv (the runner's per-point CSV, sweep.hpp), then, derived from
// that file alone, DIR/specular_summary.csv and TABLES/specular_vs_roughness.{md,csv}.
// `--brdf gaussian` measures the `specular-gaussian-ndf` quantity instead (the Gaussian-angle NDF
// BRDF, each method against that BRDF's own reference) on the same grid, into
// DIR/specular-gaussian_points.csv, DIR/specular_gaussian_summary.csv and
// TABLES/specular_gaussian_vs_roughness.{md,csv}.
#include "sweep_specular.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <tuple>

#include <fmt/core.h>

#include "atomic_file.hpp"
#include "table.hpp"
#include "option_checks.hpp"
#include "parse_number.hpp"
#include "resource_limits.hpp"
#include "constant_sets.hpp"
#include "sglab/registry.hpp"
#include "sglab/text_limits.hpp"
#include "registry.hpp"
#include "csv_fields.hpp"

namespace sglab::experiments {
namespace {

namespace fs = std::filesystem;

const char* quantity_name(SpecularBrdf brdf) {
  return brdf == SpecularBrdf::ggx ? "specular" : "specular-gaussian-ndf";
}

const Quantity& specular_quantity(SpecularBrdf brdf) {
  const Quantity* q = find_quantity(quantity_name(brdf));
  if (!q || q->reference_method.empty() || !q->find(q->reference_method))
    throw std::logic_error(std::string("sweep specular: the registry has no `") + quantity_name(brdf) +
                           "` quantity with a reference method");
  return *q;
}

// The methods measured: every method of the quantity but its reference, in registry order.
std::vector<const Method*> measured_methods(const Quantity& q) {
  std::vector<const Method*> out;
  for (const auto& m : q.methods)
    if (m.name != q.reference_method) out.push_back(&m);
  return out;
}

std::string join_numbers(const std::vector<double>& v) {
  std::string s;
  for (double x : v) s += (s.empty() ? "" : ", ") + runner::csv_number(x);
  return s;
}

const std::vector<std::string> kColumns = {"roughness", "light_sharpness", "view_cos",       "f0",          "position",
                                           "light_cos", "light_azimuth",   "reference",      "scale",       "method",
                                           "value",     "status",          "relative_error", "scaled_error"};

}  // namespace

bool specular_position_near_lobe(const std::string& position) {
  return position == "mirror" || position == "toward-normal" || position == "toward-horizon" || position == "side";
}

namespace {

// Point k of a specular grid: its (α, λ, view_cos), roughness slowest, view_cos fastest.
struct GridInputs {
  SpecularGrid g;
  std::array<double, 3> operator()(std::size_t k) const {
    const std::size_t nl = g.light_sharpness.size(), nv = g.view_cos.size();
    return {g.roughness[k / (nl * nv)], g.light_sharpness[(k / nv) % nl], g.view_cos[k % nv]};
  }
};

// A row read back must be at point k's grid point: its (α, λ, view_cos, f0), one of its light
// positions with that position's (light_cos, light_azimuth), and a method the sweep measures.
std::optional<std::string> check_specular_row(const GridInputs& inputs, const std::vector<const Method*>& methods,
                                              std::size_t k, const runner::SweepRow& row) {
  const double f0 = inputs.g.f0;
  if (row.size() != kColumns.size()) return fmt::format("{} fields, expected {}", row.size(), kColumns.size());
  const auto [alpha, lambda, v] = inputs(k);
  const std::array<double, 4> at{alpha, lambda, v, f0};
  for (std::size_t i = 0; i < at.size(); ++i)
    if (row[i] != runner::csv_number(at[i]))
      return fmt::format("{} {} is not the grid point's {} (moved off the grid)", kColumns[i], quote(row[i]),
                         runner::csv_number(at[i]));
  bool position = false;
  for (const auto& p : specular_light_positions(alpha, lambda, v))
    position = position || (row[4] == p.name && row[5] == runner::csv_number(p.light_cos) &&
                            row[6] == runner::csv_number(p.light_azimuth));
  if (!position)
    return fmt::format("light position {} at light_cos {} light_azimuth {} is not one of the grid point's",
                       quote(row[4]), quote(row[5]), quote(row[6]));
  if (std::none_of(methods.begin(), methods.end(), [&](const Method* m) { return m->name == row[9]; }))
    return fmt::format("method {} is not measured by this sweep", quote(row[9]));
  return std::nullopt;
}

// Point k's rows: every light position against every measured method, each with the reference at
// that position and the point's largest reference.
std::vector<runner::SweepRow> specular_point_rows(const GridInputs& inputs, const Quantity& q,
                                                  const std::vector<const Method*>& methods, std::size_t k) {
  const double f0 = inputs.g.f0;
  const auto [alpha, lambda, v] = inputs(k);
  const std::vector<LightPosition> positions = specular_light_positions(alpha, lambda, v);
  std::vector<std::array<double, 6>> args;
  std::vector<double> refs;
  for (const auto& p : positions) {
    args.push_back({alpha, lambda, p.light_cos, v, p.light_azimuth, f0});
    const double r = reference_value(q, args.back());
    if (!std::isfinite(r) || r < 0)
      throw std::runtime_error(fmt::format("sweep specular: the reference is {} at α={} λ={} view_cos={} position {}",
                                           r, alpha, lambda, v, p.name));
    refs.push_back(r);
  }
  const double scale = *std::max_element(refs.begin(), refs.end());
  std::vector<runner::SweepRow> rows;
  for (std::size_t j = 0; j < positions.size(); ++j) {
    const auto& a = args[j];
    for (const Method* m : methods) {
      std::string value, status, relative, scaled;
      if (m->domain_error && m->domain_error(a)) {
        status = "out_of_domain";
      } else {
        const double x = m->eval_double(a);
        if (!std::isfinite(x)) {
          status = "non_finite";
        } else {
          value = runner::csv_number(x);
          const double error = std::fabs(x - refs[j]);
          if (scale > 0) scaled = runner::csv_number(error / scale);
          if (scale > 0 && refs[j] > 0 && refs[j] >= kSpecularNearZero * scale) {
            status = "ok";
            relative = runner::csv_number(error / refs[j]);
          } else {
            status = "near_zero_reference";
          }
        }
      }
      rows.push_back({runner::csv_number(alpha), runner::csv_number(lambda), runner::csv_number(v),
                      runner::csv_number(f0), positions[j].name, runner::csv_number(a[2]), runner::csv_number(a[4]),
                      runner::csv_number(refs[j]), runner::csv_number(scale), m->name, value, status, relative,
                      scaled});
    }
  }
  return rows;
}

}  // namespace

runner::SweepDefinition specular_sweep_definition(bool quick, SpecularBrdf brdf, const frontend::Constants& constants) {
  const Quantity& q = specular_quantity(brdf);
  const Method& reference = *q.find(q.reference_method);
  // The measured methods with the set's constants bound (copies of the registry's when it sets
  // none), owned by the definition's functions.
  auto bound = std::make_shared<std::vector<Method>>();
  for (const Method* m : measured_methods(q)) bound->push_back(bind(*m, constants.set));
  std::vector<const Method*> methods;
  for (const Method& m : *bound) methods.push_back(&m);
  const SpecularGrid g = specular_grid(quick);

  runner::SweepDefinition d;
  const bool gaussian = brdf == SpecularBrdf::gaussian;
  d.name = gaussian ? "specular-gaussian" : "specular";
  d.args = {"sweep", "specular"};
  if (gaussian) d.args.insert(d.args.end(), {"--brdf", "gaussian"});
  if (quick) d.args.push_back("--quick");
  for (const auto& a : frontend::constants_arguments(constants)) d.args.push_back(a);
  std::string method_names;
  for (const Method* m : methods) method_names += (method_names.empty() ? "" : ", ") + m->name;
  std::string position_names;
  for (const auto& p : specular_light_positions(0.1, 1, 0.7))
    position_names += (position_names.empty() ? "" : ", ") + p.name;
  d.grid = fmt::format(
      "{}roughness {{{}}} × light_sharpness {{{}}} × view_cos {{{}}}; f0 {}; positions {{{}}} (offsets in the lobe's "
      "widths "
      "min(√(1/λ + 2α²), π/6) in the plane of incidence, min(√(1/λ + 2α²v²), π/6) across; above the horizon only, "
      "no duplicates); reference `{}`; methods {{{}}}; near zero below {} of the point's largest reference",
      gaussian ? "BRDF: Gaussian-angle NDF (`specular-gaussian-ndf`, roughness = the NDF width m); " : "",
      join_numbers(g.roughness), join_numbers(g.light_sharpness), join_numbers(g.view_cos), runner::csv_number(g.f0),
      position_names, reference.name, method_names, runner::csv_number(kSpecularNearZero));
  // The constant sets' contents, not only their paths: an edited record is another sweep.
  if (constants.given()) d.grid += "; constants fnv1a " + constants.fingerprint;
  d.point_count = g.point_count();
  d.columns = kColumns;
  const GridInputs inputs{g};
  d.describe = [inputs](std::size_t k) {
    const auto [alpha, lambda, v] = inputs(k);
    return fmt::format("α={:.3g} λ={:g} view_cos={:g}", alpha, lambda, v);
  };
  d.check_row = [inputs, bound, methods](std::size_t k, const runner::SweepRow& row) {
    return check_specular_row(inputs, methods, k, row);
  };
  // The registry lives for the whole program: the quantity's pointer stays valid; `bound` keeps
  // the measured methods alive. The references come through the process's kept values
  // (reference_value): in a `sglab reproduce`, `fit all` has integrated these rows already.
  d.compute = [inputs, quantity = &q, bound, methods](std::size_t k) {
    return specular_point_rows(inputs, *quantity, methods, k);
  };
  return d;
}

// ---- the command ----------------------------------------------------------------------------------

namespace {

struct SpecularOptions {
  std::string out = runner::Places{}.dir(kSpecularDir);  // --out: a plain run's
  std::string tables_dir;                                // empty: the --out directory
  std::string shard;
  std::size_t threads = 0;
  bool quick = false;
  bool fresh = false;
  std::string brdf = "ggx";       // ggx | gaussian
  frontend::Constants constants;  // --constants: the measured methods' fitted constants (sglab-specular's)
};

void run_specular(const SpecularOptions& o, const runner::RunContext& run) {
  const SpecularBrdf brdf = o.brdf == "gaussian" ? SpecularBrdf::gaussian : SpecularBrdf::ggx;
  const std::string base = brdf == SpecularBrdf::gaussian ? "specular_gaussian" : "specular";
  const runner::SweepDefinition d = specular_sweep_definition(o.quick, brdf, o.constants);
  const runner::SweepRunResult r = runner::run_sweep_command(d, o.out, o.shard, o.threads, o.fresh, run);
  if (r.sharded) return;
  const auto rows = summarize_specular_points(runner::read_sweep_points(r.points_csv), r.points_csv.string());
  std::string command = "sglab";
  for (const auto& a : d.args) command += " " + a;
  command += o.tables_dir.empty() ? runner::option_argument("--out", o.out, SpecularOptions{}.out)
                                  : runner::option_argument("--tables-dir", o.tables_dir);
  const fs::path tables = runner::tables_place(o.tables_dir, o.out);
  const std::string csv = specular_summary_csv(rows);
  const runner::Provenance provenance = runner::run_provenance(run, command, o.quick);
  const std::string md = specular_summary_markdown(rows, provenance, brdf);
  runner::OutputSet outputs;
  outputs.add(fs::path(o.out) / (base + "_summary.csv"), csv);
  outputs.add(tables / (base + "_vs_roughness.csv"), runner::csv_header(provenance) + csv);
  outputs.add(tables / (base + "_vs_roughness.md"), md);
  outputs.commit();
  std::fputs(md.c_str(), stdout);
  std::fprintf(stderr, "sweep specular: wrote %s/%s_summary.csv and %s/%s_vs_roughness.{md,csv} (%.1f s)\n",
               o.out.c_str(), base.c_str(), tables.c_str(), base.c_str(), r.seconds);
}

}  // namespace

void add_sweep_specular(CLI::App& sweep, const runner::RunContext& run) {
  auto o = std::make_shared<SpecularOptions>();
  auto* sub = sweep.add_subcommand(
      "specular", "Every specular method vs the reference over roughness × light sharpness × view × light position");
  o->out = run.places.dir(kSpecularDir);
  o->tables_dir = run.places.tables;
  sub->add_option("--out", o->out, "directory for specular_points.csv and specular_summary.csv")->capture_default_str();
  sub->add_flag("--quick", o->quick, "coarser grid (3 α × 3 λ × 3 views; seconds)");
  sub->add_option("--shard", o->shard, "compute only shard i of N (points k with k % N == i); join with `sglab merge`")
      ->check(frontend::shard_given());
  sub->add_option("--threads", o->threads, "worker threads (0: all cores)")
      ->capture_default_str()
      ->check(frontend::unsigned_at_most(runner::kMaxThreads));
  sub->add_option("--tables-dir", o->tables_dir,
                  "directory for specular_vs_roughness.{md,csv} (default: the --out directory)")
      ->capture_default_str();
  sub->add_option("--brdf", o->brdf,
                  "ggx (the `specular` quantity) or gaussian (the Gaussian-angle NDF BRDF, `specular-gaussian-ndf`; "
                  "tables specular_gaussian_vs_roughness.{md,csv})")
      ->capture_default_str()
      ->check(frontend::one_of({"ggx", "gaussian"}, "BRDF"));
  sub->add_flag("--fresh", o->fresh, "ignore earlier output and checkpoints of this sweep (recompute everything)");
  frontend::add_constants_option(*sub, o->constants);
  sub->callback([o, run] { run_specular(*o, run); });
}

std::vector<Step> sweep_specular_steps(const runner::Places& p) {
  return std::vector<Step>{
      sglab_step("sweep-specular",
                 "specular methods against the GGX reference over roughness (paper_tables/specular_vs_roughness.*)",
                 {"sweep", "specular"}, {"--quick"}, true),
      sglab_step("sweep-specular-gaussian",
                 "specular methods of the Gaussian-angle NDF BRDF against that BRDF's own reference "
                 "(paper_tables/specular_gaussian_vs_roughness.*)",
                 {"sweep", "specular", "--brdf", "gaussian"}, {"--quick"}, true),
      plot_step("plot-specular", "specular error against roughness, one line per method",
                {"plots/specular_vs_roughness.py", p.dir(kSpecularDir) + "/specular_summary.csv", p.key_figures()},
                {"--quick"})};
}

Experiment sweep_specular_experiment() {
  return {"sweep-specular", "`sglab sweep specular`: specular methods against the GGX reference over roughness",
          add_sweep_specular, sweep_specular_steps, "sweep"};
}

}  // namespace sglab::experiments
