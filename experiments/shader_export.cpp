// `sglab shader-export` (shader_export.hpp).
#include "shader_export.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <memory>

#include <fmt/core.h>
#include <fmt/ranges.h>
#include <tbb/parallel_for.h>

#include "constant_sets.hpp"
#include "error_grid.hpp"
#include "experiment_command.hpp"
#include "registry.hpp"
#include "sglab/sg.hpp"
#include "sglab/stiff_cases.hpp"
#include "toolchain.hpp"

namespace sglab::cli::shader_export {
namespace {

const char* const kTable = "shader_export";
const std::vector<std::string> kEvaluators = {"sglab float", "c", "glsl", "hlsl"};

bool is_diffuse(const Quantity& q) {
  return q.columns.size() == 2 && q.columns[0].kind == ColumnKind::sharpness && q.columns[1].kind == ColumnKind::cosine &&
         !q.reference_method.empty();
}

// What a method's value is compared with: the quantity's reference, except for the normalized
// vMF form of the hemispherical integral, which returns H/A(λ) (its registry entry says so).
double reference_for(const Method& m, const Method& ref, double l, double c) {
  const double args[2] = {l, c};
  const double v = ref.eval_double(args);
  return m.name == "vmf-tokuyoshi2024" ? v / sg_integral(l) : v;
}

// The spacing of floats at |x|.
float float_ulp(float x) {
  const float a = std::fabs(x);
  return std::nextafter(a, std::numeric_limits<float>::infinity()) - a;
}

// The grids of one run: the error grid's rows (then the stiff grid's), as float inputs.
struct Grids {
  std::vector<float> rows;  // error grid, then stiff grid; 2 floats a row
  std::size_t grid_points = 0, stiff_points = 0;
  std::vector<double> lambdas, cosines;  // per grid point (as the float inputs, in double)
};

Grids make_grids(bool quick) {
  Grids g;
  const DiffuseAxes axes = diffuse_grid_axes(quick);
  for (double l : axes.sharpnesses)
    for (double c : axes.cosines) {
      g.rows.insert(g.rows.end(), {float(l), float(c)});
      g.lambdas.push_back(double(float(l)));
      g.cosines.push_back(double(float(c)));
    }
  g.grid_points = g.lambdas.size();
  std::vector<double> ls = stiff::sharpnesses();
  for (double l : stiff::extreme_sharpnesses())
    if (l <= double(std::numeric_limits<float>::max())) ls.push_back(l);
  for (double l : ls)
    for (double c : stiff::cosines()) g.rows.insert(g.rows.end(), {float(l), float(c)});
  g.stiff_points = g.rows.size() / 2 - g.grid_points;
  return g;
}

// The row's metrics from values on both grids.
void measure(Row& row, const std::vector<float>& v, const std::vector<float>& sglab_float, const Grids& g,
             const std::vector<double>& reference, const std::vector<double>& scale, const Method& m) {
  for (std::size_t k = 0; k < g.grid_points; ++k) {
    const double args[2] = {g.lambdas[k], g.cosines[k]};
    if (m.domain_error && m.domain_error(args)) continue;
    if (!std::isfinite(v[k])) {
      ++row.grid_non_finite;
      continue;
    }
    row.max_error = std::max(row.max_error, std::fabs(double(v[k]) - reference[k]) / scale[k]);
    // In ulps of the larger of the value and the reference at c = 1 (float): near zero (the
    // back-facing tail) raw ulps count rounding far below the value's own scale (1e-31 against 0
    // is 2e8 ulps).
    const float magnitude = std::max(std::fabs(sglab_float[k]), float(scale[k]));
    const double u = std::fabs(double(v[k]) - double(sglab_float[k])) / double(float_ulp(magnitude));
    if (std::isfinite(sglab_float[k])) row.max_ulps = std::max(row.max_ulps, u);
  }
  for (std::size_t k = g.grid_points; k < g.grid_points + g.stiff_points; ++k) {
    const double args[2] = {double(g.rows[2 * k]), double(g.rows[2 * k + 1])};
    if (m.domain_error && m.domain_error(args)) continue;
    ++row.stiff_points;
    if (!std::isfinite(v[k])) ++row.stiff_non_finite;
    else if (v[k] < 0) ++row.stiff_negatives;
  }
}

}  // namespace

Result compute(const Options& o) {
  Result r;
  r.provenance.command = "sglab shader-export";
  if (o.quick) r.provenance.command += " --quick";
  for (const auto& a : constants_arguments(o.constants)) r.provenance.command += " " + a;
  const ConstantSet set = load_constant_sets(o.constants);
  shader::VulkanCompute gpu;
  r.device = gpu.device_name();
  const Grids g = make_grids(o.quick);
  r.grid = fmt::format("error-vs-time's diffuse grid{} ({} points, inputs rounded to float)", o.quick ? " (quick)" : "", g.grid_points);
  r.stiff = fmt::format("λ ∈ {{0, 1e-8 … 1e8 (2 per decade), 1e10 … 1e35, FLT_MAX}} × the stiff cosines (±1 and the float/double "
                        "steps around them, 0, ±1e-8, 15 interior values): {} points, those in each method's domain",
                        g.stiff_points);
  std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> refs;  // per method: reference, scale
  for (const auto& name : shader::exportable_methods()) {
    const shader::MethodRef ref = shader::find_exportable(name);
    const Quantity& q = *ref.quantity;
    const Method& m = *ref.method;
    if (!is_diffuse(q)) continue;
    const Method& refm = *q.find(q.reference_method);
    std::vector<double> reference(g.grid_points), scale(g.grid_points);
    tbb::parallel_for(std::size_t(0), g.grid_points, [&](std::size_t k) {
      reference[k] = reference_for(m, refm, g.lambdas[k], g.cosines[k]);
      scale[k] = reference_for(m, refm, g.lambdas[k], 1.0);
    });
    const Method bound = bind(m, set);
    std::vector<float> sglab_float(g.rows.size() / 2);
    for (std::size_t k = 0; k < sglab_float.size(); ++k) sglab_float[k] = bound.eval_float(std::span<const float>(&g.rows[2 * k], 2));
    const shader::TracedMethod traced = shader::trace_method(q, m, set);
    for (const auto& evaluator : kEvaluators) {
      Row row;
      row.method = name;
      row.evaluator = evaluator;
      std::fprintf(stderr, "shader-export: %s, %s\n", name.c_str(), evaluator.c_str());
      try {
        std::vector<float> v;
        if (evaluator == "sglab float") {
          v = sglab_float;
        } else {
          const shader::Language lang = *shader::parse_language(evaluator);
          const shader::TracedMethod* one = &traced;
          const std::string src = shader::emit(std::span(one, 1), lang, "sglab export " + name + " --lang " + evaluator);
          if (lang == shader::Language::c) {
            v = shader::run_c(src, traced, g.rows);
          } else {
            const shader::Spirv spv = shader::compile_to_spirv(shader::compute_shader_source(src, traced, lang), lang);
            row.instructions = long(shader::method_instructions(spv, lang, 2));
            v = shader::run_compute(gpu, spv, g.rows, 2);
          }
        }
        measure(row, v, sglab_float, g, reference, scale, m);
      } catch (const std::runtime_error& e) {
        row.compiles = false;
        row.error = e.what();
      }
      r.rows.push_back(std::move(row));
    }
  }
  return r;
}

Tables tables(const Result& r) {
  Tables t;
  t.csv = "method,evaluator,compiles,spirv_instructions,max_error,max_ulps_vs_sglab_float,grid_non_finite,stiff_points,"
          "stiff_negatives,stiff_non_finite\n";
  t.markdown = fmt::format(
      "# Exported shader code, compiled and run\n\n"
      "Every exportable method (`sglab export QUANTITY/METHOD --lang L`) as C, GLSL and HLSL, in float: the C compiled by "
      "`cc -O2` and loaded, the GLSL and HLSL compiled to SPIR-V by glslang (HLSL by its HLSL front end), validated by "
      "spirv-val, and run as a Vulkan compute shader on **{}**. The row `sglab float` is sglab's own float evaluation of "
      "the same formula, for comparison.\n\n"
      "- max error: max |value − reference| / reference at c = 1 on {}; the reference is the quantity's quadrature "
      "(hemispherical/vmf-tokuyoshi2024: H/A(λ), the normalized quantity that method returns). NaN/Inf there are counted "
      "apart (`grid NaN`).\n"
      "- ulps: max |value − sglab float| on the same grid, in float units in the last place of the larger of sglab "
      "float's value and the reference at c = 1 (raw ulps near zero, in the back-facing tail, would count differences "
      "far below the value's scale).\n"
      "- SPIR-V: instructions of the exported function and its helpers as glslang emits them, unoptimized, less those of "
      "the same compute entry point around an identity function — a cost proxy, not a cycle count.\n"
      "- stiff: outputs < 0 and NaN/Inf on {}.\n\n"
      "lavapipe evaluates exp, log and sqrt with LLVM's CPU code, not a GPU's hardware approximations: on a GPU the "
      "ulps (and the helpers' accuracy, which rests on exp and log) may differ. The C uses the C library's expm1f, "
      "erff and erfcf (the functions sglab's float path calls); GLSL and HLSL lack them and get the helpers written "
      "into the code (docs/export.md).\n\n"
      "| method | evaluator | compiles | SPIR-V instr. | max error | max diff. from sglab float (ulps) | grid NaN | stiff neg | stiff NaN/Inf |\n"
      "|---|---|---|---|---|---|---|---|---|\n",
      r.device, r.grid, r.stiff);
  for (const Row& w : r.rows) {
    const std::string instr = w.instructions >= 0 ? std::to_string(w.instructions) : "—";
    const std::string compiles = w.evaluator == "sglab float" ? "—" : w.compiles ? "yes" : "**no**";
    t.csv += fmt::format("{},{},{},{},{:.6e},{},{},{},{},{}\n", w.method, w.evaluator, w.compiles ? 1 : 0, w.instructions,
                         w.max_error, w.max_ulps, w.grid_non_finite, w.stiff_points, w.stiff_negatives, w.stiff_non_finite);
    if (!w.compiles) {
      t.markdown += fmt::format("| {} | {} | **no** | — | — | — | — | — | — |\n", w.method, w.evaluator);
      continue;
    }
    t.markdown += fmt::format("| {} | {} | {} | {} | {:.3e} | {:.0f} | {} | {} | {} |\n", w.method, w.evaluator, compiles, instr,
                              w.max_error, w.max_ulps, w.grid_non_finite, w.stiff_negatives, w.stiff_non_finite);
  }
  std::string failures;
  for (const Row& w : r.rows)
    if (!w.compiles) failures += fmt::format("\n- {} ({}): {}\n", w.method, w.evaluator, w.error.substr(0, 400));
  if (!failures.empty()) t.markdown += "\nFailures:\n" + failures;
  return t;
}

void write(const Options& o, const Result& r) {
  const Tables t = tables(r);
  runner::write_table(o.tables_dir, kTable, r.provenance, t.markdown, t.csv);
  std::fputs((runner::markdown_header(r.provenance) + t.markdown).c_str(), stdout);
}

}  // namespace sglab::cli::shader_export

namespace sglab::cli {

void add_shader_export_command(CLI::App& app) {
  auto o = std::make_shared<shader_export::Options>();
  auto* sub = app.add_subcommand("shader-export",
                                 "Every exportable method as C, GLSL and HLSL, compiled and run (Vulkan, lavapipe) against "
                                 "the reference and sglab float");
  sub->add_option("--tables-dir", o->tables_dir, "directory for shader_export.{md,csv}")->capture_default_str();
  sub->add_flag("--quick", o->quick, "the quick diffuse grid");
  add_constants_option(*sub, o->constants);
  sub->callback([o] {
    runner::check_output_paths({{"--tables-dir (shader_export.md)", std::filesystem::path(o->tables_dir) / "shader_export.md"},
                        {"--tables-dir (shader_export.csv)", std::filesystem::path(o->tables_dir) / "shader_export.csv"}},
                       {});
    shader_export::write(*o, shader_export::compute(*o));
  });
}

}  // namespace sglab::cli

namespace sglab::experiments {

std::vector<Step> shader_export_steps(const Places&) {
  return {sglab_step("shader-export",
                     "every exportable method as C, GLSL and HLSL, compiled and run on lavapipe (paper_tables/shader_export.*)",
                     {"shader-export"}, {"--quick"}, "--tables-dir")};
}

Experiment shader_export_experiment() {
  return {"shader-export", "exported C/GLSL/HLSL of every exportable method, compiled and run (shader_export.*)",
          cli::add_shader_export_command, shader_export_steps};
}

}  // namespace sglab::experiments
