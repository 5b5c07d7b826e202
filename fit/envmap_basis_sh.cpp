// Basis `sh`: real spherical harmonics of order L = 1 … 8 (sglab/sh.hpp), the representation of
// SH irradiance lighting (Ramamoorthi & Hanrahan 2001: L = 2, 9 coefficients per channel).
// Projection by texel quadrature of the piecewise-constant map: L_lm = Σ_t L_t ∫_t Y_lm dω, each
// texel's integral by the midpoint rule on kShProjectionSubsamples² equal-(θ, φ) sub-texels of
// exact solid angle. Diffuse: the clamped-cosine zonal convolution, unwindowed (EnvBasisFit).
#include <chrono>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "envmap_basis.hpp"
#include "sglab/sh.hpp"

namespace sglab::fit {
namespace {

// Sub-texels per texel side of the projection's quadrature: its error on a band-limited map
// (order ≤ 8) is O((L δ/4)²) of the coefficients, δ = π/H.
constexpr int kShProjectionSubsamples = 4;

using Coefficients = std::vector<std::array<double, 3>>;

Coefficients project(const EnvMap& map, int order) {
  const int s = kShProjectionSubsamples, W = map.width * s, H = map.height * s;
  const std::size_t K = std::size_t(sh_count(order));
  auto add = [](Coefficients a, const Coefficients& b) {
    for (std::size_t k = 0; k < a.size(); ++k)
      for (int c = 0; c < 3; ++c) a[k][std::size_t(c)] += b[k][std::size_t(c)];
    return a;
  };
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, H, 8), Coefficients(K, {0, 0, 0}),
      [&](const tbb::blocked_range<int>& rows, Coefficients acc) {
        double y[sh_count(kMaxShOrder)];
        for (int v = rows.begin(); v < rows.end(); ++v) {
          const double om = texel_solid_angle(W, H, v);
          for (int u = 0; u < W; ++u) {
            const auto& t = map.at(u / s, v / s);
            if (t[0] == 0 && t[1] == 0 && t[2] == 0) continue;
            sh_eval(order, texel_direction(W, H, u, v), y);
            for (std::size_t k = 0; k < K; ++k)
              for (int c = 0; c < 3; ++c) acc[k][std::size_t(c)] += om * y[k] * double(t[std::size_t(c)]);
          }
        }
        return acc;
      },
      add);
}

std::vector<EnvBasisFit> fit_sh(const EnvMap& map, const std::vector<int>& sizes, const std::string&,
                                const EnvBasisOptions&) {
  std::vector<EnvBasisFit> out;
  for (int L : sizes) {
    if (L < 1 || L > kMaxShOrder) throw std::invalid_argument("sh order L = " + std::to_string(L) + " outside [1, 8]");
    const auto t0 = std::chrono::steady_clock::now();
    EnvBasisFit f;
    f.basis = "sh";
    f.size = L;
    f.floats = 3 * sh_count(L);
    f.sh_order = L;
    f.sh = project(map, L);
    f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    out.push_back(std::move(f));
  }
  return out;
}

int sh_floats(int L) { return 3 * sh_count(L); }

}  // namespace

EnvBasis sh_basis() {
  return {
      "sh",
      "L",
      {""},
      {1, 2, 3, 4, 6, 8},
      sh_floats,
      "real SH of order L, 3(L+1)² floats; projection by texel quadrature (4×4 sub-texels per texel); diffuse by the "
      "clamped-cosine zonal convolution of Ramamoorthi & Hanrahan 2001, unwindowed",
      fit_sh};
}

}  // namespace sglab::fit
