// The grid and light positions of `sglab sweep specular` (sglab/specular_grid.hpp).
#include "sglab/specular_grid.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace sglab {
namespace {

struct Vec {
  double x, y, z;
};
Vec rotate_toward(const Vec& a, const Vec& t, double angle) {  // a, t orthonormal
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * a.x + s * t.x, c * a.y + s * t.y, c * a.z + s * t.z};
}
LightPosition position(std::string name, const Vec& d) {
  return {std::move(name), std::clamp(d.z, -1.0, 1.0), std::atan2(d.y, d.x)};
}

// light_cos above which a light is above the horizon: 1e-12 keeps a position rotated by exactly
// π/2 (cos = 6e-17 in double) out, and no real light position is that close to the horizon.
constexpr double kAboveHorizon = 1e-12;

}  // namespace

SpecularGrid specular_grid(bool quick) {
  SpecularGrid g;
  // α = 10^(−2 + i/4), i = 0 … 8 (quick: i = 0, 4, 8, one per decade), so the quick values are
  // full-grid values. Low α costs most: a reference at α = 0.01 takes about 4 times one at α = 1.
  for (int i = 0; i <= 8; i += quick ? 4 : 1) g.roughness.push_back(std::pow(10.0, -2.0 + 0.25 * i));
  g.light_sharpness = quick ? std::vector<double>{1, 100, 1e4} : std::vector<double>{1, 10, 100, 1e3, 1e4};
  g.view_cos = quick ? std::vector<double>{1, 0.3, 0.1} : std::vector<double>{1, 0.7, 0.3, 0.1};
  return g;
}

SpecularWidths specular_offset_widths(double roughness, double light_sharpness, double view_cos) {
  const double cap = std::numbers::pi / 6;  // also caps λ = 0 (1/λ = ∞)
  const double a2 = 2 * roughness * roughness, c = std::clamp(view_cos, 0.0, 1.0);
  return {std::min(std::sqrt(1 / light_sharpness + a2), cap),
          std::min(std::sqrt(1 / light_sharpness + a2 * c * c), cap)};
}

std::vector<LightPosition> specular_light_positions(double roughness, double light_sharpness, double view_cos) {
  const double v = std::clamp(view_cos, 0.0, 1.0), s = std::sqrt(std::max(0.0, (1 - v) * (1 + v)));
  const Vec mirror{-s, 0, v};       // reflection of ωo = (s, 0, v) about n
  const Vec to_horizon{-v, 0, -s};  // d(mirror)/dθ: in the plane of incidence, away from n
  const Vec to_normal{v, 0, s};
  const Vec side{0, 1, 0};  // perpendicular to the plane of incidence
  const SpecularWidths w = specular_offset_widths(roughness, light_sharpness, v);
  const std::vector<LightPosition> all = {position("mirror", mirror),
                                          position("toward-normal", rotate_toward(mirror, to_normal, w.in_plane)),
                                          position("toward-horizon", rotate_toward(mirror, to_horizon, w.in_plane)),
                                          position("side", rotate_toward(mirror, side, w.across)),
                                          position("side-3w", rotate_toward(mirror, side, 3 * w.across)),
                                          position("normal", {0, 0, 1})};
  std::vector<LightPosition> out;
  for (const auto& p : all) {
    if (!(p.light_cos > kAboveHorizon)) continue;  // at or below the horizon
    // At view_cos = 1 only the angle from the normal matters (rotational symmetry).
    const bool duplicate = std::any_of(out.begin(), out.end(), [&](const LightPosition& q) {
      return std::fabs(q.light_cos - p.light_cos) <= 1e-12 &&
             (v == 1 || std::fabs(q.light_azimuth - p.light_azimuth) <= 1e-12);
    });
    if (!duplicate) out.push_back(p);
  }
  return out;
}

std::vector<double> specular_timing_rows(std::size_t rows) {
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> out;
  out.reserve(6 * rows);
  for (std::size_t k = 0; k < rows; ++k)
    out.insert(out.end(), {0.02 * std::pow(50.0, u(rng)), std::pow(10.0, 3 * u(rng)), -1 + 2 * u(rng),
                           0.05 + 0.95 * u(rng), 2 * std::numbers::pi * u(rng), kSpecularF0});
  return out;
}

}  // namespace sglab
