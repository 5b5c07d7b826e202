// `sglab filter-sweep --scene S --roughness v1,v2,… [--scale s1,s2,…] [--weights spatial,normal,lobe,lobe-depth]
//  [filter options] [--out DIR] [--tables-dir DIR] [--table NAME] [--quiet]`:
// the error of upsampled indirect light against the full-resolution exact VPL sum, per weighting,
// over the floor's GGX roughness (`--set floor.roughness=v` at each point, after the job's own --set
// overrides) and the upsampling scale. At each (roughness, scale) the G-buffers and the
// low-resolution indirect light are computed once and every weighting upsamples the same data
// (filtering.hpp), so the rows differ only in the weights; the reference is computed once per
// roughness. Every point's scene is validated before anything runs (exit status 2 naming the
// value). Outputs: DIR/NAME_points.csv (every row, all statistics and times) and
// TABLES/NAME.{md,csv} headed by the command.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "atomic_file.hpp"
#include "commands.hpp"
#include "csv.hpp"
#include "filter_job.hpp"
#include "parse_number.hpp"
#include "sweep.hpp"  // csv_number

namespace sglab::cli {
namespace {

namespace fs = std::filesystem;

struct Options {
  FilterJob job;
  std::string roughness = "0.02,0.05,0.1,0.2,0.4,0.7";
  std::string scales = "2,4,8";
  std::string weights = "spatial,normal,lobe,lobe-depth";
  std::string out = "results/filtering";
  std::string tables_dir = "paper_tables";
  std::string table = "filtering";
  bool quiet = false;
};

std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> parts;
  for (std::size_t start = 0;;) {
    const auto comma = text.find(',', start);
    parts.push_back(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return parts;
}

struct Row {
  int scale;
  double roughness;
  render::FilterWeights weights;
  render::FilterResult result;
  const render::FilterInputs* inputs;  // of its point (alive while the row is written)
};

// A statistic for the CSV: "" when it has no finite value (relative L2 over a subset whose reference
// is 0, e.g. receivers no VPL reaches, is +∞ in image_error's convention).
std::string stat_number(double x) { return std::isfinite(x) ? csv_number(x) : std::string(); }

std::string cell(double x, const char* format = "{:.4f}") { return std::isfinite(x) ? fmt::format(fmt::runtime(format), x) : "–"; }

void write_file(const fs::path& path, const std::string& text) {
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
  AtomicFile f(path);
  f.write(text);
  f.commit();
}

void run(const Options& options) {
  Options o = options;
  apply_filter_constants(o.job);
  if (o.job.render.scene_path.empty()) throw UsageError("filter-sweep needs --scene SCENE.json");
  if (o.table.empty() || o.table.find_first_of("/\\ ") != std::string::npos)
    throw UsageError(fmt::format("--table '{}' is not a file name", o.table));
  std::vector<double> roughness;
  for (const auto& t : split(o.roughness)) {
    try {
      roughness.push_back(parse_decimal<double>(t));
    } catch (const NumberError& e) {
      throw UsageError(fmt::format("--roughness: '{}' {}", t, e.what()));
    }
  }
  std::vector<int> scales;
  for (const auto& t : split(o.scales)) {
    double x = 0;
    try {
      x = parse_decimal<double>(t);
    } catch (const NumberError& e) {
      throw UsageError(fmt::format("--scale: '{}' {}", t, e.what()));
    }
    if (x != std::floor(x) || x < 1 || x > 64) throw UsageError(fmt::format("--scale: '{}' is not an integer in [1, 64]", t));
    scales.push_back(int(x));
  }
  std::vector<render::FilterWeights> weights;
  for (const auto& t : split(o.weights)) weights.push_back(parse_weights_option(t));
  check_filter_parameters(o.job.parameters);
  render::FilterInputOptions input_options = filter_input_options(o.job);
  // Every point's scene first: a bad roughness stops here, naming it.
  const nlohmann::json base = load_scene_document(o.job.render.scene_path, o.job.render.overrides);
  std::vector<render::Scene> scenes;
  for (const double a : roughness) {
    nlohmann::json doc = base;
    const std::string assignment = fmt::format("floor.roughness={}", a);
    try {
      render::apply_override(doc, assignment);
    } catch (const render::SceneError& e) {
      throw UsageError(fmt::format("--roughness {}: {}", a, e.what()));
    }
    try {
      scenes.push_back(scene_from_document(doc, o.job.render));
    } catch (const UsageError& e) {
      throw UsageError(fmt::format("--roughness {}: {}", a, e.what()));
    }
  }

  if (!scenes.empty() && !scales.empty()) {  // every point's inputs are kept: all at the finest scale bound it
    render::FilterInputOptions finest = input_options;
    finest.scale = *std::min_element(scales.begin(), scales.end());
    check_filter_memory(scenes.front(), finest, scenes.size() * scales.size());
  }

  std::vector<std::string> args = {"filter-sweep", "--scene",   o.job.render.scene_path, "--roughness", o.roughness,
                                   "--scale",      o.scales,    "--weights",             o.weights};
  for (const auto& a : filter_job_arguments(o.job, false)) args.push_back(a);
  if (o.table != Options{}.table) args.insert(args.end(), {"--table", o.table});
  std::string command = "sglab";
  for (const auto& a : args) command += " " + quote_argument(a);

  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [start] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  // Point (scale s, roughness k); the reference of roughness k is computed once, at its first scale.
  std::vector<render::FilterInputs> inputs(scenes.size() * scales.size());
  std::vector<Row> rows;
  for (std::size_t k = 0; k < scenes.size(); ++k) {
    for (std::size_t s = 0; s < scales.size(); ++s) {
      const std::size_t point = k * scales.size() + s;
      if (!o.quiet) {
        std::fprintf(stderr, "filter-sweep [%zu/%zu] floor.roughness=%g, scale %d (%.1f s)\n", point + 1, inputs.size(),
                     roughness[k], scales[s], elapsed());
        input_options.progress = [&](std::string_view stage, double fraction) {
          if (fraction == 1.0) std::fprintf(stderr, "  %.*s done (%.1f s)\n", int(stage.size()), stage.data(), elapsed());
        };
      }
      input_options.scale = scales[s];
      input_options.reference = s == 0 ? nullptr : &inputs[k * scales.size()].reference;
      try {
        inputs[point] = render::prepare_filter_inputs(scenes[k], input_options);
        for (const auto w : weights)
          rows.push_back({scales[s], roughness[k], w, render::upsample_indirect(inputs[point], w, o.job.parameters), &inputs[point]});
      } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
      }
    }
  }
  // The reference's time, for the rows that reused it.
  for (std::size_t k = 0; k < scenes.size(); ++k)
    for (std::size_t s = 1; s < scales.size(); ++s)
      inputs[k * scales.size() + s].seconds.reference = inputs[k * scales.size()].seconds.reference;

  // Every row, every statistic.
  std::string points;
  append_csv_record(points, std::vector<std::string>{"scale", "floor_roughness", "weights", "relative_l2", "smape", "rmse", "max_abs",
                                                     "glossy_relative_l2", "glossy_smape", "glossy_rmse", "diffuse_relative_l2",
                                                     "diffuse_smape", "diffuse_rmse", "fallback_pixels", "pixels_hit",
                                                     "glossy_receivers", "vpl_count", "seconds_low_res", "seconds_upsampling",
                                                     "seconds_reference"});
  for (const Row& r : rows) {
    std::size_t hit = 0, glossy = 0;
    for (std::size_t k = 0; k < r.inputs->hit.size(); ++k) hit += r.inputs->hit[k] != 0, glossy += r.inputs->glossy[k] != 0;
    const auto& e = r.result;
    append_csv_record(points, std::vector<std::string>{
                                  std::to_string(r.scale), csv_number(r.roughness), std::string(render::filter_weights_name(r.weights)), stat_number(e.all.relative_l2),
                                  stat_number(e.all.smape), stat_number(e.all.rmse), stat_number(e.all.max_abs), stat_number(e.glossy.relative_l2),
                                  stat_number(e.glossy.smape), stat_number(e.glossy.rmse), stat_number(e.diffuse.relative_l2),
                                  stat_number(e.diffuse.smape), stat_number(e.diffuse.rmse), std::to_string(e.fallback_pixels),
                                  std::to_string(hit), std::to_string(glossy), std::to_string(r.inputs->vpl_count),
                                  csv_number(r.inputs->seconds.low_res), stat_number(e.seconds), csv_number(r.inputs->seconds.reference)});
  }
  const std::string header = "# Generated by `" + command + "`; do not edit by hand.\n";
  write_file(fs::path(o.out) / (o.table + "_points.csv"), header + points);

  // The Markdown summary: relative L2 and SMAPE per weighting, all pixels and by receiver kind.
  const auto find = [&](int scale, double a, render::FilterWeights w) -> const Row* {
    for (const Row& r : rows)
      if (r.scale == scale && r.roughness == a && r.weights == w) return &r;
    return nullptr;
  };
  const auto& p = o.job.parameters;
  const auto& in0 = inputs.front();
  std::string md = fmt::format(
      "<!-- Generated by `{}`; do not edit by hand. -->\n"
      "# Upsampling indirect light: normal/depth-aware vs lobe-aware weights over the floor's roughness\n\n"
      "Scene `{}`{}, {}×{} pixels; indirect light computed at 1/scale resolution (scale {{{}}}; {} low-resolution "
      "source, RSM {}² → {} VPLs at the first point) and upsampled by joint bilateral upsampling over {}×{} low-resolution samples "
      "(image-space σ_s = {} low-resolution pixels) with the range weights:\n\n"
      "- **spatial**: none (Gaussian upsampling);\n"
      "- **normal**: G(n_p; n_q, 1/σ_n²)·g(z_p − z_q, (σ_z z_p)²), σ_n² = {}, σ_z = {} (relative depth);\n"
      "- **lobe-depth**: the lobe-aware directional weight q_ω^β times the normal weighting's depth term (what the lobes "
      "alone change);\n"
      "- **lobe**: lobe-aware q^β (Tokuyoshi 2015 (lobe-aware filtering), Eq. (12)/App. E for the lobes, App. A for the positions), "
      "β = {}, κ = {}, ν = {} scene units; diffuse lobe = SG of sharpness {:.4f} about the normal (= 2λ_c: App. D, the "
      "normal weight with σ_n² = (2λ_c + κ)/(βλ_cκ)), specular lobe = the GGX lobe's SG by the spherical warp "
      "(App. B: axis = reflected view, λ = (2/α²)/(4|ω_o·n|)).\n\n"
      "Diffuse and specular parts are upsampled separately (demodulated by albedo and f0). Error of the upsampled "
      "indirect light against the exact VPL sum at full resolution (core/render reference.hpp), all channels: "
      "relative L2 = ‖v − r‖/‖r‖, SMAPE = mean 2|v − r|/(|v| + |r|). **Glossy** receivers: the floor and the sphere; "
      "**diffuse**: the other surfaces. \"X vs normal\" = (X − normal)/normal: negative is better. Per-row data "
      "with RMSE, max error and times: `{}_points.csv` in the `--out` directory.\n\n",
      command, o.job.render.scene_path,
      o.job.render.overrides.empty() ? "" : fmt::format(" with `--set {}`", fmt::join(o.job.render.overrides, "`, `--set ")),
      in0.width, in0.height, fmt::join(scales, ", "), o.job.source, input_options.rsm_resolution, in0.vpl_count,
      2 * p.radius, 2 * p.radius, p.spatial_sigma, p.sigma_n2, p.depth_sigma, p.beta, p.kappa, p.nu, p.diffuse_sharpness, o.table);

  const auto has = [&](render::FilterWeights w) {
    for (const auto x : weights)
      if (x == w) return true;
    return false;
  };
  // Each weighting other than spatial and normal is also given relative to normal.
  std::vector<render::FilterWeights> compared;
  if (has(render::FilterWeights::normal))
    for (const auto w : weights)
      if (w != render::FilterWeights::normal && w != render::FilterWeights::spatial) compared.push_back(w);
  const char* subset_names[] = {"all pixels", "glossy receivers", "diffuse receivers"};
  for (const bool smape : {false, true}) {
    for (int subset = 0; subset < 3; ++subset) {
      const auto pick = [subset, smape](const Row* r) {
        if (!r) return std::numeric_limits<double>::quiet_NaN();
        const render::ImageError& e = subset == 0 ? r->result.all : subset == 1 ? r->result.glossy : r->result.diffuse;
        return smape ? e.smape : e.relative_l2;
      };
      md += fmt::format("## {}, {}\n\n| scale | floor α |", smape ? "SMAPE" : "Relative L2", subset_names[subset]);
      std::string rule = "|---|---|";
      for (const auto w : weights) {
        md += fmt::format(" {} |", render::filter_weights_name(w));
        rule += "---|";
      }
      for (const auto w : compared) {
        md += fmt::format(" {} vs normal |", render::filter_weights_name(w));
        rule += "---|";
      }
      md += "\n" + rule + "\n";
      for (const int sc : scales)
        for (const double a : roughness) {
          md += fmt::format("| {} | {:g} |", sc, a);
          // (appended piecewise: GCC 12 warns falsely (-Wrestrict) on " " + std::string + " |")
          for (const auto w : weights) md += fmt::format(" {} |", cell(pick(find(sc, a, w))));
          for (const auto w : compared)
            md += fmt::format(" {} |", cell(percent_change(pick(find(sc, a, w)), pick(find(sc, a, render::FilterWeights::normal))),
                                            "{:+.1f} %"));
          md += "\n";
        }
      md += "\n";
    }
  }
  std::size_t fallbacks = 0;
  for (const Row& r : rows) fallbacks += r.result.fallback_pixels;
  md += fmt::format(
      "Pixels whose range weights all underflowed (they fall back to spatial weights): {} over all rows. Times "
      "(wall clock, all cores) are in the per-row CSV.\n",
      fallbacks);

  // The CSV table: one row per (roughness, weights), the statistics of the Markdown table.
  std::string csv;
  append_csv_record(csv, std::vector<std::string>{"scale", "floor_roughness", "weights", "relative_l2", "glossy_relative_l2",
                                                  "diffuse_relative_l2", "smape", "glossy_smape", "diffuse_smape", "rmse",
                                                  "fallback_pixels"});
  for (const Row& r : rows) {
    const auto& e = r.result;
    append_csv_record(csv, std::vector<std::string>{std::to_string(r.scale), csv_number(r.roughness), std::string(render::filter_weights_name(r.weights)),
                                                    stat_number(e.all.relative_l2), stat_number(e.glossy.relative_l2),
                                                    stat_number(e.diffuse.relative_l2), stat_number(e.all.smape),
                                                    stat_number(e.glossy.smape), stat_number(e.diffuse.smape), stat_number(e.all.rmse),
                                                    std::to_string(e.fallback_pixels)});
  }
  write_file(fs::path(o.tables_dir) / (o.table + ".csv"), header + csv);
  write_file(fs::path(o.tables_dir) / (o.table + ".md"), md);
  std::fputs(md.c_str(), stdout);
  std::fprintf(stderr, "filter-sweep: wrote %s/%s.{md,csv} and %s/%s_points.csv (%.1f s)\n", o.tables_dir.c_str(), o.table.c_str(),
               o.out.c_str(), o.table.c_str(), elapsed());
}

}  // namespace

void add_filter_sweep_command(CLI::App& app) {
  auto opts = std::make_shared<Options>();
  auto* sub = app.add_subcommand("filter-sweep",
                                 "Upsampling error per weighting (spatial, normal, lobe) over the floor's roughness (paper_tables/filtering.*)");
  sub->add_option("--scene", opts->job.render.scene_path, "scene JSON with an object named floor")->required();
  sub->add_option("--roughness", opts->roughness, "floor GGX roughness values, comma-separated")->capture_default_str();
  sub->add_option("--weights", opts->weights, "weightings, comma-separated (spatial, normal, lobe, lobe-depth)")->capture_default_str();
  sub->add_option("--out", opts->out, "directory for the per-row CSV")->capture_default_str();
  sub->add_option("--tables-dir", opts->tables_dir, "directory for NAME.md and NAME.csv")->capture_default_str();
  sub->add_option("--table", opts->table, "table name")->capture_default_str();
  sub->add_flag("--quiet", opts->quiet, "no progress on stderr");
  sub->add_option("--scale", opts->scales, "scales (the indirect light at 1/SCALE resolution), comma-separated")->capture_default_str();
  add_filter_job_options(*sub, opts->job, false);
  sub->callback([opts] { run(*opts); });
}

}  // namespace sglab::cli
