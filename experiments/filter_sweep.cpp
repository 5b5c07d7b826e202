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
#include "filter_sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "atomic_file.hpp"
#include "table.hpp"
#include "experiment_command.hpp"
#include "csv.hpp"
#include "parse_number.hpp"
#include "sweep.hpp"  // csv_number
#include "registry.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::cli {
namespace filter_sweep {
namespace {

namespace fs = std::filesystem;

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

// A statistic for the CSV: "" when it has no finite value (relative L2 over a subset whose reference
// is 0, e.g. receivers no VPL reaches, is +∞ in image_error's convention).
std::string stat_number(double x) { return std::isfinite(x) ? csv_number(x) : std::string(); }

std::string cell(double x, const char* format = "{:.4f}") { return std::isfinite(x) ? fmt::format(fmt::runtime(format), x) : "–"; }

// --roughness, --scale and --weights (InputError naming the bad item).
void parse_lists(const Options& o, Result& r) {
  for (const auto& t : split(o.roughness)) {
    try {
      r.roughness.push_back(parse_decimal<double>(t));
    } catch (const NumberError& e) {
      throw UsageError(fmt::format("--roughness: {} {}", quote(t), e.what()));
    }
  }
  for (const auto& t : split(o.scales)) {
    double x = 0;
    try {
      x = parse_decimal<double>(t);
    } catch (const NumberError& e) {
      throw UsageError(fmt::format("--scale: {} {}", quote(t), e.what()));
    }
    if (x != std::floor(x) || x < 1 || x > 64) throw UsageError(fmt::format("--scale: {} is not an integer in [1, 64]", quote(t)));
    r.scales.push_back(int(x));
  }
  for (const auto& t : split(o.weights)) r.weights.push_back(parse_weights_option(t));
}

// Every point's scene first: a bad roughness stops here, naming it.
std::vector<render::Scene> point_scenes(const Options& o, const std::vector<double>& roughness) {
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
  return scenes;
}

std::string command_line(const Options& o) {
  std::vector<std::string> args = {"filter-sweep", "--scene",   o.job.render.scene_path, "--roughness", o.roughness,
                                   "--scale",      o.scales,    "--weights",             o.weights};
  for (const auto& a : filter_job_arguments(o.job, false)) args.push_back(a);
  if (o.table != Options{}.table) args.insert(args.end(), {"--table", o.table});
  std::string command = "sglab";
  for (const auto& a : args) command += " " + quote_argument(a);
  return command;
}

Point point_summary(const render::FilterInputs& in) {
  Point p{in.width, in.height, in.vpl_count, 0, 0, in.seconds.low_res, in.seconds.reference};
  for (std::size_t k = 0; k < in.hit.size(); ++k) p.pixels_hit += in.hit[k] != 0, p.glossy_receivers += in.glossy[k] != 0;
  return p;
}

// Point (scale s, roughness k); the reference of roughness k is computed once, at its first scale,
// and kept (with its point's inputs) while the roughness's other scales use it.
void compute_points(const Options& o, const std::vector<render::Scene>& scenes, render::FilterInputOptions input_options,
                    Result& r) {
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [start] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const std::size_t n = scenes.size() * r.scales.size();
  for (std::size_t k = 0; k < scenes.size(); ++k) {
    render::FilterInputs first;
    for (std::size_t s = 0; s < r.scales.size(); ++s) {
      const std::size_t point = k * r.scales.size() + s;
      if (!o.quiet) {
        std::fprintf(stderr, "filter-sweep [%zu/%zu] floor.roughness=%g, scale %d (%.1f s)\n", point + 1, n, r.roughness[k],
                     r.scales[s], elapsed());
        input_options.progress = [&](std::string_view stage, double fraction) {
          if (fraction == 1.0) std::fprintf(stderr, "  %.*s done (%.1f s)\n", int(stage.size()), stage.data(), elapsed());
        };
      }
      input_options.scale = r.scales[s];
      input_options.reference = s == 0 ? nullptr : &first.reference;
      try {
        render::FilterInputs inputs = render::prepare_filter_inputs(scenes[k], input_options);
        for (const auto w : r.weights)
          r.rows.push_back({r.scales[s], r.roughness[k], w, render::upsample_indirect(inputs, w, o.job.parameters), point});
        r.points.push_back(point_summary(inputs));
        if (s == 0) first = std::move(inputs);
      } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
      }
      r.points.back().seconds_reference = first.seconds.reference;  // the reference's time, also for the rows that reused it
    }
  }
  r.seconds = elapsed();
}

std::string points_csv(const Result& r) {
  std::string points;
  append_csv_record(points, std::vector<std::string>{"scale", "floor_roughness", "weights", "relative_l2", "smape", "rmse", "max_abs",
                                                     "glossy_relative_l2", "glossy_smape", "glossy_rmse", "diffuse_relative_l2",
                                                     "diffuse_smape", "diffuse_rmse", "fallback_pixels", "pixels_hit",
                                                     "glossy_receivers", "vpl_count", "seconds_low_res", "seconds_upsampling",
                                                     "seconds_reference"});
  for (const Row& row : r.rows) {
    const Point& p = r.points[row.point];
    const auto& e = row.result;
    append_csv_record(points, std::vector<std::string>{
                                  std::to_string(row.scale), csv_number(row.roughness), std::string(render::filter_weights_name(row.weights)), stat_number(e.all.relative_l2),
                                  stat_number(e.all.smape), stat_number(e.all.rmse), stat_number(e.all.max_abs), stat_number(e.glossy.relative_l2),
                                  stat_number(e.glossy.smape), stat_number(e.glossy.rmse), stat_number(e.diffuse.relative_l2),
                                  stat_number(e.diffuse.smape), stat_number(e.diffuse.rmse), std::to_string(e.fallback_pixels),
                                  std::to_string(p.pixels_hit), std::to_string(p.glossy_receivers), std::to_string(p.vpl_count),
                                  csv_number(p.seconds_low_res), stat_number(e.seconds), csv_number(p.seconds_reference)});
  }
  return points;
}

// The CSV table: one row per (roughness, weights), the statistics of the Markdown table.
std::string summary_csv(const Result& r) {
  std::string csv;
  append_csv_record(csv, std::vector<std::string>{"scale", "floor_roughness", "weights", "relative_l2", "glossy_relative_l2",
                                                  "diffuse_relative_l2", "smape", "glossy_smape", "diffuse_smape", "rmse",
                                                  "fallback_pixels"});
  for (const Row& row : r.rows) {
    const auto& e = row.result;
    append_csv_record(csv, std::vector<std::string>{std::to_string(row.scale), csv_number(row.roughness), std::string(render::filter_weights_name(row.weights)),
                                                    stat_number(e.all.relative_l2), stat_number(e.glossy.relative_l2),
                                                    stat_number(e.diffuse.relative_l2), stat_number(e.all.smape),
                                                    stat_number(e.glossy.smape), stat_number(e.diffuse.smape), stat_number(e.all.rmse),
                                                    std::to_string(e.fallback_pixels)});
  }
  return csv;
}

std::string markdown_intro(const Result& r) {
  const Options& o = r.options;
  const auto& p = o.job.parameters;
  const Point& in0 = r.points.front();
  return fmt::format(
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
      o.job.render.scene_path,
      o.job.render.overrides.empty() ? "" : fmt::format(" with `--set {}`", fmt::join(o.job.render.overrides, "`, `--set ")),
      in0.width, in0.height, fmt::join(r.scales, ", "), o.job.source, r.rsm_resolution, in0.vpl_count,
      2 * p.radius, 2 * p.radius, p.spatial_sigma, p.sigma_n2, p.depth_sigma, p.beta, p.kappa, p.nu, p.diffuse_sharpness, o.table);
}

// One Markdown table: relative L2 or SMAPE over a subset of pixels (0 all, 1 glossy, 2 diffuse
// receivers), per weighting, and each weighting in `compared` relative to normal.
std::string markdown_table(const Result& r, bool smape, int subset, const std::vector<render::FilterWeights>& compared) {
  const char* subset_names[] = {"all pixels", "glossy receivers", "diffuse receivers"};
  const auto find = [&](int scale, double a, render::FilterWeights w) -> const Row* {
    for (const Row& row : r.rows)
      if (row.scale == scale && row.roughness == a && row.weights == w) return &row;
    return nullptr;
  };
  const auto pick = [subset, smape](const Row* row) {
    if (!row) return std::numeric_limits<double>::quiet_NaN();
    const render::ImageError& e = subset == 0 ? row->result.all : subset == 1 ? row->result.glossy : row->result.diffuse;
    return smape ? e.smape : e.relative_l2;
  };
  std::string md = fmt::format("## {}, {}\n\n| scale | floor α |", smape ? "SMAPE" : "Relative L2", subset_names[subset]);
  std::string rule = "|---|---|";
  for (const auto w : r.weights) {
    md += fmt::format(" {} |", render::filter_weights_name(w));
    rule += "---|";
  }
  for (const auto w : compared) {
    md += fmt::format(" {} vs normal |", render::filter_weights_name(w));
    rule += "---|";
  }
  md += "\n" + rule + "\n";
  for (const int sc : r.scales)
    for (const double a : r.roughness) {
      md += fmt::format("| {} | {:g} |", sc, a);
      // (appended piecewise: GCC 12 warns falsely (-Wrestrict) on " " + std::string + " |")
      for (const auto w : r.weights) md += fmt::format(" {} |", cell(pick(find(sc, a, w))));
      for (const auto w : compared)
        md += fmt::format(" {} |", cell(percent_change(pick(find(sc, a, w)), pick(find(sc, a, render::FilterWeights::normal))),
                                        "{:+.1f} %"));
      md += "\n";
    }
  return md + "\n";
}

// The Markdown summary: relative L2 and SMAPE per weighting, all pixels and by receiver kind.
std::string markdown(const Result& r) {
  std::string md = markdown_intro(r);
  // Each weighting other than spatial and normal is also given relative to normal.
  std::vector<render::FilterWeights> compared;
  if (std::find(r.weights.begin(), r.weights.end(), render::FilterWeights::normal) != r.weights.end())
    for (const auto w : r.weights)
      if (w != render::FilterWeights::normal && w != render::FilterWeights::spatial) compared.push_back(w);
  for (const bool smape : {false, true})
    for (int subset = 0; subset < 3; ++subset) md += markdown_table(r, smape, subset, compared);
  std::size_t fallbacks = 0;
  for (const Row& row : r.rows) fallbacks += row.result.fallback_pixels;
  md += fmt::format(
      "Pixels whose range weights all underflowed (they fall back to spatial weights): {} over all rows. Times "
      "(wall clock, all cores) are in the per-row CSV.\n",
      fallbacks);
  return md;
}

}  // namespace

Result compute(const Options& options) {
  Result r;
  r.options = options;
  Options& o = r.options;
  apply_filter_constants(o.job);
  if (o.job.render.scene_path.empty()) throw UsageError("filter-sweep needs --scene SCENE.json");
  if (o.table.empty() || o.table.find_first_of("/\\ ") != std::string::npos)
    throw UsageError(fmt::format("--table {} is not a file name", quote(o.table)));
  parse_lists(o, r);
  check_filter_parameters(o.job.parameters);
  const render::FilterInputOptions input_options = filter_input_options(o.job);
  r.rsm_resolution = input_options.rsm_resolution;
  const std::vector<render::Scene> scenes = point_scenes(o, r.roughness);
  if (!scenes.empty() && !r.scales.empty()) {  // bounded as if every point's inputs were kept, all at the finest scale
    render::FilterInputOptions finest = input_options;
    finest.scale = *std::min_element(r.scales.begin(), r.scales.end());
    check_filter_memory(scenes.front(), finest, scenes.size() * r.scales.size());
  }
  r.provenance.command = command_line(o);
  compute_points(o, scenes, input_options, r);
  return r;
}

Tables tables(const Result& r) { return {points_csv(r), markdown(r), summary_csv(r)}; }

void write(const Result& r) {
  const Options& o = r.options;
  const Tables t = tables(r);
  write_table(o.out, o.table + "_points", r.provenance, "", t.points_csv);
  write_table(o.tables_dir, o.table, r.provenance, t.markdown, t.csv);
  std::fputs((markdown_header(r.provenance) + t.markdown).c_str(), stdout);
  std::fprintf(stderr, "filter-sweep: wrote %s/%s.{md,csv} and %s/%s_points.csv (%.1f s)\n", o.tables_dir.c_str(), o.table.c_str(),
               o.out.c_str(), o.table.c_str(), r.seconds);
}

}  // namespace filter_sweep

void add_filter_sweep_command(CLI::App& app) {
  auto opts = std::make_shared<filter_sweep::Options>();
  auto* sub = app.add_subcommand("filter-sweep",
                                 "Upsampling error per weighting (spatial, normal, lobe) over the floor's roughness (paper_tables/filtering.*)");
  sub->add_option("--scene", opts->job.render.scene_path, "scene JSON with an object named floor")->required();
  sub->add_option("--roughness", opts->roughness, "floor GGX roughness values, comma-separated")->capture_default_str();
  sub->add_option("--weights", opts->weights, "weightings, comma-separated (spatial, normal, lobe, lobe-depth)")->capture_default_str();
  add_places_options(*sub, opts->out, opts->tables_dir, "directory for the per-row CSV", "directory for NAME.md and NAME.csv");
  sub->add_option("--table", opts->table, "table name")->capture_default_str();
  sub->add_flag("--quiet", opts->quiet, "no progress on stderr");
  sub->add_option("--scale", opts->scales, "scales (the indirect light at 1/SCALE resolution), comma-separated")->capture_default_str();
  add_filter_job_options(*sub, opts->job, false);
  sub->callback([opts] { filter_sweep::write(filter_sweep::compute(*opts)); });
}

}  // namespace sglab::cli

namespace sglab::experiments {

// Lobe-aware filtering: both weightings on cornell-glossy (`sglab filter`), then the roughness sweep.
std::vector<Step> filtering_steps(const Places& p) {
  std::vector<Step> v;
  for (const char* weights : {"normal", "lobe"}) {
    const std::string base = p.out + "/filtering/cornell-glossy-" + weights;
    v.push_back(sglab_step(std::string("filter-cornell-glossy-") + weights,
                           std::string("upsampling 1/4-resolution indirect light with ") +
                               (std::string(weights) == "normal" ? "normal/depth" : "lobe-aware") + " weights (EXR + stats)",
                           {"filter", "scenes/cornell-glossy.json", "--weights", weights, "--out", base + ".exr", "--stats",
                            base + ".json"},
                           {"--width", "64", "--height", "64"}, "", true));
  }
  v.push_back(sglab_step("filter-sweep",
                         "upsampling error per weighting over the floor's roughness on cornell-glossy (paper_tables/filtering.*)",
                         {"filter-sweep", "--scene", "scenes/cornell-glossy.json", "--out", p.out + "/filtering"},
                         {"--width", "64", "--height", "64"}, "--tables-dir", true));
  return v;
}

Experiment filtering_experiment() {
  return {"filter-sweep",
          "upsampling error per weighting (normal/depth vs lobe-aware) over the floor's roughness (filtering.*)",
          cli::add_filter_sweep_command, filtering_steps};
}

}  // namespace sglab::experiments
