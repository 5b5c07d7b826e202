// `sglab near-wall` as a library: Tokuyoshi 2022's poster figure (a sharp SG light near a wall),
// per pixel each clamped-cosine method of the registry against the exact integral by SMAPE
// (compute), optionally over the light's sharpness × distance; then its tables (ranked SMAPE,
// the sweep) and the per-pixel dump.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "render_job.hpp"
#include "run_context.hpp"
#include "table.hpp"

namespace sglab::experiments::near_wall {

// Its directory in a run's places (runner::Places::dir): its tables go to results/near_wall unless
// the run has a tables directory (paper_tables/ in `sglab reproduce`).
inline constexpr std::string_view kDir = "near_wall";

struct Options {
  frontend::RenderJob job;  // scene path, --set, --width, --height
  std::string dump;
  std::string tables_dir = runner::Places{}.tables_or_dir(kDir);  // --tables-dir: a plain run's
  std::vector<double> sweep_sharpness, sweep_distance;
  int sweep_width = 96, sweep_height = 72;
};

// The virtual SG light (Tokuyoshi 2015): intensity c G(ω; ξ, λ) from an isotropic Gaussian of
// positions (mean μ, σ = radius).
struct SgLight {
  render::Vec3 position = render::Vec3::Zero();  // μ
  render::Vec3 axis = render::Vec3::UnitZ();     // ξ, unit
  double sharpness = 0, amplitude = 0, radius = 0, distance = 0;
};

struct Pixel {
  bool lit = false;
  int object = -1;
  double sharpness = 0, cosine = 0;
  double log_radiance_scale = 0;  // log(R_d/π · c · e^{log_scale}): radiance = e^{this} · D
  double reference = 0;
  std::vector<double> value;  // D per compared method (NaN outside its domain)
};

struct MethodError {
  std::string method;
  double mean = 0, max = 0;
  std::size_t pixels = 0;
};

struct SweepPoint {
  double sharpness = 0, distance = 0;
  std::vector<MethodError> errors;  // ranked by mean
};

struct Result {
  runner::Provenance provenance;  // the command line that reproduces it
  Options options;
  SgLight light;
  int width = 0, height = 0;
  std::string reference;             // the registry's reference method
  std::vector<std::string> methods;  // the compared methods, in registry order (Pixel::value's order)
  std::vector<Pixel> pixels;         // row-major, width × height
  std::vector<MethodError> errors;   // ranked by mean SMAPE
  bool swept = false;                // --sweep-sharpness or --sweep-distance given
  std::vector<SweepPoint> sweep;     // sharpness slowest
};

// InputError for a bad scene, SG light or sweep value (every sweep point is checked first).
Result compute(const Options& o);

struct Tables {
  std::string markdown, csv;              // near_wall_smape; without the provenance header
  std::string sweep_markdown, sweep_csv;  // near_wall_smape_sweep (empty unless swept)
  std::string dump_csv;                   // the per-pixel CSV (no header line: `sglab eval` reads it)
};
Tables tables(const Result& r);

// --dump, TABLES/near_wall_smape.{md,csv} and, if swept, TABLES/near_wall_smape_sweep.{md,csv};
// the Markdown also on stdout.
void write(const Result& r);

}  // namespace sglab::experiments::near_wall
