// `sglab filter-sweep --noisy …` as a library: the error of filtered noisy indirect light against the
// exact VPL sum, per weighting, over the floor's GGX roughness and the noisy input (interleaved M×M
// subsets or K random VPLs per pixel; core/render denoise.hpp) (compute), then its tables: the
// Markdown and CSV summary with the noisy input's own error on every row, and the images the figure
// crops (plots/filtering_denoise.py).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "filter_job.hpp"
#include "filter_sweep.hpp"
#include "table.hpp"

namespace sglab::experiments::denoise_sweep {

struct Options {
  frontend::FilterJob job;  // parameters.radius is used only if `radius` is set
  std::string roughness = "0.02,0.05,0.1,0.2,0.4,0.7";
  std::string noisy = "interleaved:2,interleaved:4,interleaved:8";
  std::string weights = "spatial,normal,lobe,lobe-depth";
  std::optional<int> radius;  // unset: each input's default (M for interleaved:M)
  std::uint64_t noisy_seed = 1;
  // The figure's images: these roughness values (those in the sweep) at this noisy input, for the
  // noisy image, normal and lobe weights and the exact sum.
  std::string figure_roughness = "0.05,0.4";
  std::string figure_noisy = "interleaved:4";
  std::string out = runner::Places{}.dir(filter_sweep::kDir);  // a plain run's; the command's is filter-sweep's --out
  std::string tables_dir;                                      // empty: `out`
  std::string table = "filtering_denoise";
  bool quiet = false;
};

struct Row {
  double roughness = 0;
  render::NoisySpec noisy;
  int radius = 0;
  render::FilterWeights weights = render::FilterWeights::normal;
  render::ImageError all, glossy, diffuse;  // filtered
  render::NoisyError noisy_error;           // the noisy input's own, the same on every row of its point
  double seconds = 0;                       // the filter pass
  double ns_per_pixel = 0;
};

// One image of the figure: the layers of one (roughness, noisy input) point.
struct FigureImage {
  double roughness = 0;
  render::NoisySpec noisy;
  int width = 0, height = 0;
  std::vector<char> glossy;
  std::vector<render::Rgb> noisy_image, normal, lobe, exact;
};

struct Result {
  runner::Provenance provenance;
  Options options;
  std::vector<double> roughness;
  std::vector<render::NoisySpec> noisy;
  std::vector<render::FilterWeights> weights;
  int width = 0, height = 0, rsm_resolution = 0;
  std::size_t vpl_count = 0, pixels_hit = 0, glossy_receivers = 0;  // at the first point
  std::vector<Row> rows;
  std::vector<FigureImage> images;
  double seconds = 0;
};

// Validates every option and every point's scene first (InputError naming the value), then
// computes every point; the exact VPL sum of a roughness is computed once, at its first input.
Result compute(const Options& o);

runner::TableWithImages tables(const Result& r);

// TABLES/TABLE.{md,csv} and OUT/TABLE_images.csv; the Markdown also on stdout.
void write(const Result& r);

}  // namespace sglab::experiments::denoise_sweep
