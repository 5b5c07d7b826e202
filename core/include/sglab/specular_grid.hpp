// The grid of `sglab sweep specular` (experiments/sweep_specular.cpp) and its light positions in
// the lobe's own frame: shared by the sweep and by `sglab fit sglab-specular` (fit/
// sglab_specular.cpp), which fits on the same rows. Pure values; no I/O.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace sglab {

// Schlick f0 of the sweep: a dielectric of index 1.5, ((1.5 − 1)/(1.5 + 1))² = 0.04.
inline constexpr double kSpecularF0 = 0.04;

// The sweep's roughness × light sharpness × view_cos values.
struct SpecularGrid {
  std::vector<double> roughness;        // GGX α, log-spaced over [0.01, 1]
  std::vector<double> light_sharpness;  // λ
  std::vector<double> view_cos;         // ωo·n
  double f0 = kSpecularF0;
  // The point index k runs over roughness (outermost), light sharpness, view_cos (innermost).
  std::size_t point_count() const { return roughness.size() * light_sharpness.size() * view_cos.size(); }
};

// The full grid (9 × 5 × 4 points) or the --quick grid (3 × 3 × 3).
SpecularGrid specular_grid(bool quick);

// The light positions evaluated at every point, as registry inputs.
struct LightPosition {
  std::string name;
  double light_cos;      // ξ·n
  double light_azimuth;  // from the view's azimuth (radians)
};

// The angular widths that the offset positions are measured in, in the lobe's own frame: the
// light's and the BRDF lobe's angular standard deviations added in quadrature. The lobe is the
// Xu et al. 2013 ASG warp (brdf.hpp asg_warp) with η_x = λ_h/8 in the plane of incidence and
// η_y = λ_h/(8 cos²θo) across it (λ_h = 2/α²), so its standard deviations are √2·α in the plane and
// √2·α·cos θo across it: in-plane √(1/λ + 2α²), across √(1/λ + 2α²cos²θo). Each capped at π/6.
struct SpecularWidths {
  double in_plane = 0, across = 0;
};
SpecularWidths specular_offset_widths(double roughness, double light_sharpness, double view_cos);

// The positions: "mirror" (the mirror direction of the view), "toward-normal" and "toward-horizon"
// (rotated by one in-plane width within the plane of incidence), "side" and "side-3w" (rotated by
// one and three across-widths out of it), "normal" (ξ = n). Only lights ABOVE THE HORIZON are kept
// (light_cos > 0), and no duplicates: at view_cos = 1 the setting is symmetric about the normal, so
// positions at the same angle from it are one (the first kept: "mirror" covers "normal").
std::vector<LightPosition> specular_light_positions(double roughness, double light_sharpness, double view_cos);

// The seeded inputs that the specular methods' cost is timed on: by `sglab error-vs-time` (its
// ns/eval column) and by `sglab_core_bench --versus specular` (benchmarks/core_bench.cpp). `rows`
// rows of (α, λ, light_cos, view_cos, light_azimuth, f0): α log-uniform over [0.02, 1], λ over
// [1, 1e3], light_cos uniform over [−1, 1], view_cos over [0.05, 1], the azimuth over a turn,
// f0 = kSpecularF0 (seed 20261122).
std::vector<double> specular_timing_rows(std::size_t rows = 1024);

}  // namespace sglab
