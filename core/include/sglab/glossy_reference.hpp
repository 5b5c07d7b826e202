// Exact glossy reflection of an SG light:
//
//   L = ∫ G(ω; ξ, λ) f(ωo, ω) ⟨ω·n⟩ dω,  f = GGX·height-correlated Smith·Schlick (brdf.hpp),
//
// by deterministic adaptive 2D quadrature (sphere_quadrature.hpp: integrate_sg_about_axis, the pole
// the light axis, the foci the mirror direction and the dominant-visible-normal reflection, the clip
// the horizon), and a seeded importance-sampled Monte Carlo estimator that checks it
// (tests/glossy_reference_test.cpp).
// Accuracy: ≤ 1e-6 relative is asserted in tests (comparison with a finer rule, and with Monte
// Carlo within 4 standard errors).
//
// Double only: the reference is evaluated in double and converted for float and mp50 (an mp50
// 2D quadrature would take minutes per point; the registry says so in the method's flaws).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>

#include <boost/math/constants/constants.hpp>

#include "sglab/brdf.hpp"
#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"
#include "sglab/specular_input.hpp"
#include "sglab/sphere_quadrature.hpp"

namespace sglab {

// The smallest GGX α the specular reference accepts. Its panels follow the BRDF lobe, whose
// width ~2α(ωo·n) shrinks without bound: below this the cost grows past minutes a value (at
// α = 1e-8 and grazing view, hours), so smaller α are refused rather than left to hang. The
// same minimum as the renderer's scenes (scene.hpp kMinSceneRoughness).
inline constexpr double kMinReferenceRoughness = 1e-3;

// ---- the configuration of the `specular` quantity ---------------------------------------------
// n = (0, 0, 1), ωo = (√(1 − v²), 0, v), light axis ξ = (s cos φ, s sin φ, c), s = √(1 − c²).
struct SpecularConfig {
  double roughness;        // GGX α > 0
  double light_sharpness;  // λ ≥ 0
  double light_cos;        // ξ·n
  double view_cos;         // ωo·n ∈ [0, 1]
  double light_azimuth;    // φ, from the view's azimuth (π and light_cos = view_cos: mirror)
  double f0;               // Schlick reflectance at normal incidence
};

// ggx_brdf_cosine(alpha, f0, wo, ω) at the n directions ω = (x[k], y[k], z[k]) into out, the
// template's values bit for bit, on the active instruction set's vector registers
// (core/src/ggx_points.cpp, src/simd/simd_ggx_points.hpp).
void ggx_brdf_cosine_points(double alpha, double f0, const Vec3d& wo, const double* x, const double* y, const double* z,
                            double* out, std::size_t n);

// The specular reference's h: the GGX BRDF times the cosine, at one direction or at many.
struct GgxCosine {
  double alpha, f0;
  Vec3d wo;
  double operator()(const Vec3d& w) const { return ggx_brdf_cosine(alpha, f0, wo, w); }
  void points(const double* x, const double* y, const double* z, double* out, std::size_t n) const {
    ggx_brdf_cosine_points(alpha, f0, wo, x, y, z, out, n);
  }
};

// The exact L by the quadrature above: pole = light axis (width 1/√λ, capped at 1 rad for broad
// lights), foci = the mirror direction and the dominant-visible-normal reflection (width of the
// BRDF lobe in ω: ~2α(ωo·n) across the plane of incidence, the narrowest of its two widths),
// clip = the horizon. Right up to λ = DBL_MAX (integrate_sg_about_axis; tests/hardening_extremes_test.cpp
// checks it against the point-light limit 2π f(ωo, ξ)⟨ξ·n⟩/λ in 50 digits).
// The integrand h(ω) = f(ωo, ω)⟨ω·n⟩ is GgxCosine, whose `points` puts each rule's nodes on vector
// registers; specular_reference_of takes any h of the same values (tests: one node at a time).
template <class H>
double specular_reference_of(const SpecularConfig& c, const H& h, const SphereQuadrature& q) {
  const double alpha = c.roughness;
  const Vec3d wo = specular_view(c.view_cos);
  const Vec3d xi = specular_light_axis(c.light_cos, c.light_azimuth);
  const double lambda = c.light_sharpness;
  const Vec3d n(0, 0, 1);
  const double lobe_width = std::min(1.0, 2.0 * alpha * std::max(wo(2), 1e-3));
  const SphereFocus foci[2] = {{reflect_about(wo, n), lobe_width}, {dvn_reflection_lobe(alpha, wo).axis, lobe_width}};
  const Vec3d clips[1] = {n};
  return integrate_sg_about_axis(h, xi, lambda, foci, clips, q);
}
inline double specular_reference(const SpecularConfig& c, const SphereQuadrature& q = {}) {
  return specular_reference_of(c, GgxCosine{c.roughness, c.f0, specular_view(c.view_cos)}, q);
}

// ---- Monte Carlo check ------------------------------------------------------------------------

struct MonteCarloEstimate {
  double mean;
  double standard_error;
  std::uint64_t samples;
};

// Seeded estimator of the same L with multiple importance sampling (Veach 1997, balance
// heuristic, one-sample mixture): half the samples from the light's vMF (exact inversion,
// Jakob 2012 "Numerically stable sampling of the von Mises–Fisher distribution on S²"), half from
// the GGX NDF (Walter et al. 2007 Eq. 35–36, h reflected to ω with pdf D(h)(n·h)/(4|ωo·h|)).
// The mixture pdf covers both peaks, so the variance stays small at α = 0.01 and λ = 1e4.
inline MonteCarloEstimate specular_monte_carlo(const SpecularConfig& c, std::uint64_t samples, std::uint64_t seed) {
  const double pi = boost::math::constants::pi<double>();
  const double alpha = c.roughness, a2 = alpha * alpha;
  const double lambda = c.light_sharpness;
  const Vec3d wo = specular_view(c.view_cos);
  const Vec3d xi = specular_light_axis(c.light_cos, c.light_azimuth);
  Vec3d e1, e2;
  detail::orthonormal_frame(xi, e1, e2);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double vmf_norm = 1.0 / sg_integral(lambda);
  auto pdf_light = [&](const Vec3d& w) { return sg_eval(w, xi, lambda) * vmf_norm; };
  auto pdf_brdf = [&](const Vec3d& w) -> double {
    if (!(w(2) > 0)) return 0.0;  // the NDF sampler only produces ω with h in the upper hemisphere
    const Vec3d h = half_vector(wo, w);
    const double oh = wo.dot(h);
    if (!(oh > 0)) return 0.0;
    return ggx_ndf(alpha, h(2)) * h(2) / (4 * oh);
  };
  // Welford's running mean and sum of squared deviations (no E[x²] − E[x]² cancellation).
  double mean = 0, m2 = 0;
  for (std::uint64_t i = 0; i < samples; ++i) {
    const double u1 = uni(rng), u2 = uni(rng), u3 = uni(rng);
    Vec3d w;
    if (u1 < 0.5) {
      // vMF: cos θ = 1 + log(u + (1 − u)e^{−2λ})/λ (Jakob 2012), 1 − cos θ kept exact.
      // With u' = 1 − u also uniform: 1 − cos θ = −log1p(u'·expm1(−2λ))/λ, → 2u' as λ → 0.
      const double one_minus = lambda > 0 ? -std::log1p(u2 * std::expm1(-2 * lambda)) / lambda : 2 * u2;
      const double om = std::clamp(one_minus, 0.0, 2.0);
      const double ct = 1 - om;
      const double st = std::sqrt(om * (2 - om));
      const double ph = 2 * pi * u3;
      w = ct * xi + st * (std::cos(ph) * e1 + std::sin(ph) * e2);
    } else {
      // GGX NDF: cos²θh = (1 − u)/(1 + (α² − 1)u) (Walter et al. 2007 Eq. 35 in cosine form).
      const double c2 = (1 - u2) / (1 + (a2 - 1) * u2);
      const double ch = std::sqrt(c2), sh = std::sqrt(std::max(0.0, 1 - c2));
      const double ph = 2 * pi * u3;
      const Vec3d h(sh * std::cos(ph), sh * std::sin(ph), ch);
      w = reflect_about(wo, h);
    }
    const double value = sg_eval(w, xi, lambda) * ggx_brdf_cosine(alpha, c.f0, wo, w);
    double x = 0;
    if (value > 0) {
      const double pdf = 0.5 * pdf_light(w) + 0.5 * pdf_brdf(w);
      x = value / pdf;
    }
    const double delta = x - mean;
    mean += delta / double(i + 1);
    m2 += delta * (x - mean);
  }
  const double n = double(samples);
  return {mean, std::sqrt(m2 / (n - 1) / n), samples};
}

}  // namespace sglab
