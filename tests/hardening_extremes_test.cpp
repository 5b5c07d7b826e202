// Wrong values at the largest and smallest finite inputs, against values computed independently (in
// 50 digits with Boost.Multiprecision where the range or the digits need it, quadratures in double
// where their tolerance allows): the specular references at light sharpness up to DBL_MAX (the
// point-light limit 2π f(ωo, ξ)⟨ξ·n⟩/λ), the ASG × SG product at ASG bandwidths up to DBL_MAX (the
// line and point limits), and `punctual-approx` at the smallest normal float and double (2π⟨c⟩/λ).
// Every value goes through the registry, as `sglab eval` and the Python module call it.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/quadrature/tanh_sinh.hpp>
#include <boost/math/special_functions/erf.hpp>
#include <gtest/gtest.h>

#include "sglab/asg_integral.hpp"
#include "sglab/gaussian_ndf.hpp"
#include "sglab/glossy_reference.hpp"
#include "sglab/registry.hpp"
#include "sglab/scalar.hpp"
#include "gauss_kronrod_panel.hpp"
#include "sglab/registry_mp50.hpp"

namespace {

using sglab::mp50;
constexpr double kDblMax = std::numeric_limits<double>::max();

const sglab::Method& method(const char* quantity, const char* name) {
  const sglab::Quantity* q = sglab::find_quantity(quantity);
  EXPECT_NE(q, nullptr) << quantity;
  const sglab::Method* m = q->find(name);
  EXPECT_NE(m, nullptr) << quantity << "/" << name;
  return *m;
}

template <class T>
T eval_row(const sglab::Method& m, const std::vector<double>& row) {
  std::vector<T> a;
  for (double x : row) a.push_back(T(x));
  return sglab::eval_as<T>(m, std::span<const T>(a));
}

double rel(double value, const mp50& expected) { return double(abs((mp50(value) - expected) / expected)); }

// The point-light limit of ∫ G(ω; ξ, λ) h(ω) dω: 2π h(ξ)/λ, relative error O(1/(λ w²)) for h
// smooth on the scale w (here w ≥ 0.05 rad and λ ≥ 1e16: below 1e-13). h in 50 digits.
template <class H>
mp50 point_light_limit(const H& h_mp50, const std::vector<double>& row) {
  const mp50 view_cos(row[3]), light_cos(row[2]), azimuth(row[4]);
  const auto wo = sglab::specular_view<mp50>(view_cos);
  const auto xi = sglab::specular_light_axis<mp50>(light_cos, azimuth);
  return 2 * boost::math::constants::pi<mp50>() * h_mp50(wo, xi) / mp50(row[1]);
}

// `specular` and `specular-gaussian-ndf` references at λ from 1e16 to DBL_MAX (they gave 6.9e-24 at
// 1e22 and 0 at 1e24): within the reference's 1e-6 of the limit, in float, double and mp50.
TEST(HardeningExtremes, GroupG_SpecularReferenceAtSharpLights) {
  const std::vector<std::vector<double>> configs = {
      // roughness, (λ), light_cos, view_cos, light_azimuth, f0
      {0.3, 0, 0.7, 0.6, 3.0, 0.04},               // near the mirror direction
      {0.5, 0, 0.4, 0.9, 1.0, 0.5},                // off it
      {0.2, 0, 0.5, 0.5, std::numbers::pi, 0.04},  // on it
      {0.4, 0, 0.8, 0.0, 2.0, 0.04},  // grazing view (the Gaussian-NDF reference's mirror-pole branch before)
  };
  for (const char* quantity : {"specular", "specular-gaussian-ndf"}) {
    const bool ggx = std::string(quantity) == "specular";
    const sglab::Method& ref = method(quantity, "reference");
    for (auto row : configs) {
      if (ggx && row[3] == 0) continue;  // GGX at grazing view: its lobe width floor makes w ~ 1e-3
      for (const double lambda : {1e16, 1e22, 1e24, 1e100, 1e300, kDblMax}) {
        row[1] = lambda;
        const mp50 expected = point_light_limit(
            [&](const auto& wo, const auto& xi) {
              return ggx ? sglab::ggx_brdf_cosine(mp50(row[0]), mp50(row[5]), wo, xi)
                         : sglab::gaussian_ndf_brdf_cosine(mp50(row[0]), mp50(row[5]), wo, xi);
            },
            row);
        ASSERT_GT(expected, 0);
        const double d = eval_row<double>(ref, row);
        EXPECT_LT(rel(d, expected), 1e-6) << quantity << " λ=" << lambda << " α=" << row[0] << " lc=" << row[2]
                                          << " v=" << row[3] << ": " << d << " vs " << expected;
        EXPECT_LT(rel(double(eval_row<mp50>(ref, row)), expected), 1e-6) << quantity << " mp50 λ=" << lambda;
        if (lambda <= 1e30) {  // float: λ ≤ FLT_MAX, 2πh/λ a normal float; 1e-5 for the inputs' rounding to float
          EXPECT_LT(rel(double(eval_row<float>(ref, row)), expected), 1e-5) << quantity << " float λ=" << lambda;
        }
      }
    }
  }
}

// The same reference is continuous across the old failure: at λ = 1e10…1e14 (inside the range the
// 1e-7 pole floor still resolved) it agrees with the limit to O(1/(λw²)) (w ≈ 0.3 here: ≤ 1e-8).
TEST(HardeningExtremes, GroupG_SpecularReferenceMeetsTheLimit) {
  const sglab::Method& ref = method("specular", "reference");
  std::vector<double> row{0.5, 0, 0.4, 0.9, 1.0, 0.5};
  for (const double lambda : {1e10, 1e12, 1e14}) {
    row[1] = lambda;
    const mp50 expected = point_light_limit(
        [&](const auto& wo, const auto& xi) { return sglab::ggx_brdf_cosine(mp50(row[0]), mp50(row[5]), wo, xi); },
        row);
    EXPECT_LT(rel(eval_row<double>(ref, row), expected), 1e-6) << "λ=" << lambda;
  }
}

// ∫ cos b e^{−ηy sin²b} e^{λ(ξ·ω(b) − 1)} db over (−π/2, π/2), ω(b) = (0, sin b, cos b), by
// tanh-sinh in double (the ASG's line integral for ηx → ∞). At the ηy ≤ 100, λ ≤ 50, cosines 1 and
// 0.999 below, the same rule in 50 digits (what this was until the suite was made faster: 2 of the
// test's 2.1 CPU s, for 12 integrals) gave the same values to 1e-15 relative or better (compared once): the
// integrand is smooth and positive, nothing cancels, and the check's tolerance is 1e-6.
double line_integral(double eta_y, double lambda, double cosine) {
  // ξ = (√(1 − c²), 0, c) at azimuth 0, off the line by its x component: ξ·ω(b) = c·cos b.
  boost::math::quadrature::tanh_sinh<double> ts;
  const double half_pi = std::numbers::pi / 2;
  return ts.integrate(
      [&](double b) {
        return std::cos(b) * std::exp(-eta_y * std::sin(b) * std::sin(b) + lambda * (cosine * std::cos(b) - 1));
      },
      -half_pi, half_pi, 1e-14);
}

// The ASG × SG product's `exact` method at ηx from 1e20 to DBL_MAX (it gave 2.9e-19 at 1e20 and 0 at
// 1e30): √(π/ηx)·(line integral) to O(1/ηx); with λ = 0 the line integral is √(π/ηy) erf(√ηy)
// (2 at ηy = 0), a closed form.
TEST(HardeningExtremes, GroupG_AsgSgProductAtSharpAsg) {
  const sglab::Method& exact = method("asg-sg-product-integral", "exact");
  const mp50 pi = boost::math::constants::pi<mp50>();
  for (const double eta_x : {1e20, 1e30, 1e100, 1e300, kDblMax}) {
    for (const double eta_y : {0.0, 1.0, 100.0}) {
      const mp50 closed = eta_y == 0 ? 2 * sqrt(pi / mp50(eta_x))
                                     : sqrt(pi / mp50(eta_x)) * sqrt(pi / mp50(eta_y)) * erf(sqrt(mp50(eta_y)));
      const double v = eval_row<double>(exact, {eta_x, eta_y, 0.0, 0.3, 0.7});
      EXPECT_LT(rel(v, closed), 1e-6) << "ηx=" << eta_x << " ηy=" << eta_y << " λ=0: " << v << " vs " << closed;
      // Swapped roles: ηy the sharp one (x ↔ y symmetry).
      const double w = eval_row<double>(exact, {eta_y, eta_x, 0.0, 0.3, 0.7});
      EXPECT_LT(rel(w, closed), 1e-6) << "ηy=" << eta_x << " ηx=" << eta_y << " λ=0 (swapped)";
      for (const double lambda : {2.0, 50.0}) {
        for (const double cosine : {1.0, 0.999}) {
          const mp50 expected = sqrt(pi / mp50(eta_x)) * mp50(line_integral(eta_y, lambda, cosine));
          const double u = eval_row<double>(exact, {eta_x, eta_y, lambda, cosine, 0.0});
          EXPECT_LT(rel(u, expected), 1e-6) << "ηx=" << eta_x << " ηy=" << eta_y << " λ=" << lambda << " c=" << cosine
                                            << ": " << u << " vs " << expected;
        }
      }
    }
  }
  // From ηx = 1e4 up, with λ = 0, against the exact ∫Ĝ dω (asg_integral_exact: a 1D integral of its
  // own, tested in asg_test): where the 2D quadrature gave 2.3e-2 relative at ηx = 1e6, ηy = 1.
  for (const double eta_x : {1e4, 1e5, 1e6, 1e7, 1e9})
    for (const double eta_y : {0.0, 1.0, 10.0}) {
      const double exact_value = sglab::asg_integral_exact(eta_x, eta_y);
      EXPECT_NEAR(eval_row<double>(exact, {eta_x, eta_y, 0.0, 0.5, 0.3}) / exact_value, 1.0, 1e-6)
          << "ηx=" << eta_x << " ηy=" << eta_y;
    }
  // Both bandwidths huge: the point limit π G(z; ξ, λ)/√(ηxηy) (to O(1/η)).
  for (const double eta : {1e20, 1e100, 1e300}) {
    const double lambda = 3, cosine = 0.8;
    const mp50 expected = pi * exp(mp50(lambda) * (mp50(cosine) - 1)) / mp50(eta);
    EXPECT_LT(rel(eval_row<double>(exact, {eta, eta, lambda, cosine, 0.4}), expected), 1e-6) << "η=" << eta;
  }
  // A sharp SG and a broad ASG: the point-light limit 2π Ĝ(ξ)/λ.
  for (const double lambda : {1e20, 1e100, kDblMax}) {
    const double eta_x = 2, eta_y = 5, cosine = 0.6, azimuth = 0.9;
    const mp50 c(cosine), s = sqrt(1 - c * c), az(azimuth);
    const mp50 x = s * cos(az), y = s * sin(az);
    const mp50 expected = 2 * pi * c * exp(-mp50(eta_x) * x * x - mp50(eta_y) * y * y) / mp50(lambda);
    EXPECT_LT(rel(eval_row<double>(exact, {eta_x, eta_y, lambda, cosine, azimuth}), expected), 1e-6) << "λ=" << lambda;
  }
}

// ---- exactly grazing view, the light at the mirror direction on the horizon ---------------------
// In polar coordinates (θ, ψ) about the mirror direction −ωo = (−1, 0, 0) at n·o = 0, ψ from n
// towards +y: ω = (−cos θ, sin θ sin ψ, sin θ cos ψ), and ωo + ω = 2 sin(θ/2)·h with
// h = (sin(θ/2), cos(θ/2) sin ψ, cos(θ/2) cos ψ) exactly, so o·h = sin(θ/2), n·h = cos(θ/2) cos ψ,
// n·ω = sin θ cos ψ (> 0 for |ψ| < π/2). With dω = sin θ dθ dψ the integrands f·⟨ω·n⟩ sin θ are
//   Gaussian NDF (S/(n·o) = 2(n·h)/(o·h) at n·o = 0): D(θ_h)·F(sin(θ/2))·4 cos²(θ/2) cos ψ/π,
//   GGX (V·(n·ω) = 1/(2α) at n·o = 0, height-correlated Smith): D_GGX(n·h)·F(sin(θ/2))·sin θ/(2α),
// both bounded: the singularity of the Gaussian-NDF one at θ = 0 is gone. Derived here, not taken
// from the code under test.
struct GrazingBrdf {
  bool ggx;
  double roughness, f0;
  // the integrand above without the light, from sin(θ/2) = o·h, cos(θ/2), sin θ and ψ's sine and
  // cosine; 1 − (n·h)² = sin²(θ/2) + cos²(θ/2) sin²ψ, without the cancellation of 1 − (n·h)² near h = n
  double operator()(double sh, double ch, double st, double sin_psi, double cos_psi) const {
    const double pi = std::numbers::pi;
    const double cn = ch * cos_psi, sn2 = sh * sh + ch * ch * sin_psi * sin_psi;  // n·h, 1 − (n·h)²
    const double om = 1 - sh, fresnel = f0 + (1 - f0) * om * om * om * om * om;
    if (ggx) {
      const double a2 = roughness * roughness, d = sn2 + a2 * cn * cn;
      return a2 / (pi * d * d) * fresnel * st / (2 * roughness);
    }
    const double theta_h = std::atan2(std::sqrt(sn2), cn) / roughness;
    return std::exp(-theta_h * theta_h) * fresnel * 4 * ch * ch * cos_psi / pi;
  }
};

// The light axis' offset δ = ξ − (−1, 0, 0) from the row's light_cos and azimuth in 50 digits.
std::pair<mp50, mp50> light_offset_yz(const mp50& light_cos, const mp50& azimuth) {
  const mp50 s = sqrt(1 - light_cos * light_cos);
  return {s * sin(azimuth), light_cos};
}

// The nodes and weights of the 15-point Kronrod rule (boost's gauss_kronrod<double, 15>, the
// estimate its integrate(f, a, b, 0, ·) returns) on each panel [ends[i], ends[i + 1]].
std::vector<std::pair<double, double>> kronrod15_nodes(const std::vector<double>& ends) {
  using Rule = boost::math::quadrature::gauss_kronrod<double, 15>;
  const auto& x = Rule::abscissa();
  const auto& w = Rule::weights();
  std::vector<std::pair<double, double>> nodes;
  for (std::size_t i = 0; i + 1 < ends.size(); ++i) {
    const double mid = (ends[i] + ends[i + 1]) / 2, half = (ends[i + 1] - ends[i]) / 2;
    nodes.emplace_back(mid, half * w[0]);
    for (std::size_t k = 1; k < x.size(); ++k) {
      nodes.emplace_back(mid - half * x[k], half * w[k]);
      nodes.emplace_back(mid + half * x[k], half * w[k]);
    }
  }
  return nodes;
}

// L by the product of 15-point Gauss–Kronrod rules over θ = t/√λ, t ∈ [0, 40 + √λ‖δ‖] (the light
// is e^{−800} past it), and ψ ∈ [−π/2, π/2], the light e^{−λ‖ω − ξ‖²/2} with
// ω − ξ = (2 sin²(θ/2) − δx, sin θ sin ψ − δy, sin θ cos ψ − δz), δx = (δy² + δz²)/(1 + √(1 − δy² − δz²)).
// Panel ends at t = 0, 1, 2, 4, 8, 16 and at ψ = 0, ±m/2, ±m, ±2m (the light's and D's widths
// resolved: within 1e-15 relative of 31-point rules on twice the panels at m = 0.3, λ = 1e4 … 1e12,
// checked once). In double, for λ ≤ 1e12 and δ ≲ 1/√λ: no difference above cancels (ω − ξ's
// components are differences of terms O(1/√λ) or a sum of squares, the BRDF takes 1 − (n·h)² as a sum), so λ‖ω − ξ‖²/2
// (≤ 800 where it counts) is off by ≤ 1e-13 absolute and the integrand by ≤ 1e-13 relative. The
// same rule in 50 digits (what this was until the suite was made faster) gave the same L to
// 6e-16 relative or better at every λ, light offset and BRDF below (compared once): 50 digits
// bought nothing against the 2e-6 tolerance and took 5.6 of the test's 7.7 CPU s.
// The sines of θ's and ψ's nodes are taken once each, not at every pair of nodes (the sum is the
// nested one's, to rounding).
double grazing_quadrature(const GrazingBrdf& brdf, double lambda, double dy, double dz) {
  const double half_pi = std::numbers::pi / 2, rl = std::sqrt(lambda);
  const double r2 = dy * dy + dz * dz, dx = r2 / (1 + std::sqrt(1 - r2));
  std::vector<double> tb{0.0, 1.0, 2.0, 4.0, 8.0, 16.0, 40 + rl * std::sqrt(r2)};
  const double m = brdf.roughness;
  struct ThetaNode {
    double weight, sh, ch, st, x;  // weight/√λ, sin(θ/2), cos(θ/2), sin θ, 2 sin²(θ/2) − δx
  };
  std::vector<ThetaNode> thetas;
  for (const auto& [t, weight] : kronrod15_nodes(tb)) {
    const double theta = t / rl, sh = std::sin(theta / 2);
    thetas.push_back({weight / rl, sh, std::cos(theta / 2), std::sin(theta), 2 * sh * sh - dx});
  }
  double sum = 0;
  for (const auto& [psi, weight] : kronrod15_nodes({-half_pi, -2 * m, -m, -m / 2, 0.0, m / 2, m, 2 * m, half_pi})) {
    const double sp = std::sin(psi), cp = std::cos(psi);
    double inner = 0;
    for (const ThetaNode& n : thetas) {
      const double y = n.st * sp - dy, z = n.st * cp - dz;
      inner += n.weight * std::exp(-lambda * (n.x * n.x + y * y + z * z) / 2) * brdf(n.sh, n.ch, n.st, sp, cp);
    }
    sum += weight * inner;
  }
  return sum;
}

// The sharp-light (Laplace) limit of the same L, derived: as λ → ∞ only θ = O(1/√λ + ‖δ‖) counts;
// with (y, z) = r(sin ψ, cos ψ) the tangent-plane offset of ω from −ωo, the light is
// e^{−λ(r² − 2r·a + ‖δ‖²)/2}, a = δy sin ψ + δz cos ψ, and the integrands above tend to
// their θ → 0 forms (relative corrections O(r): F(r/2) = 1 − 5(1 − f0)r/2 + …, D's θ dependence):
//   Gaussian NDF: (4/π) cos ψ e^{−ψ²/m²} ∫₀^∞ e^{−λ(…)/2} dr
//     = (4/π) cos ψ e^{−ψ²/m²} √(π/(2λ)) erfc(−a√λ/√2) e^{−λb²/2},  b = δy cos ψ − δz sin ψ,
//   GGX: α/(2π(cos²ψ(α² − 1) + 1)²) ∫₀^∞ r e^{−λ(…)/2} dr
//     = H(ψ)/λ·(e^{−λ‖δ‖²/2} + A√(π/2) erfc(−A/√2) e^{−B²/2}),  A = a√λ, B = b√λ,
// integrated over ψ ∈ (−π/2, π/2). With D = √λ(δy, δz) ≠ 0 the variable is τ = ψ − ψ_D
// (ψ_D the light's azimuth, A = ‖D‖cos τ, B = ‖D‖sin τ exactly, cos ψ and sin ψ from D's components):
// the light's width in ψ, 1/‖D‖ (1e-134 at λ = 1e300), is then resolved about τ = 0 where ψ itself
// could not be (π/2 ± 1e-134 is π/2 in any precision). Panel ends at τ = 0, ±2^k/(4‖D‖), and where ψ is
// ±π/2, 0, ±m/2, ±m, ±2m. At δ = 0 the Gaussian-NDF limit is √(π/(2λ))·(4/π)∫cos ψ e^{−ψ²/m²} dψ
// ≈ 0.8296/√λ at m = 0.3, the λ^{−1/2} law. D is formed in 50 digits (δ of the 50-digit azimuth π
// is ~1e-50) and the factor 1/√λ resp. 1/λ applied in 50 digits (GGX's value at λ = DBL_MAX is below
// double's normal range); the ψ integral itself in double, where ‖D‖ ≤ 1.6e138 here and every
// term is a product of O(1) factors. In 50 digits (what this was until the suite was made faster,
// about 1 CPU s for the test's 30 values) it gave the same values to 1e-15 relative or better at every λ and offset
// of the test (compared once; tolerance 2e-6).
mp50 grazing_limit(const GrazingBrdf& brdf, const mp50& lambda, const mp50& dy, const mp50& dz) {
  const double pi = std::numbers::pi, half_pi = pi / 2, m = brdf.roughness;
  const mp50 rl = sqrt(lambda);
  const double Dy = double(dy * rl), Dz = double(dz * rl), D2 = Dy * Dy + Dz * Dz, Dn = std::sqrt(D2);
  const double cd = Dn > 0 ? Dz / Dn : 1.0, sd = Dn > 0 ? Dy / Dn : 0.0;
  auto f = [&](double tau) -> double {
    const double cpsi = cd * std::cos(tau) - sd * std::sin(tau), spsi = sd * std::cos(tau) + cd * std::sin(tau);
    if (!(cpsi > 0)) return 0.0;  // below the horizon
    const double A = Dn * std::cos(tau), B = Dn * std::sin(tau);
    const double tail = std::erfc(-A / std::sqrt(2.0)) * std::exp(-B * B / 2);
    if (!brdf.ggx) {
      const double x = std::atan2(spsi, cpsi) / m;
      return 4 / pi * cpsi * std::exp(-x * x) * std::sqrt(pi / 2) * tail;  // times 1/√λ
    }
    const double a2 = m * m;
    const double den = cpsi * cpsi * (a2 - 1) + 1;
    const double h = m / (2 * pi * den * den);
    return h * (std::exp(-D2 / 2) + A * std::sqrt(pi / 2) * tail);  // times 1/λ
  };
  // For ‖D‖ ≥ 40 the light is e^{−B²/2} < e^{−2000} past |τ| = 64/‖D‖ (and erfc(−A/√2) < e^{−800}
  // near τ = π): only |τ| ≤ 64/‖D‖ is integrated.
  const double reach = Dn >= 40 ? 64 / Dn : pi;
  std::vector<double> br{-reach, reach, 0.0};
  if (Dn > 0)
    for (double w = 0.25 / Dn; w < reach; w *= 2) {
      br.push_back(w);
      br.push_back(-w);
    }
  const double psi_d = std::atan2(sd, cd);
  for (const double psi : {half_pi, -half_pi, 0.0, m / 2, -m / 2, m, -m, 2 * m, -2 * m}) {
    double t = psi - psi_d;
    if (t > pi) t -= 2 * pi;
    if (t < -pi) t += 2 * pi;
    if (t > -reach && t < reach) br.push_back(t);
  }
  std::sort(br.begin(), br.end());
  // Each panel mapped onto [−1, 1] (gauss_kronrod_panel.hpp): unmapped, a panel 1/‖D‖ ≈ 1e-134 wide
  // was bisected to the depth limit (30 000 evaluations, no digit gained).
  double sum = 0;
  for (std::size_t i = 0; i + 1 < br.size(); ++i)
    if (br[i + 1] > br[i]) sum += sglab::test::gauss_kronrod_panel<31>(f, br[i], br[i + 1], 6, 1e-13);
  return mp50(sum) / (brdf.ggx ? lambda : rl);
}

// |value − expected| within `tol` relative, or both below the type's smallest subnormal (a value
// that underflows in the type is 0 or a subnormal there, never more).
template <class T>
void expect_close(T value, const mp50& expected, double tol, const std::string& what) {
  const mp50 floor = 2 * mp50(std::numeric_limits<T>::denorm_min());
  EXPECT_LE(abs(mp50(value) - expected), tol * expected + floor) << what << ": " << double(value) << " vs " << expected;
}

// The Gaussian-NDF reference at exactly grazing view with the light on the horizon at the mirror
// direction: its value fell like λ^{−1/2} only up to λ ≈ 1e12 (1% low there), then 2.15e-9 at 1e16
// (8.30e-9 expected) and 0 from 1e20, from a 1e-7 floor on the light's width and ωo + ω formed
// from ω. Checked in float, double and mp50 (each row's inputs rounded to its type, as `sglab
// eval --type` rounds them: the double azimuth nearest π puts the light 1.22e-16 rad off the
// mirror direction, float's 8.7e-8, and from λ ≈ 1e32 resp. 1e14 that offset is many light widths),
// against the quadrature above for λ = 1e4 … 1e12 and the sharp-light limit from 1e16 on
// (its O(1/√λ) corrections ≤ 1e-7 relative there). Tolerance 2e-6: the quadrature's 1e-6 target,
// twice (float's rounding of the result, 6e-8, is inside it). The GGX reference at the same
// configurations is checked the same way: it is bounded at the mirror direction (V·(n·ω) = 1/(2α)
// at n·o = 0), so the light-pole quadrature already gives the limit.
TEST(HardeningExtremes, GroupK_GrazingMirrorReferences) {
  const mp50 pi = boost::math::constants::pi<mp50>();
  // The reference's grazing integrand from u = ωo + ω agrees with the BRDF's own form wherever
  // that one still has its digits (ω far from −ωo): a grid over the upper hemisphere, 1e-13.
  const sglab::Vec3d wo(1, 0, 0);
  for (double ct : {0.05, 0.3, 0.7, 0.99})
    for (double phi = 0.1; phi < 6.2; phi += 0.5) {
      const double st = std::sqrt(1 - ct * ct);
      const sglab::Vec3d w(st * std::cos(phi), st * std::sin(phi), ct);
      const double a = sglab::gaussian_ndf_brdf_cosine(0.3, 0.04, wo, w);
      const double b = sglab::gaussian_ndf_grazing_brdf_cosine(0.3, 0.04, sglab::Vec3d(wo + w));
      EXPECT_NEAR(b, a, 1e-13 * std::max(a, 1e-300)) << "ω·n=" << ct << " φ=" << phi;
    }
  for (const bool ggx : {false, true}) {
    const sglab::Method& ref = method(ggx ? "specular" : "specular-gaussian-ndf", "reference");
    const char* name = ggx ? "GGX" : "Gaussian NDF";
    // {roughness, λ, light_cos, view_cos, azimuth, f0}
    for (const double lambda : {1e4, 1e8, 1e12, 1e16, 1e20, 1e30, 1e100, 1e300, kDblMax}) {
      const std::vector<double> row{0.3, lambda, 0.0, 0.0, std::numbers::pi, 0.04};
      auto expected_for = [&](const mp50& lambda_t, const mp50& light_cos, const mp50& azimuth) {
        const GrazingBrdf brdf{ggx, 0.3, 0.04};
        const auto [dy, dz] = light_offset_yz(light_cos, azimuth);
        return lambda <= 1e12 ? mp50(grazing_quadrature(brdf, double(lambda_t), double(dy), double(dz)))
                              : grazing_limit(brdf, lambda_t, dy, dz);
      };
      const mp50 expected = expected_for(mp50(lambda), mp50(0.0), mp50(std::numbers::pi));
      const double d = eval_row<double>(ref, row);
      std::printf("%s λ=%g: double %.6e, expected %.6e\n", name, lambda, d, double(expected));
      expect_close(d, expected, 2e-6, std::string(name) + " double λ=" + std::to_string(lambda));
      // mp50: the Gaussian-NDF reference forms the offset in 50 digits, so an azimuth π to 50
      // digits puts the light 1e-50 rad off (GGX's reference converts the inputs to double first).
      std::vector<mp50> row50{mp50(0.3), mp50(lambda), mp50(0), mp50(0), pi, mp50(0.04)};
      const mp50 m50 = sglab::eval_as<mp50>(ref, std::span<const mp50>(row50));
      // Up to λ = 1e12 the light is ≥ 1e-6 rad wide, and moving it by the double azimuth's 1.22e-16
      // rad changes L by O(1.22e-16·√λ) ≤ 1.3e-10 relative (tolerance 2e-6): the quadrature for the double row
      // serves. Beyond, the sharp limit at the 50-digit offset.
      const mp50 expected50 = (ggx || lambda <= 1e12) ? expected : expected_for(mp50(lambda), mp50(0), pi);
      std::printf("%s λ=%g: mp50 (azimuth π to 50 digits) %.6e, expected %.6e\n", name, lambda, double(m50),
                  double(expected50));
      expect_close(m50, expected50, 2e-6, std::string(name) + " mp50 λ=" + std::to_string(lambda));
      if (lambda <= 1e38) {
        const float fl = eval_row<float>(ref, row);
        const mp50 expected_f = expected_for(mp50(float(lambda)), mp50(0), mp50(float(std::numbers::pi)));
        std::printf("%s λ=%g: float %.6e, expected %.6e\n", name, lambda, double(fl), double(expected_f));
        expect_close(fl, expected_f, 2e-6, std::string(name) + " float λ=" + std::to_string(lambda));
      }
    }
  }
  // The light exactly at the mirror direction (δ = 0, which no double azimuth reaches): the
  // λ^{−1/2} law up to DBL_MAX.
  const GrazingBrdf brdf{false, 0.3, 0.04};
  for (const double lambda : {1e16, 1e100, 1e300, kDblMax}) {
    const sglab::SpecularConfig c{0.3, lambda, 0.0, 0.0, std::numbers::pi, 0.04};
    const double v = sglab::specular_gaussian_ndf_reference_grazing(c, sglab::Vec3d(0, 0, 0));
    const mp50 expected = grazing_limit(brdf, mp50(lambda), mp50(0), mp50(0));
    std::printf("δ = 0, λ=%g: %.6e·λ^{-1/2}, expected %.6e·λ^{-1/2}\n", lambda, v * std::sqrt(lambda),
                double(expected * sqrt(mp50(lambda))));
    expect_close(v, expected, 2e-6, "δ = 0 λ=" + std::to_string(lambda));
  }
}

// The ASG × SG product's `exact` method with both lobes sharp and of similar sharpness (its 2D
// quadrature about the SG axis), against the sharp limit derived here: with ω = (x, y, √(1 − x² − y²))
// and the SG axis ξ = (ax, ay, c), Ĝ G = (ω·z)e^{−ηx x² − ηy y²}·e^{−λ‖ω − ξ‖²/2}, and as every
// sharpness → ∞ only x, y = O(η^{−1/2}) count, where ω·z = 1 − O(r²) and ‖ω − ξ‖² =
// (x − ax)² + (y − ay)² + O(r⁴): the product of two Gaussians in the tangent plane,
//   ∫ Ĝ G dω → π/√((ηx + λ/2)(ηy + λ/2))·exp(−(ηxλ/2)/(ηx + λ/2)·ax² − (ηyλ/2)/(ηy + λ/2)·ay²),
// relative error O(1/η) (≤ 1e-8 here, from ηmin ≥ 1e8). In 50 digits from the row's doubles (the
// method rounds its inputs to double; the cosine 1 − k·1e-12 is not the decimal text). Offsets of
// the SG axis of ~1 lobe width are representable only while the width ≥ 1.5e-8 (1 − c ≥ 1.1e-16),
// so η ≤ 1e14 carries them; above, ξ = z. At ηx = ηy = λ = DBL_MAX the line limit's error bound
// overflowed to 0 and took the line limit for two equal lobes: 0 instead of π/(1.5·DBL_MAX)
// (1.17e-308, a subnormal: compared within 2e-6 relative plus double's smallest subnormal).
TEST(HardeningExtremes, GroupL_AsgSgProductBothSharp) {
  const sglab::Method& exact = method("asg-sg-product-integral", "exact");
  const mp50 pi = boost::math::constants::pi<mp50>();
  auto limit = [&](const std::vector<double>& r) {
    const mp50 ex(r[0]), ey(r[1]), l(r[2]), c(r[3]), az(r[4]);
    const mp50 s = sqrt((1 - c) * (1 + c)), ax = s * cos(az), ay = s * sin(az);
    const mp50 hx = ex + l / 2, hy = ey + l / 2;
    return pi / sqrt(hx * hy) * exp(-(ex * l / 2) / hx * ax * ax - (ey * l / 2) / hy * ay * ay);
  };
  std::vector<std::vector<double>> rows;
  for (const double e : {1e8, 1e10, 1e12, 1e14, 1e16, 1e20, 1e50, 1e100, 1e200, 1e300, kDblMax}) {
    // (ηx, ηy, λ) ratios around 1: equal, anisotropic, the SG 4× broader or 4× sharper
    for (const auto& [ry, rl] :
         std::vector<std::pair<double, double>>{{1, 1}, {0.5, 1}, {1, 0.25}, {0.1, 0.3}, {1, 0.004}}) {
      rows.push_back({e, e * ry, e * rl, 1.0, 0.0});
      // Offset rows (each a 2D quadrature of the method, ≈ 0.025 CPU s per evaluation) at the two ends
      // of the range that carries offsets, ηx = 1e8 (the limit's O(1/η) at the tolerance's edge) and
      // 1e14 (the last with offsets); 1e10 and 1e12 between them keep their rows without offset. Of
      // the ratios, the ends: equal lobes, the most anisotropic ASG (ηy = ηx/10, the SG 3× broader)
      // and the broadest SG (λ = ηx/250); the two between them keep their rows without offset.
      const bool end_ratio = (ry == 1 && rl == 1) || ry == 0.1 || rl == 0.004;
      if ((e == 1e8 || e == 1e14) && end_ratio)
        for (const auto& [k, az] : std::vector<std::pair<double, double>>{{1, 0.0}, {2, 0.7}, {0.5, 2.0}})
          rows.push_back({e, e * ry, e * rl, 1 - k / e, az});
    }
    if (e <= 1e300) rows.push_back({e / 4, e, 4 * e, 1.0, 0.0});  // the SG the sharpest
  }
  for (const auto& r : rows) {
    const mp50 expected = limit(r);
    const std::string what = "ηx=" + std::to_string(r[0]) + " ηy=" + std::to_string(r[1]) +
                             " λ=" + std::to_string(r[2]) + " c=" + std::to_string(r[3]) + " φ=" + std::to_string(r[4]);
    expect_close(eval_row<double>(exact, r), expected, 2e-6, "double " + what);
    expect_close(eval_row<mp50>(exact, r), expected, 2e-6, "mp50 " + what);
    if (r[0] <= 1e30 && r[2] <= 1e30 && r[3] == 1.0)  // float: the inputs exact in float, the value a normal float
      expect_close(eval_row<float>(exact, r),
                   limit({double(float(r[0])), double(float(r[1])), double(float(r[2])), 1.0, 0.0}), 2e-6,
                   "float " + what);
  }
}

// `punctual-approx` at the smallest normal sharpness of each type: 2π⟨c⟩/λ in 50 digits where it
// fits in the type (it printed "-nan" at DBL_MIN), +inf never: where it does not fit, as `sglab eval`
// refuses it, the value is not finite and the row is refused by the caller (checked end to end in
// hardening_test's Group08).
TEST(HardeningExtremes, GroupG_PunctualApproxAtSmallestNormal) {
  const sglab::Method& m = method("clamped-cosine", "punctual-approx");
  const mp50 two_pi = 2 * boost::math::constants::pi<mp50>();
  for (const double c : {1e-300, 0.25, 0.5, 0.6}) {
    const double lambda = std::numeric_limits<double>::min();
    const mp50 expected = two_pi * mp50(c) / mp50(lambda);
    ASSERT_LT(expected, mp50(kDblMax));
    EXPECT_LT(rel(eval_row<double>(m, {lambda, c}), expected), 4e-16) << "double c=" << c;
    EXPECT_LT(rel(double(eval_row<mp50>(m, {lambda, c})), expected), 1e-15) << "mp50 c=" << c;
  }
  for (const double c : {1e-30, 0.25, 0.5}) {
    const float lambda = std::numeric_limits<float>::min();
    const mp50 expected = two_pi * mp50(float(c)) / mp50(lambda);
    ASSERT_LT(expected, mp50(std::numeric_limits<float>::max()));
    EXPECT_LT(rel(double(eval_row<float>(m, {double(lambda), c})), expected), 3e-7) << "float c=" << c;
  }
  // ⟨c⟩ = 0 at the smallest normal: exactly 0 (not ∞·0).
  EXPECT_EQ(eval_row<double>(m, {std::numeric_limits<double>::min(), 0.0}), 0.0);
  EXPECT_EQ(eval_row<float>(m, {double(std::numeric_limits<float>::min()), -0.5}), 0.0f);
  // Where 2π⟨c⟩/λ exceeds the type's largest value the result is +inf (never NaN), which the
  // callers' finite-result check refuses.
  EXPECT_EQ(eval_row<double>(m, {std::numeric_limits<double>::min(), 1.0}), std::numeric_limits<double>::infinity());
}

}  // namespace
