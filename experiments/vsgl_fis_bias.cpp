// `sglab vsgl-fis-bias`: is the modified filtered importance sampling of VSGLs (Tokuyoshi 2016,
// supplement §3.3 and Algorithm 1; vsgl_generation.cpp) unbiased? For each RSM and N, the FIS
// VSGLs are built with seeds 1 … S and their sums compared with the exact sums over every RSM
// texel (u_i = Y(Φ_i(R_d + R_s)) the importance, ȳ the importance-weighted mean position):
//   importance    Σ u_i                       (exact by construction: every cluster gets W/N)
//   total_power   Σ Φ_i(R_d + R_s), RGB summed (FIS estimate: Σ_c of the clusters' powers)
//   first_moment  Σ u_i (y_i − ȳ) = 0         (estimate Σ_c W_c (μ_c − ȳ)); its bias is reported
//                                             as ‖mean − exact‖/(W σ), σ² = Σ u‖y − ȳ‖²/W
//   second_moment Σ u_i ‖y_i − ȳ‖²            (estimate Σ_c W_c (σ_c² + ‖μ_c − ȳ‖²))
// relative_bias = (mean over seeds − exact)/exact, standard_error = the standard error of that mean
// (sample standard deviation/√S, same units). RSMs: the shipped scenes' (at --rsm) and a random
// 8×8 RSM (positions, normals, RGB flux and albedo drawn independently of each other, so the
// summed values are not proportional to the importance).
// Writes TABLES/vsgl_fis_bias.{md,csv}.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "vsgl_fis_bias.hpp"

#include "atomic_file.hpp"
#include "table.hpp"
#include "option_checks.hpp"
#include "csv.hpp"
#include "render_job.hpp"
#include "sglab/render/rsm.hpp"
#include "sglab/render/vsgl_generation.hpp"
#include "sweep.hpp"
#include "registry.hpp"

namespace sglab::experiments::vsgl_fis_bias {
namespace {

namespace fs = std::filesystem;
using render::Vec3;

const std::vector<std::string> kScenes = {"scenes/cornell-glossy.json", "scenes/diffuse-only.json",
                                          "scenes/sg-light-near-wall.json"};
const std::vector<int> kCounts = {4, 16, 64};
constexpr int kRandomResolution = 8;
constexpr std::uint64_t kRandomRsmSeed = 20161001;  // arbitrary, fixed

// A random RSM: every field independent of the others.
render::ReflectiveShadowMap random_rsm(int res, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  auto u = [&] { return double(rng() >> 11) * 0x1.0p-53; };
  render::ReflectiveShadowMap rsm;
  rsm.resolution = res;
  rsm.texels.resize(std::size_t(res) * res);
  for (auto& v : rsm.texels) {
    v.valid = true;
    v.position = Vec3(u(), u(), u());
    v.normal = Vec3(u() - 0.5, u() - 0.5, 1).normalized();
    v.incoming = Vec3(u() - 0.5, u() - 0.5, 1).normalized();
    v.flux = render::Rgb(u(), u(), u());
    v.diffuse_reflectance = render::Rgb::Constant(0.1 + 0.8 * u());
  }
  return rsm;
}

struct Sums {
  double importance = 0, power = 0, second = 0;
  Vec3 first = Vec3::Zero();
};

struct Exact {
  Sums s;
  Vec3 mean = Vec3::Zero();
};

Exact exact_sums(const render::ReflectiveShadowMap& rsm) {
  Exact e;
  const render::VsglOptions o;
  const double ml = vsgl_mean_length(o.lambda_d, o.estimator);
  Vec3 weighted = Vec3::Zero();
  for (const auto& v : rsm.texels) {
    const auto s = render::vpl_sums(v, Vec3::Zero(), ml, o.estimator);
    e.s.importance += s.position.weight;
    weighted += s.position.offset;
  }
  e.mean = weighted / e.s.importance;
  for (const auto& v : rsm.texels) {
    const auto s = render::vpl_sums(v, e.mean, ml, o.estimator);
    e.s.power += (s.diffuse.power + s.specular.power).sum();
    e.s.first += s.position.offset;
    e.s.second += s.position.squared_offset;
  }
  return e;
}

Sums estimate(const render::VsglSet& set, const Vec3& mean) {
  Sums s;
  for (const auto& c : set.clusters) {
    s.importance += c.position_weight;
    s.power += (c.diffuse_power + c.specular_power).sum();
    s.first += c.position_weight * (c.mean - mean);
    s.second += c.position_weight * (c.variance + (c.mean - mean).squaredNorm());
  }
  return s;
}

struct Stat {  // running mean and variance (Welford)
  double n = 0, mean = 0, m2 = 0;
  void add(double x) {
    ++n;
    const double d = x - mean;
    mean += d / n;
    m2 += d * (x - mean);
  }
  double standard_error() const { return n > 1 ? std::sqrt(m2 / (n - 1) / n) : NAN; }
};

// The rows of one RSM: per N, the four sums' means over the seeds against the exact sums.
void rsm_rows(const std::string& name, const render::ReflectiveShadowMap& rsm, int seeds, std::vector<Row>& out) {
  const Exact e = exact_sums(rsm);
  const double sigma = std::sqrt(e.s.second / e.s.importance);
  for (const int n : kCounts) {
    Stat importance, power, second;
    Stat first[3];
    for (int seed = 1; seed <= seeds; ++seed) {
      render::VsglOptions v;
      v.mode = render::VsglMode::fis;
      v.count = n;
      v.seed = std::uint64_t(seed);
      const Sums s = estimate(render::build_vsgls(rsm, v), e.mean);
      importance.add(s.importance);
      power.add(s.power);
      second.add(s.second);
      for (int k = 0; k < 3; ++k) first[k].add(s.first(k));
    }
    const Vec3 first_mean(first[0].mean, first[1].mean, first[2].mean);
    const double first_scale = e.s.importance * sigma;
    const double first_se = std::sqrt(std::pow(first[0].standard_error(), 2) + std::pow(first[1].standard_error(), 2) +
                                      std::pow(first[2].standard_error(), 2));
    out.push_back({name, n, "importance", e.s.importance, importance.mean,
                   (importance.mean - e.s.importance) / e.s.importance, importance.standard_error() / e.s.importance});
    out.push_back({name, n, "total_power", e.s.power, power.mean, (power.mean - e.s.power) / e.s.power,
                   power.standard_error() / e.s.power});
    out.push_back({name, n, "first_moment", e.s.first.norm(), first_mean.norm(),
                   (first_mean - e.s.first).norm() / first_scale, first_se / first_scale});
    out.push_back({name, n, "second_moment", e.s.second, second.mean, (second.mean - e.s.second) / e.s.second,
                   second.standard_error() / e.s.second});
  }
}

}  // namespace

Result compute(const Options& o) {
  if (o.seeds < 2 || o.seeds > 100000)
    throw runner::InputError(fmt::format("--seeds {} is outside [2, 100000]", o.seeds));
  if (o.rsm < 1 || o.rsm > 1024) throw runner::InputError(fmt::format("--rsm {} is outside [1, 1024]", o.rsm));
  std::vector<std::pair<std::string, render::ReflectiveShadowMap>> rsms;
  for (const auto& path : kScenes) {
    frontend::RenderJob job;
    job.scene_path = path;
    rsms.emplace_back(path, render::render_rsm(frontend::load_scene(job), o.rsm));
  }
  rsms.emplace_back(fmt::format("random {0}×{0} RSM (seed {1})", kRandomResolution, kRandomRsmSeed),
                    random_rsm(kRandomResolution, kRandomRsmSeed));
  Result r;
  r.options = o;
  r.provenance.command = fmt::format("sglab vsgl-fis-bias --seeds {} --rsm {}", o.seeds, o.rsm) +
                         runner::option_argument("--tables-dir", o.tables_dir, Options{}.tables_dir);
  for (const auto& [name, rsm] : rsms) rsm_rows(name, rsm, o.seeds, r.rows);
  return r;
}

Tables tables(const Result& r) {
  const Options& o = r.options;
  Tables t;
  runner::append_csv_record(t.csv, std::vector<std::string>{"rsm", "n", "quantity", "exact", "mean_estimate",
                                                            "relative_bias", "standard_error", "seeds"});
  t.markdown = fmt::format(
      "# Bias of the FIS VSGLs (Tokuyoshi 2016, modified FIS) against the exact sums\n\n"
      "Each row: N FIS VSGLs built with seeds 1 … {} from one RSM ({}×{} for the shipped scenes), their sums compared "
      "with the exact sums over every texel (u = Y(Φ(R_d + R_s)) the importance, ȳ the importance-weighted mean): "
      "importance Σu (exact by construction), total power ΣΦ(R_d + R_s) (RGB summed), first moment Σu(y − ȳ) = 0 (bias "
      "given as ‖mean − exact‖/(Wσ), σ² = Σu‖y − ȳ‖²/W), second moment Σu‖y − ȳ‖². Relative bias = (mean over seeds − "
      "exact)/exact, ± its standard error (sample sd/√seeds). A |bias| well above 2 standard errors is a real bias: "
      "the "
      "per-sample mip level and the trilinear interpolation between levels make the estimator biased for every sum but "
      "the importance.\n\n"
      "| RSM | N | total power bias | ± s.e. | first moment bias | ± s.e. | second moment bias | ± s.e. | importance "
      "bias |\n"
      "|---|---|---|---|---|---|---|---|---|\n",
      o.seeds, o.rsm, o.rsm);
  for (const Row& row : r.rows)
    runner::append_csv_record(
        t.csv, std::vector<std::string>{row.rsm, std::to_string(row.n), row.quantity, runner::csv_number(row.exact),
                                        runner::csv_number(row.mean), runner::csv_number(row.bias),
                                        runner::csv_number(row.standard_error), std::to_string(o.seeds)});
  // One Markdown line per (RSM, N): its four rows, importance first.
  for (std::size_t i = 0; i + 3 < r.rows.size(); i += 4) {
    const Row* q = &r.rows[i];
    t.markdown += fmt::format(
        "| {} | {} | {:+.2f} % | {:.2f} % | {:.2f} % | {:.2f} % | {:+.2f} % | {:.2f} % | {:+.1e} |\n", q[0].rsm, q[0].n,
        100 * q[1].bias, 100 * q[1].standard_error, 100 * q[2].bias, 100 * q[2].standard_error, 100 * q[3].bias,
        100 * q[3].standard_error, q[0].bias);
  }
  return t;
}

void write(const Result& r) {
  const Tables t = tables(r);
  runner::write_and_show_table(r.options.tables_dir, "vsgl_fis_bias", r.provenance, t.markdown, t.csv);
}

}  // namespace sglab::experiments::vsgl_fis_bias

namespace sglab::experiments {

void add_vsgl_fis_bias_command(CLI::App& app, const runner::RunContext& run) {
  auto o = std::make_shared<vsgl_fis_bias::Options>();
  auto* sub = app.add_subcommand("vsgl-fis-bias",
                                 "bias of the FIS VSGLs' sums (power, moments) against the exact sums, over seeds");
  sub->add_option("--seeds", o->seeds, "seeds 1 … S per RSM and N")->capture_default_str();
  sub->add_option("--rsm", o->rsm, "RSM resolution of the shipped scenes")->capture_default_str();
  frontend::add_tables_option(*sub, run.places, vsgl_fis_bias::kDir, o->tables_dir,
                              "directory for vsgl_fis_bias.{md,csv}");
  sub->callback([o, run] { vsgl_fis_bias::write(runner::with_run(vsgl_fis_bias::compute(*o), run)); });
}

std::vector<Step> vsgl_fis_bias_steps(const runner::Places&) {
  return std::vector<Step>{
      sglab_step("vsgl-fis-bias",
                 "bias of the FIS VSGLs' sums against the exact sums over 64 seeds (paper_tables/vsgl_fis_bias.*)",
                 {"vsgl-fis-bias"}, {"--seeds", "8", "--rsm", "16"})};
}

Experiment vsgl_fis_bias_experiment() {
  return {"vsgl-fis-bias", "bias of the FIS VSGLs' sums against the exact sums over seeds (vsgl_fis_bias.*)",
          add_vsgl_fis_bias_command, vsgl_fis_bias_steps};
}

}  // namespace sglab::experiments
