// `sglab shader-export` (shader_export.hpp).
#include "shader_export.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>

#include <fmt/core.h>
#include <fmt/ranges.h>
#include <tbb/parallel_for.h>

#include "constant_sets.hpp"
#include "error_grid.hpp"
#include "option_checks.hpp"
#include "registry.hpp"
#include "sglab/sg.hpp"
#include "sglab/stiff_cases.hpp"
#include "stability_atlas.hpp"
#include "toolchain.hpp"

namespace sglab::experiments::shader_export {
namespace {

const char* const kTable = "shader_export";
const std::vector<std::string> kEvaluators = {"sglab float", "c", "glsl", "hlsl"};

bool is_diffuse(const Quantity& q) {
  return q.columns.size() == 2 && q.columns[0].kind == ColumnKind::sharpness &&
         q.columns[1].kind == ColumnKind::cosine && !q.reference_method.empty();
}
bool is_specular(const Quantity& q) { return q.name == "specular"; }
// The export-only filtering weights (shader::export_only_quantities): each against the same
// template evaluated in double.
bool is_filtering(const Quantity& q) { return shader::is_export_only(q); }

// What a method's value is compared with: the quantity's reference, except for the normalized
// vMF form of the hemispherical integral, which returns H/A(λ) (its registry entry says so).
double reference_for(const Method& m, const Method& ref, std::span<const double> args) {
  const double v = ref.eval_double(args);
  return m.name == "vmf-tokuyoshi2024" ? v / sg_integral(args[0]) : v;
}

// The spacing of floats at |x|.
float float_ulp(float x) {
  const float a = std::fabs(x);
  return std::nextafter(a, std::numeric_limits<float>::infinity()) - a;
}

// The grids of one kind of quantity (diffuse (λ, c) or specular): the error grid's rows, then the
// stiff grid's, as float inputs, and per error-grid point its reference and error scale.
struct Grids {
  std::size_t arity = 0;
  std::vector<float> rows;  // error grid, then stiff grid; `arity` floats a row
  std::size_t grid_points = 0, stiff_points = 0;
  std::vector<double> args;           // per error-grid point, as the float inputs, in double (arity each)
  std::vector<std::size_t> scale_of;  // per error-grid point: the index of the point whose reference is its scale
  // The error is relative to each point's own reference (the filtering weights), and points whose
  // reference is below FLT_MIN (an underflowed weight) are left out of the error and the ulps.
  bool relative = false;
  std::span<const double> point(std::size_t k) const { return {&args[arity * k], arity}; }
};

void add_error_point(Grids& g, std::span<const double> a) {
  for (double x : a) {
    g.rows.push_back(float(x));
    g.args.push_back(double(float(x)));
  }
}

Grids diffuse_grids(bool quick) {
  Grids g;
  g.arity = 2;
  const fit::DiffuseAxes axes = fit::diffuse_grid_axes(quick);
  const std::size_t nc = axes.cosines.size();
  for (std::size_t i = 0; i < axes.sharpnesses.size(); ++i)
    for (double c : axes.cosines) {
      const double a[2] = {axes.sharpnesses[i], c};
      add_error_point(g, a);
      g.scale_of.push_back(i * nc + nc - 1);  // the reference at c = 1 (the last cosine), same λ
    }
  g.grid_points = g.args.size() / 2;
  std::vector<double> ls = stiff::sharpnesses();
  for (double l : stiff::extreme_sharpnesses())
    if (l <= double(std::numeric_limits<float>::max())) ls.push_back(l);
  for (double l : ls)
    for (double c : stiff::cosines()) g.rows.insert(g.rows.end(), {float(l), float(c)});
  g.stiff_points = g.rows.size() / 2 - g.grid_points;
  return g;
}

// Specular: error-vs-time's specular grid; the stiff grid is the stability atlas's grid of the
// quantity (registry_grid, rows with a value past FLT_MAX left out: the float inputs).
Grids specular_grids(const Quantity& q, bool quick) {
  Grids g;
  g.arity = 6;
  const fit::SpecularGridPoints points = fit::specular_grid_points(quick);
  for (std::size_t k = 0; k < points.args.size(); k += 6) {
    add_error_point(g, std::span<const double>(&points.args[k], 6));
    const std::size_t i = k / 6;
    g.scale_of.push_back(i - i % points.per_peak);
  }
  g.grid_points = g.args.size() / 6;
  const atlas::Grid stiff = atlas::registry_grid(q, quick);
  for (std::size_t r = 0; r < stiff.rows; ++r) {
    const std::vector<double> row = stiff.row(r);
    bool fits = true;
    for (double x : row) fits = fits && std::fabs(x) <= double(std::numeric_limits<float>::max());
    if (!fits) continue;
    for (double x : row) g.rows.push_back(float(x));
  }
  g.stiff_points = g.rows.size() / 6 - g.grid_points;
  return g;
}

// The filtering weights' grids: an error grid of moderate lobes (sharpness 0.1 … 1e4, β 1 … 100,
// κ 10 … 1e3, the second axis 0 … π from the first, which sits from the pole to the horizon) and a
// stiff grid (coincident, opposite, orthogonal and nearly coincident axes, grazing ones with z = 0
// and z = ±1e-8; sharpness 0 … FLT_MAX, β 0 … 1e4, κ 1e-8 … +∞). `lobe`: the lobe-aware weight's
// 10 columns (axis_i, λ_i, axis_j, λ_j, β, κ); else the normal-aware weight's 7 (n_i, n_j, σ_n²).
struct AxisPair {
  double a[3], b[3];
};
AxisPair axes_at(double theta, double delta, double phi) {
  return {{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)},
          {std::sin(theta + delta) * std::cos(phi), std::sin(theta + delta) * std::sin(phi), std::cos(theta + delta)}};
}

Grids filtering_grids(bool lobe, bool quick) {
  Grids g;
  g.arity = lobe ? 10 : 7;
  g.relative = true;
  const double pi = 3.14159265358979323846, inf = std::numeric_limits<double>::infinity();
  const double fmax = double(std::numeric_limits<float>::max());
  const std::vector<double> thetas = quick ? std::vector<double>{0.0, 1.2, pi / 2}
                                           : std::vector<double>{0.0, 0.5, 1.2, pi / 2 - 1e-3, pi / 2};
  const std::vector<double> deltas = quick ? std::vector<double>{0.0, 1e-3, 0.3, 2.0}
                                           : std::vector<double>{0.0, 1e-3, 0.01, 0.1, 0.3, 1.0, 2.0, pi};
  std::vector<AxisPair> pairs;
  for (double t : thetas)
    for (double d : deltas) pairs.push_back(axes_at(t, d, 0.7));
  auto add = [&](const AxisPair& p, std::span<const double> rest, bool error_point) {
    std::vector<double> row;
    if (lobe) row = {p.a[0], p.a[1], p.a[2], rest[0], p.b[0], p.b[1], p.b[2], rest[1], rest[2], rest[3]};
    else row = {p.a[0], p.a[1], p.a[2], p.b[0], p.b[1], p.b[2], rest[0]};
    if (error_point) {
      add_error_point(g, row);
      g.scale_of.push_back(g.scale_of.size());  // its own reference
    } else {
      for (double x : row) g.rows.push_back(float(x));
    }
  };
  const std::vector<double> ls = quick ? std::vector<double>{0.1, 10.0, 1e4}
                                       : std::vector<double>{0.1, 1.0, 10.0, 100.0, 1e3, 1e4};
  const std::vector<double> betas = quick ? std::vector<double>{1.0, 20.0} : std::vector<double>{1.0, 20.0, 100.0};
  const std::vector<double> kappas = quick ? std::vector<double>{100.0} : std::vector<double>{10.0, 100.0, 1e3};
  const std::vector<double> variances = {0.01, 0.05404477, 0.5, 2.0};
  for (const auto& p : pairs) {
    if (lobe) {
      for (double li : ls)
        for (double lj : ls)
          for (double b : betas)
            for (double k : kappas) {
              const double rest[4] = {li, lj, b, k};
              add(p, rest, true);
            }
    } else {
      for (double v : variances) add(p, std::span<const double>(&v, 1), true);
    }
  }
  g.grid_points = g.args.size() / g.arity;
  // Stiff: coincident (bit-identical), nearly coincident (1e-7 rad), orthogonal, opposite, and
  // axes in or just off the horizontal plane.
  std::vector<AxisPair> stiff_pairs = {
      axes_at(0.7, 0.0, 0.3),    axes_at(0.7, 1e-7, 0.3),    axes_at(0.7, pi / 2, 0.3),   axes_at(0.7, pi, 0.3),
      axes_at(pi / 2, 0.0, 1.1), axes_at(pi / 2, 1e-8, 1.1), axes_at(pi / 2, -1e-8, 1.1), axes_at(pi / 2, pi, 1.1)};
  const std::vector<double> stiff_ls = {0.0, 1e-8, 1.0, 1e8, 1e20, 1e30, fmax};
  for (const auto& p : stiff_pairs) {
    if (lobe) {
      for (double li : stiff_ls)
        for (double lj : stiff_ls)
          for (double b : {0.0, 1.0, 20.0, 1e4})
            for (double k : {1e-8, 1.0, 100.0, 1e30, inf}) {
              const double rest[4] = {li, lj, b, k};
              add(p, rest, false);
            }
    } else {
      for (double v : {0.0, 1e-30, 1e-8, 0.05404477, 1e8, fmax}) add(p, std::span<const double>(&v, 1), false);
    }
  }
  g.stiff_points = g.rows.size() / g.arity - g.grid_points;
  return g;
}

// The row's metrics from values on both grids.
void measure(Row& row, const std::vector<float>& v, const std::vector<float>& sglab_float, const Grids& g,
             const std::vector<double>& reference, const std::vector<double>& scale, const Method& m) {
  for (std::size_t k = 0; k < g.grid_points; ++k) {
    if (m.domain_error && m.domain_error(g.point(k))) continue;
    if (!std::isfinite(v[k])) {
      ++row.grid_non_finite;
      continue;
    }
    if (g.relative && !(scale[k] >= double(std::numeric_limits<float>::min()))) continue;
    row.max_error = std::max(row.max_error, std::fabs(double(v[k]) - reference[k]) / scale[k]);
    // In ulps of the larger of the value and the reference at the peak (float): near zero (the
    // back-facing tail) raw ulps count rounding far below the value's own scale (1e-31 against 0
    // is 2e8 ulps).
    const float magnitude = std::max(std::fabs(sglab_float[k]), float(scale[k]));
    const double u = std::fabs(double(v[k]) - double(sglab_float[k])) / double(float_ulp(magnitude));
    if (std::isfinite(sglab_float[k])) row.max_ulps = std::max(row.max_ulps, u);
  }
  std::vector<double> args(g.arity);
  for (std::size_t k = g.grid_points; k < g.grid_points + g.stiff_points; ++k) {
    for (std::size_t j = 0; j < g.arity; ++j) args[j] = double(g.rows[g.arity * k + j]);
    if (m.domain_error && m.domain_error(args)) continue;
    ++row.stiff_points;
    if (!std::isfinite(v[k])) ++row.stiff_non_finite;
    else if (v[k] < 0) ++row.stiff_negatives;
  }
}

// One exportable method: its grids, references and sglab float values, and its traced formula.
struct Prepared {
  std::string name;
  const Method* m = nullptr;
  const Grids* shared = nullptr;  // the diffuse or specular grids, or
  std::optional<Grids> own;       // the filtering weights' own
  std::vector<double> reference, scale;
  std::vector<float> sglab_float;
  shader::TracedMethod traced;
  const Grids& grids() const { return own ? *own : *shared; }
};

// Every exportable method prepared in order (the references are parallel loops of their own), the
// grids they share (Prepared::shared points at them: not to be copied or moved), and what the result
// says of the grids.
struct Preparation {
  Preparation(const Preparation&) = delete;
  Preparation& operator=(const Preparation&) = delete;
  const Options& o;
  Result& r;
  const Grids diffuse;
  std::optional<Grids> specular;
  std::map<std::string, std::vector<double>> quantity_reference;  // a quantity's grid's, computed once
  std::vector<Prepared> prepared;                                 // in the order of shader::exportable_methods()

  Preparation(const Options& opts, Result& result) : o(opts), r(result), diffuse(diffuse_grids(opts.quick)) {}

  void add(const std::string& name) {
    const ConstantSet& set = o.constants.set;
    const shader::MethodRef ref = shader::find_exportable(name);
    const Quantity& q = *ref.quantity;
    const Method& m = *ref.method;
    if (!is_diffuse(q) && !is_specular(q) && !is_filtering(q)) return;
    if (is_specular(q) && !specular) {
      specular = specular_grids(q, o.quick);
      r.specular_grid = fmt::format("error-vs-time's specular grid{} ({} points, inputs rounded to float)",
                                    o.quick ? " (quick)" : "", specular->grid_points);
      r.specular_stiff = fmt::format(
          "the stability atlas's grid of `specular`{} ({} points; rows with a value past FLT_MAX left out)",
          o.quick ? " (quick)" : "", specular->stiff_points);
    }
    Prepared& p = prepared.emplace_back();
    p.name = name;
    p.m = &m;
    if (is_filtering(q)) {
      p.own = filtering_grids(m.name == "lobe-weight", o.quick);
      r.filtering_grids.push_back(
          fmt::format("`{}`: {} error points, {} stiff points", name, p.own->grid_points, p.own->stiff_points));
    } else {
      p.shared = is_specular(q) ? &*specular : &diffuse;
    }
    const Grids& g = p.grids();
    std::vector<double>& reference = p.reference;
    reference.resize(g.grid_points);
    if (is_filtering(q)) {
      // The same template in double on the float inputs.
      const Method bound_ref = bind(m, set);
      for (std::size_t k = 0; k < g.grid_points; ++k) reference[k] = bound_ref.eval_double(g.point(k));
    } else if (const Method& refm = *q.find(q.reference_method);
               m.name == "vmf-tokuyoshi2024" || !quantity_reference.count(q.name)) {
      std::fprintf(stderr, "shader-export: the reference of %s (%zu points)\n", name.c_str(), g.grid_points);
      tbb::parallel_for(std::size_t(0), g.grid_points,
                        [&](std::size_t k) { reference[k] = reference_for(m, refm, g.point(k)); });
      if (m.name != "vmf-tokuyoshi2024") quantity_reference[q.name] = reference;
    } else {
      reference = quantity_reference[q.name];
    }
    p.scale.resize(g.grid_points);
    for (std::size_t k = 0; k < g.grid_points; ++k) p.scale[k] = reference[g.scale_of[k]];
    const Method bound = bind(m, set);
    const std::size_t n = g.rows.size() / g.arity;
    p.sglab_float.resize(n);
    for (std::size_t k = 0; k < n; ++k)
      p.sglab_float[k] = bound.eval_float(std::span<const float>(&g.rows[g.arity * k], g.arity));
    p.traced = shader::trace_method(q, m, set);
  }
};

// One (method, evaluator) row: the formula emitted, compiled and run (or sglab's own float
// evaluation), then measured; a compile failure is the row's error.
Row run_row(const Prepared& p, const std::string& evaluator, shader::VulkanCompute& gpu, std::mutex& device) {
  const Grids& g = p.grids();
  Row row;
  row.method = p.name;
  row.evaluator = evaluator;
  std::fprintf(stderr, "shader-export: %s, %s\n", p.name.c_str(), evaluator.c_str());
  try {
    std::vector<float> v;
    if (evaluator == "sglab float") {
      v = p.sglab_float;
    } else {
      const shader::Language lang = *shader::parse_language(evaluator);
      const shader::TracedMethod* one = &p.traced;
      const std::string src = shader::emit(std::span(one, 1), lang, "sglab export " + p.name + " --lang " + evaluator);
      if (lang == shader::Language::c) {
        v = shader::run_c(src, p.traced, g.rows);
      } else {
        const shader::Spirv spv = shader::compile_to_spirv(shader::compute_shader_source(src, p.traced, lang), lang);
        row.instructions = long(shader::method_instructions(spv, lang, g.arity));
        const std::lock_guard one_at_a_time(device);
        v = shader::run_compute(gpu, spv, g.rows, g.arity);
      }
    }
    measure(row, v, p.sglab_float, g, p.reference, p.scale, *p.m);
  } catch (const std::runtime_error& e) {
    row.compiles = false;
    row.error = e.what();
  }

  return row;
}

}  // namespace

Result compute(const Options& o) {
  Result r;
  r.provenance.quick = o.quick;
  r.provenance.command = "sglab shader-export";
  if (o.quick) r.provenance.command += " --quick";
  for (const auto& a : frontend::constants_arguments(o.constants)) r.provenance.command += " " + a;
  shader::VulkanCompute gpu;
  r.device = gpu.device_name();
  Preparation prep(o, r);
  const Grids& diffuse = prep.diffuse;
  r.grid = fmt::format("error-vs-time's diffuse grid{} ({} points, inputs rounded to float)", o.quick ? " (quick)" : "",
                       diffuse.grid_points);
  r.stiff = fmt::format(
      "λ ∈ {{0, 1e-8 … 1e8 (2 per decade), 1e10 … 1e35, FLT_MAX}} × the stiff cosines (±1 and the float/double "
      "steps around them, 0, ±1e-8, 15 interior values): {} points, those in each method's domain",
      diffuse.stiff_points);
  for (const auto& q : quantities())
    for (const auto& m : q.methods) {
      if (m.trace || m.name == q.reference_method || !(is_diffuse(q) || is_specular(q))) continue;
      r.not_exportable.push_back({q.name + "/" + m.name, shader::not_exportable_reason(q, m)});
    }
  for (const auto& name : shader::exportable_methods()) prep.add(name);
  // Every (method, evaluator) row, side by side: most of a row's time is compiling (cc, a
  // subprocess; glslang and the SPIR-V validator, in-process), so rows run in parallel keep every
  // core busy. The device runs one shader at a time. Each row is the same calls on the same inputs
  // wherever it runs, so the values do not depend on the order; the rows are kept in the table's
  // order.
  std::vector<Row> rows(prep.prepared.size() * kEvaluators.size());
  std::mutex device;
  tbb::parallel_for(std::size_t(0), rows.size(), [&](std::size_t i) {
    rows[i] = run_row(prep.prepared[i / kEvaluators.size()], kEvaluators[i % kEvaluators.size()], gpu, device);
  });
  r.rows = std::move(rows);
  return r;
}

Tables tables(const Result& r) {
  Tables t;
  t.csv =
      "method,evaluator,compiles,spirv_instructions,max_error,max_ulps_vs_sglab_float,grid_non_finite,stiff_points,"
      "stiff_negatives,stiff_non_finite\n";
  t.markdown = fmt::format(
      "# Exported shader code, compiled and run\n\n"
      "Every exportable method (`sglab export QUANTITY/METHOD --lang L`) as C, GLSL and HLSL, in float: the C compiled "
      "by "
      "`cc -O2` and loaded, the GLSL and HLSL compiled to SPIR-V by glslang (HLSL by its HLSL front end), validated by "
      "spirv-val, and run as a Vulkan compute shader on **{}**. The row `sglab float` is sglab's own float evaluation "
      "of "
      "the same formula, for comparison.\n\n"
      "- max error: max |value − reference| / reference at c = 1 on {}; the reference is the quantity's quadrature "
      "(hemispherical/vmf-tokuyoshi2024: H/A(λ), the normalized quantity that method returns). NaN/Inf there are "
      "counted "
      "apart (`grid NaN`).{}\n"
      "- ulps: max |value − sglab float| on the same grid, in float units in the last place of the larger of sglab "
      "float's value and the reference at c = 1 (`specular`: with the light at the mirror direction; raw ulps near "
      "zero, "
      "in the back-facing tail, would count differences far below the value's scale).\n"
      "- SPIR-V: instructions of the exported function and its helpers as glslang emits them, unoptimized, less those "
      "of "
      "the same compute entry point around an identity function — a cost proxy, not a cycle count.\n"
      "- stiff: outputs < 0 and NaN/Inf on {}.{}\n"
      "{}\n"
      "lavapipe evaluates exp, log, sqrt, sin and cos with LLVM's CPU code, not a GPU's hardware approximations: on a "
      "GPU the ulps (and the helpers' accuracy, which rests on exp and log) may differ. The GLSL and HLSL arithmetic "
      "is "
      "`precise` (SPIR-V NoContraction: evaluated as written, no reassociation or fused multiply-add). The C uses the "
      "C "
      "library's expm1f, erff, erfcf, sinf and cosf (the functions sglab's float path calls); GLSL and HLSL lack the "
      "first three and get helpers written into the code (docs/export.md).\n\n"
      "| method | evaluator | compiles | SPIR-V instr. | max error | max diff. from sglab float (ulps) | grid NaN | "
      "stiff neg | stiff NaN/Inf |\n"
      "|---|---|---|---|---|---|---|---|---|\n",
      r.device, r.grid,
      r.specular_grid.empty()
          ? std::string()
          : fmt::format(" `specular`: max |value − reference| / reference with the light at the mirror "
                        "direction (the peak) for the same α, λ and view, on {}; the reference is its "
                        "2D quadrature.",
                        r.specular_grid),
      r.stiff, r.specular_stiff.empty() ? std::string() : fmt::format(" `specular`: on {}.", r.specular_stiff),
      r.filtering_grids.empty()
          ? std::string()
          : fmt::format(
                "- `filtering/…` (the filtering weights of Tokuyoshi 2015 (lobe-aware filtering), App. E and D; not "
                "registry quantities, `sglab export` names them): max error is |value − w| / w against the same "
                "template evaluated in double on the float inputs (w < FLT_MIN, an underflowed weight, left out of the "
                "error and the ulps), ulps are of the value itself; the error grid has sharpness 0.1 … 1e4, β 1 … 100, "
                "κ 10 … 1e3 (σ_n² 0.01 … 2) and axes 0 … π apart from the pole to the horizon, the stiff grid "
                "coincident, "
                "nearly coincident, orthogonal, opposite and grazing axes with sharpness 0 … FLT_MAX, β 0 … 1e4, κ "
                "1e-8 … +∞ "
                "(σ_n² 0 … FLT_MAX): {}.\n",
                fmt::join(r.filtering_grids, "; ")));
  for (const Row& w : r.rows) {
    const std::string instr = w.instructions >= 0 ? std::to_string(w.instructions) : "—";
    const std::string compiles = w.evaluator == "sglab float" ? "—" : w.compiles ? "yes" : "**no**";
    t.csv += fmt::format("{},{},{},{},{:.6e},{},{},{},{},{}\n", w.method, w.evaluator, w.compiles ? 1 : 0,
                         w.instructions, w.max_error, w.max_ulps, w.grid_non_finite, w.stiff_points, w.stiff_negatives,
                         w.stiff_non_finite);
    if (!w.compiles) {
      t.markdown += fmt::format("| {} | {} | **no** | — | — | — | — | — | — |\n", w.method, w.evaluator);
      continue;
    }
    t.markdown += fmt::format("| {} | {} | {} | {} | {:.3e} | {:.0f} | {} | {} | {} |\n", w.method, w.evaluator,
                              compiles, instr, w.max_error, w.max_ulps, w.grid_non_finite, w.stiff_negatives,
                              w.stiff_non_finite);
  }
  if (!r.not_exportable.empty()) {
    t.markdown += "\nNot exportable (`sglab export` refuses them with exit status 2 and this reason):\n\n";
    for (const auto& n : r.not_exportable) t.markdown += fmt::format("- {}: {}\n", n.method, n.reason);
  }
  std::string failures;
  for (const Row& w : r.rows)
    if (!w.compiles) failures += fmt::format("\n- {} ({}): {}\n", w.method, w.evaluator, w.error.substr(0, 400));
  if (!failures.empty()) t.markdown += "\nFailures:\n" + failures;
  return t;
}

void write(const Options& o, const Result& r) {
  const Tables t = tables(r);
  runner::write_and_show_table(o.tables_dir, kTable, r.provenance, t.markdown, t.csv);
}

}  // namespace sglab::experiments::shader_export

namespace sglab::experiments {

void add_shader_export_command(CLI::App& app, const runner::RunContext& run) {
  auto o = std::make_shared<shader_export::Options>();
  auto* sub = app.add_subcommand(
      "shader-export",
      "Every exportable method as C, GLSL and HLSL, compiled and run (Vulkan, lavapipe) against "
      "the reference and sglab float");
  frontend::add_tables_option(*sub, run.places, shader_export::kDir, o->tables_dir,
                              "directory for shader_export.{md,csv}");
  sub->add_flag("--quick", o->quick, "the quick diffuse grid");
  frontend::add_constants_option(*sub, o->constants);
  sub->callback([o, run] {
    runner::check_output_paths(
        {{"--tables-dir (shader_export.md)", std::filesystem::path(o->tables_dir) / "shader_export.md"},
         {"--tables-dir (shader_export.csv)", std::filesystem::path(o->tables_dir) / "shader_export.csv"}},
        {});
    shader_export::write(*o, runner::with_run(shader_export::compute(*o), run));
  });
}

std::vector<Step> shader_export_steps(const runner::Places&) {
  return {sglab_step(
      "shader-export",
      "every exportable method as C, GLSL and HLSL, compiled and run on lavapipe (paper_tables/shader_export.*)",
      {"shader-export"}, {"--quick"})};
}

Experiment shader_export_experiment() {
  return {"shader-export", "exported C/GLSL/HLSL of every exportable method, compiled and run (shader_export.*)",
          add_shader_export_command, shader_export_steps};
}

}  // namespace sglab::experiments
