// `sglab sweep render`'s summary table (sweep_render.hpp: tables, write), from the per-point CSV
// alone; the sweep itself is sweep_render.cpp.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "sweep_render.hpp"
#include "table.hpp"

namespace sglab::experiments::sweep_render {

// What the table says of --precision and --reference-precision.
namespace {

std::string arithmetic_text(const frontend::RenderJob& job) {
  const std::string reference = job.reference_precision.empty() ? job.precision : job.reference_precision;
  if (job.precision == "double" && reference == "double") return "double";
  return fmt::format(
      "the VPL sum (reference) in {}, the VSGLs' diffuse method in {}, the rest in double; float is within "
      "1e-5 relative L2 of the double path (docs/simd.md)",
      reference, job.precision);
}

}  // namespace

// The summary table (Markdown and CSV) from the per-point CSV alone.
Tables tables(const Result& r) {
  const runner::CsvTable& t = r.points;
  const Options& o = r.options;
  const auto col = [&](const std::string& c) {
    const auto i = t.column(c);
    if (i == runner::CsvTable::npos)
      throw runner::InputError(fmt::format("sweep render: the per-point CSV has no column '{}'", c));
    return i;
  };
  const auto num = [](const std::string& s) { return s.empty() ? NAN : std::stod(s); };
  std::string md = fmt::format(
      "# VSGL indirect light against the exact VPL sum\n\n"
      "Scene `{}`{}. Error of the VSGL indirect layer against the exact sum over every VPL (true BRDFs at both "
      "ends, same visibility assumption: {}), over the pixels that hit geometry, all channels: relative L2 = "
      "‖v − r‖/‖r‖, SMAPE = mean 2|v − r|/(|v| + |r|), RMSE in W/(m² sr). Lobes: VSGLs built (diffuse + specular). "
      "Times: wall clock on this machine, all cores; VSGL = generation + shading of every pixel; speedup = "
      "reference / VSGL. Arithmetic: {}.\n\n",
      o.job.scene_path,
      o.job.overrides.empty() ? "" : " with " + fmt::format("`--set {}`", fmt::join(o.job.overrides, "`, `--set ")),
      o.job.visibility
          ? "VSGL visibility from a cube shadow map at each μ_v (Tokuyoshi 2016 §4.1), VPL visibility by ray casting"
          : "none",
      arithmetic_text(o.job));
  md += "Constants (`--constants`; a varied vsgl.lambda_d replaces the render's λ_d):\n\n" +
        frontend::constants_text(o.job.constants.set, {{"render", find_standalone_constant("render", "lambda_d")}},
                                 "- ") +
        "\n";
  if (!r.lambda_d_sources.empty())
    md += fmt::format("Varied {}: {}.\n\n", kLambdaDKey, fmt::join(r.lambda_d_sources, "; "));
  std::string header = "|", rule = "|";
  for (const auto& v : r.vary) {
    header += fmt::format(" {} |", v.key);
    rule += "---|";
  }
  header += " VSGLs | lobes (specular) | VPLs | relative L2 | SMAPE | RMSE | VSGL ms | reference s | speedup |\n";
  rule += "---|---|---|---|---|---|---|---|---|\n";
  md += header + rule;
  for (const auto& row : t.rows) {
    const auto& f = row.fields;
    md += "|";
    for (const auto& v : r.vary) md += fmt::format(" {:.4g} |", num(f[col(v.key)]));
    const double vsgl_ms = 1e3 * (num(f[col("seconds_vsgl")]) + num(f[col("seconds_shading")]));
    md += fmt::format(" {} | {} ({}) | {} | {:.4f} | {:.4f} | {:.4g} | {:.3g} | {:.3g} | {:.0f}× |\n", f[col("vsgl")],
                      f[col("vsgl_count")], f[col("specular_vsgls")], f[col("vpl_count")], num(f[col("relative_l2")]),
                      num(f[col("smape")]), num(f[col("rmse")]), vsgl_ms, num(f[col("seconds_reference")]),
                      num(f[col("speedup")]));
  }
  std::string csv;
  runner::append_csv_record(csv, t.header);
  for (const auto& row : t.rows) runner::append_csv_record(csv, row.fields);
  return {md, csv};
}

void write(const Result& r) {
  if (r.sharded) return;
  const Tables t = tables(r);
  runner::write_and_show_table(runner::tables_place(r.options.tables_dir, r.options.out), r.name, r.provenance,
                               t.markdown, t.csv);
  std::fprintf(stderr, "sweep render: wrote %s/%s.{md,csv}\n",
               runner::tables_place(r.options.tables_dir, r.options.out).c_str(), r.name.c_str());
}

}  // namespace sglab::experiments::sweep_render
