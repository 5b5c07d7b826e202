// `sglab filter-sweep --noisy LIST` (denoise_sweep.hpp): at each floor roughness the G-buffer and the
// exact VPL sum are computed once; at each noisy input the noisy image is rendered once and every
// weighting filters the same image, so the rows of a point differ only in the weights.
#include "denoise_sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "csv.hpp"
#include "option_checks.hpp"
#include "filter_sweep.hpp"
#include "sglab/text_limits.hpp"
#include "sweep.hpp"  // csv_number
#include "table.hpp"

namespace sglab::experiments::denoise_sweep {
namespace {

using filter_sweep::cell;
using filter_sweep::stat_number;
using render::FilterWeights;

std::vector<render::NoisySpec> parse_noisy_list(const std::string& text) {
  std::vector<render::NoisySpec> specs;
  for (const auto& t : filter_sweep::split(text)) specs.push_back(frontend::parse_noisy_option(t));
  return specs;
}

std::string command_line(const Options& o) {
  std::vector<std::string> args = {"filter-sweep", "--scene",   o.job.render.scene_path,
                                   "--noisy",      o.noisy,     "--roughness",
                                   o.roughness,    "--weights", o.weights};
  if (o.radius) args.insert(args.end(), {"--radius", std::to_string(*o.radius)});
  if (o.noisy_seed != Options{}.noisy_seed) args.insert(args.end(), {"--noisy-seed", std::to_string(o.noisy_seed)});
  for (const auto& a : frontend::filter_job_arguments(o.job, false, false)) args.push_back(a);
  if (o.figure_roughness != Options{}.figure_roughness)
    args.insert(args.end(), {"--figure-roughness", o.figure_roughness});
  if (o.figure_noisy != Options{}.figure_noisy) args.insert(args.end(), {"--figure-noisy", o.figure_noisy});
  if (o.table != Options{}.table) args.insert(args.end(), {"--table", o.table});
  std::string command = "sglab";
  for (const auto& a : args) command += " " + frontend::quote_argument(a);
  return command;
}

bool same_spec(const render::NoisySpec& a, const render::NoisySpec& b) {
  return a.mode == b.mode && a.count == b.count;
}

void compute_points(const Options& o, const std::vector<render::Scene>& scenes,
                    const std::vector<double>& figure_roughness, const render::NoisySpec& figure_noisy, Result& r) {
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [start] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const std::size_t n = scenes.size() * r.noisy.size();
  for (std::size_t k = 0; k < scenes.size(); ++k) {
    std::vector<render::Rgb> reference;
    for (std::size_t s = 0; s < r.noisy.size(); ++s) {
      const render::NoisySpec& spec = r.noisy[s];
      if (!o.quiet)
        std::fprintf(stderr, "filter-sweep --noisy [%zu/%zu] floor.roughness=%g, %s (%.1f s)\n",
                     k * r.noisy.size() + s + 1, n, r.roughness[k], render::noisy_spec_name(spec).c_str(), elapsed());
      render::DenoiseInputOptions io = frontend::denoise_input_options(o.job, spec, o.noisy_seed);
      io.reference = reference.empty() ? nullptr : &reference;
      render::FilterParameters parameters = o.job.parameters;
      parameters.radius = frontend::denoise_radius(spec, o.radius);
      try {
        render::DenoiseInputs in = render::prepare_denoise_inputs(scenes[k], io);
        if (r.rows.empty()) {
          r.width = in.width, r.height = in.height, r.vpl_count = in.vpl_count;
          for (std::size_t p = 0; p < in.hit.size(); ++p)
            r.pixels_hit += in.hit[p] != 0, r.glossy_receivers += in.glossy[p] != 0;
        }
        const render::NoisyError noisy = render::noisy_error(in);
        const bool figure = same_spec(spec, figure_noisy) && std::find(figure_roughness.begin(), figure_roughness.end(),
                                                                       r.roughness[k]) != figure_roughness.end();
        FigureImage image;
        if (figure)
          image = {r.roughness[k], spec, in.width, in.height, in.glossy, in.noisy_image, {}, {}, in.reference};
        const double pixels = double(in.width) * double(in.height);
        for (const FilterWeights w : r.weights) {
          render::DenoiseResult d = render::denoise_indirect(in, w, parameters);
          r.rows.push_back({r.roughness[k], spec, d.radius, w, d.all, d.glossy, d.diffuse, noisy, d.seconds,
                            1e9 * d.seconds / pixels});
          if (figure && w == FilterWeights::normal) image.normal = std::move(d.filtered);
          if (figure && w == FilterWeights::lobe) image.lobe = std::move(d.filtered);
        }
        if (figure) r.images.push_back(std::move(image));
        if (reference.empty()) reference = std::move(in.reference);
      } catch (const std::invalid_argument& e) {
        throw runner::InputError(e.what());
      }
    }
  }
  r.seconds = elapsed();
}

const Row* find_row(const Result& r, double roughness, const render::NoisySpec& spec, FilterWeights w) {
  for (const Row& row : r.rows)
    if (row.roughness == roughness && same_spec(row.noisy, spec) && row.weights == w) return &row;
  return nullptr;
}

// subset: 0 all pixels, 1 glossy receivers, 2 diffuse receivers.
double pick(const Row* row, bool smape, int subset) {
  if (!row) return std::numeric_limits<double>::quiet_NaN();
  const render::ImageError& e = subset == 0 ? row->all : subset == 1 ? row->glossy : row->diffuse;
  return smape ? e.smape : e.relative_l2;
}

double pick_noisy(const Row& row, bool smape, int subset) {
  const render::ImageError& e = subset == 0   ? row.noisy_error.all
                                : subset == 1 ? row.noisy_error.glossy
                                              : row.noisy_error.diffuse;
  return smape ? e.smape : e.relative_l2;
}

bool has(const Result& r, FilterWeights w) {
  return std::find(r.weights.begin(), r.weights.end(), w) != r.weights.end();
}

std::string markdown_table(const Result& r, bool smape, int subset) {
  const char* subset_names[] = {"all pixels", "glossy receivers", "diffuse receivers"};
  std::vector<FilterWeights> compared;
  if (has(r, FilterWeights::normal))
    for (const auto w : r.weights)
      if (w != FilterWeights::normal && w != FilterWeights::spatial) compared.push_back(w);
  std::string md = fmt::format("## {}, {}\n\n| noisy input | R | floor α | noisy |", smape ? "SMAPE" : "Relative L2",
                               subset_names[subset]);
  std::string rule = "|---|---|---|---|";
  for (const auto w : r.weights) md += fmt::format(" {} |", render::filter_weights_name(w)), rule += "---|";
  for (const auto w : compared) md += fmt::format(" {} vs normal |", render::filter_weights_name(w)), rule += "---|";
  md += "\n" + rule + "\n";
  for (const auto& spec : r.noisy)
    for (const double a : r.roughness) {
      const Row* first = find_row(r, a, spec, r.weights.front());
      if (!first) continue;
      md += fmt::format("| {} | {} | {:g} | {} |", render::noisy_spec_name(spec), first->radius, a,
                        cell(pick_noisy(*first, smape, subset)));
      for (const auto w : r.weights) md += fmt::format(" {} |", cell(pick(find_row(r, a, spec, w), smape, subset)));
      for (const auto w : compared)
        md += fmt::format(" {} |", runner::signed_percent_cell(frontend::percent_change(
                                       pick(find_row(r, a, spec, w), smape, subset),
                                       pick(find_row(r, a, spec, FilterWeights::normal), smape, subset))));
      md += "\n";
    }
  return md + "\n";
}

// "lobe vs normal" on a receiver subset for one input, over the roughness values: mean, min, max (%).
struct Change {
  double mean = 0, lo = 0, hi = 0;
};
Change change_over_roughness(const Result& r, const render::NoisySpec& spec, FilterWeights w, int subset) {
  Change c{0, std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  int count = 0;
  for (const double a : r.roughness) {
    const double x = frontend::percent_change(pick(find_row(r, a, spec, w), false, subset),
                                              pick(find_row(r, a, spec, FilterWeights::normal), false, subset));
    if (!std::isfinite(x)) continue;
    c.mean += x, c.lo = std::min(c.lo, x), c.hi = std::max(c.hi, x), ++count;
  }
  c.mean = count ? c.mean / count : std::numeric_limits<double>::quiet_NaN();
  return c;
}

std::string headline(const Result& r) {
  if (!has(r, FilterWeights::normal) || !has(r, FilterWeights::lobe)) return "";
  std::string md =
      "## Headline: lobe vs normal (relative L2, mean over the floor's roughness; min … max)\n\n"
      "| noisy input | glossy receivers | diffuse receivers | all pixels |\n|---|---|---|---|\n";
  for (const auto& spec : r.noisy) {
    md += fmt::format("| {} |", render::noisy_spec_name(spec));
    for (const int subset : {1, 2, 0}) {
      const Change c = change_over_roughness(r, spec, FilterWeights::lobe, subset);
      md += fmt::format(" {} ({} … {}) |", runner::signed_percent_cell(c.mean), runner::signed_percent_cell(c.lo),
                        runner::signed_percent_cell(c.hi));
    }
    md += "\n";
  }
  md += "\n";
  // Where lobe loses in relative L2, and what SMAPE and lobe-depth say there.
  std::size_t points = 0, smape_better = 0, l2_worse = 0;
  double depth_lo = std::numeric_limits<double>::infinity(), depth_hi = -depth_lo;
  for (const auto& spec : r.noisy)
    for (const double a : r.roughness) {
      const Row *n = find_row(r, a, spec, FilterWeights::normal), *l = find_row(r, a, spec, FilterWeights::lobe);
      if (!n || !l) continue;
      ++points;
      smape_better += l->all.smape < n->all.smape;
      if (frontend::percent_change(l->glossy.relative_l2, n->glossy.relative_l2) > 1) {
        ++l2_worse;
        if (const Row* d = find_row(r, a, spec, FilterWeights::lobe_depth)) {
          const double x = frontend::percent_change(d->glossy.relative_l2, n->glossy.relative_l2);
          depth_lo = std::min(depth_lo, x), depth_hi = std::max(depth_hi, x);
        }
      }
    }
  md += fmt::format(
      "In SMAPE over all pixels `lobe` is better than `normal` on {} of {} rows. On glossy receivers its relative L2 "
      "is more than 1 % worse on {} rows",
      smape_better, points, l2_worse);
  if (l2_worse > 0 && std::isfinite(depth_lo))
    md += fmt::format(
        "; there `lobe-depth` (the same lobes, normal's depth term instead of App. A's positional term) is {} … {} "
        "against "
        "`normal`: most of the loss is the positional term's (ν = {} scene units keeps fewer of the window's noisy "
        "samples than the "
        "depth term, so the near-mirror floor's bright outliers are averaged less; the same term is behind the "
        "upsampling "
        "table's scale-2 rows, see [filtering.md](filtering.md))",
        runner::signed_percent_cell(depth_lo), runner::signed_percent_cell(depth_hi), r.options.job.parameters.nu);
  md += ".\n\n";
  if (has(r, FilterWeights::lobe_depth)) {
    // App. D: on a Lambert receiver the lobe-aware directional weight is the normal weight with
    // σ_n² = (2λ_c + κ)/(βλ_cκ); lobe-depth and normal share the depth term.
    double worst = 0;
    for (const Row& row : r.rows) {
      if (row.weights != FilterWeights::lobe_depth) continue;
      const Row* normal = find_row(r, row.roughness, row.noisy, FilterWeights::normal);
      for (const bool smape : {false, true}) {
        const double a = pick(&row, smape, 2), b = pick(normal, smape, 2);
        if (std::isfinite(a) && std::isfinite(b) && b != 0) worst = std::max(worst, std::fabs(a - b) / b);
      }
    }
    md += fmt::format(
        "**App. D, measured.** On diffuse receivers `lobe-depth` (the lobe-aware directional weight with the diffuse "
        "lobe an SG "
        "of sharpness 2λ_c, times the same depth term) and `normal` (σ_n² = (2λ_c + κ)/(βλ_cκ) = {}) differ by at most "
        "{:.1e} "
        "(relative, over every row's diffuse-receiver relative L2 and SMAPE; per pixel ≤ 1e-7, "
        "tests/denoise_test.cpp): the "
        "diffuse lobe-aware weight is the normal weight, as App. D derives (not bit for bit: σ_n² is the published "
        "8-digit value). `lobe` differs from `normal` on diffuse receivers only through App. A's positional term, "
        "which replaces the "
        "depth term.\n\n",
        r.options.job.parameters.sigma_n2, worst);
  }
  return md;
}

std::string markdown_intro(const Result& r) {
  const Options& o = r.options;
  const auto& p = o.job.parameters;
  std::vector<std::string> radii;
  for (const auto& spec : r.noisy)
    radii.push_back(fmt::format("{} for {}", frontend::denoise_radius(spec, o.radius), render::noisy_spec_name(spec)));
  double ns = 0;
  for (const Row& row : r.rows) ns += row.ns_per_pixel;
  return fmt::format(
      "# Filtering noisy indirect light: normal/depth-aware vs lobe-aware weights over the floor's roughness\n\n"
      "Scene `{}`{}, **{}×{} pixels** ({} hit, {} glossy receivers), RSM {}² → {} VPLs. The noisy input sums a subset "
      "of "
      "the VPLs at each pixel (core/render denoise.hpp): **interleaved:M** — the VPLs split into M×M interleaved "
      "subsets "
      "(Keller & Heidrich 2001; Segovia et al. 2006), each VPL into a uniformly drawn subset (seed {}), pixel (x, y) "
      "sums "
      "subset (x mod M, y mod M) weighted by M²; **random:K** — K VPLs per pixel drawn ∝ reflected power (a 10 % "
      "uniform defensive "
      "mixture), weighted 1/(K p). Both are unbiased for the full VPL sum at every pixel; the noisy column is that "
      "input's "
      "own error.\n\n"
      "Filter: a cross-bilateral filter over the full-resolution noisy image, window (2R + 1)² with a box footprint "
      "whose "
      "edge taps weigh ½ (so that with R a multiple of M every interleaved subset has the same spatial weight), R = "
      "{}; "
      "diffuse and specular parts filtered separately (demodulated by albedo and f0). Range weights as in "
      "[filtering.md](filtering.md): **spatial** none; **normal** G(n_p; n_q, 1/σ_n²)·g(z_p − z_q, (σ_z z_p)²), σ_n² = "
      "{}, "
      "σ_z = {}; **lobe** the lobe-aware q^β (Tokuyoshi 2015 (lobe-aware filtering), Eq. (12)/App. E for the lobes, "
      "App. A for positions with τ = the pixel's footprint), β = {}, κ = {}, ν = {} scene units, diffuse lobe "
      "sharpness "
      "{:.4f} (2λ_c); **lobe-depth** the lobe-aware directional weight × the normal weighting's depth term.\n\n"
      "Error against the exact VPL sum (all VPLs) at every pixel, all channels: relative L2 = ‖v − r‖/‖r‖, SMAPE = "
      "mean "
      "2|v − r|/(|v| + |r|). **Glossy** receivers: the floor and the sphere; **diffuse**: the other surfaces. \"X vs "
      "normal\" "
      "= (X − normal)/normal: negative is better. The filter pass took {:.0f} ns per pixel on average over the rows "
      "(wall "
      "clock, all cores; per row in the CSV). Images of the figure: `{}_images.csv` in the `--out` directory.\n\n",
      o.job.render.scene_path, filter_sweep::overrides_markdown(o.job), r.width, r.height, r.pixels_hit,
      r.glossy_receivers, r.rsm_resolution, r.vpl_count, o.noisy_seed, fmt::join(radii, ", "), p.sigma_n2,
      p.depth_sigma, p.beta, p.kappa, p.nu, p.diffuse_sharpness, r.rows.empty() ? 0.0 : ns / double(r.rows.size()),
      o.table);
}

std::string markdown(const Result& r) {
  std::string md = markdown_intro(r) + headline(r);
  for (const bool smape : {false, true})
    for (int subset = 0; subset < 3; ++subset) md += markdown_table(r, smape, subset);
  return md;
}

std::string summary_csv(const Result& r) {
  std::string csv;
  runner::append_csv_record(
      csv,
      std::vector<std::string>{"noisy", "radius", "floor_roughness", "weights", "relative_l2", "glossy_relative_l2",
                               "diffuse_relative_l2", "smape", "glossy_smape", "diffuse_smape", "noisy_relative_l2",
                               "noisy_glossy_relative_l2", "noisy_diffuse_relative_l2", "noisy_smape",
                               "noisy_glossy_smape", "noisy_diffuse_smape", "seconds_filter", "ns_per_pixel"});
  for (const Row& row : r.rows) {
    const auto& ne = row.noisy_error;
    runner::append_csv_record(
        csv, std::vector<std::string>{
                 render::noisy_spec_name(row.noisy), std::to_string(row.radius), runner::csv_number(row.roughness),
                 std::string(render::filter_weights_name(row.weights)), stat_number(row.all.relative_l2),
                 stat_number(row.glossy.relative_l2), stat_number(row.diffuse.relative_l2), stat_number(row.all.smape),
                 stat_number(row.glossy.smape), stat_number(row.diffuse.smape), stat_number(ne.all.relative_l2),
                 stat_number(ne.glossy.relative_l2), stat_number(ne.diffuse.relative_l2), stat_number(ne.all.smape),
                 stat_number(ne.glossy.smape), stat_number(ne.diffuse.smape), runner::csv_number(row.seconds),
                 runner::csv_number(row.ns_per_pixel)});
  }
  return csv;
}

std::string images_csv(const Result& r) {
  std::string csv;
  std::vector<std::string> header = {"floor_roughness", "noisy", "x", "y", "glossy"};
  for (const char* layer : {"noisy", "normal", "lobe", "exact"})
    for (const char* c : {"r", "g", "b"}) header.push_back(fmt::format("{}_{}", layer, c));
  runner::append_csv_record(csv, header);
  for (const FigureImage& im : r.images) {
    if (im.normal.empty() || im.lobe.empty()) continue;
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x) {
        const std::size_t k = std::size_t(y) * std::size_t(im.width) + std::size_t(x);
        std::vector<std::string> f = {runner::csv_number(im.roughness), render::noisy_spec_name(im.noisy),
                                      std::to_string(x), std::to_string(y), std::to_string(int(im.glossy[k] != 0))};
        for (const auto* layer : {&im.noisy_image, &im.normal, &im.lobe, &im.exact})
          for (int c = 0; c < 3; ++c) f.push_back(fmt::format("{:.6g}", (*layer)[k](c)));
        runner::append_csv_record(csv, f);
      }
  }
  return csv;
}

}  // namespace

Result compute(const Options& options) {
  Result r = filter_sweep::checked_result<Result>(options);
  Options& o = r.options;
  r.noisy = parse_noisy_list(o.noisy);
  const std::vector<double> figure_roughness = filter_sweep::parse_roughness_list(o.figure_roughness);
  const render::NoisySpec figure_noisy = frontend::parse_noisy_option(o.figure_noisy);
  render::FilterParameters checked = o.job.parameters;
  checked.radius = 1;  // checked against each input below
  frontend::check_filter_parameters(checked);
  for (const auto& spec : r.noisy) frontend::denoise_radius(spec, o.radius);
  const std::vector<render::Scene> scenes = filter_sweep::roughness_scenes(o.job, r.roughness);
  r.rsm_resolution = frontend::denoise_input_options(o.job, r.noisy.front(), o.noisy_seed).rsm_resolution;
  if (!scenes.empty()) {  // one point's buffers at a time, plus the reference and the figure's images
    render::FilterInputOptions footprint;
    footprint.scale = 1;
    footprint.rsm_resolution = r.rsm_resolution;
    frontend::check_filter_memory(scenes.front(), footprint, 2 + 2 * figure_roughness.size());
  }
  r.provenance.command = command_line(o);
  compute_points(o, scenes, figure_roughness, figure_noisy, r);
  return r;
}

runner::TableWithImages tables(const Result& r) { return {markdown(r), summary_csv(r), images_csv(r)}; }

void write(const Result& r) {
  const Options& o = r.options;
  const runner::TableWithImages t = tables(r);
  const std::string tables_dir = o.tables_dir.empty() ? o.out : o.tables_dir;
  runner::write_table_with_images(tables_dir, o.table, o.out, o.table + "_images", r.provenance, t);
  std::fputs((runner::markdown_header(r.provenance) + t.markdown).c_str(), stdout);
  std::fprintf(stderr, "filter-sweep --noisy: wrote %s/%s.{md,csv} and %s/%s_images.csv (%.1f s)\n", tables_dir.c_str(),
               o.table.c_str(), o.out.c_str(), o.table.c_str(), r.seconds);
}

}  // namespace sglab::experiments::denoise_sweep
