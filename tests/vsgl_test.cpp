// tests for core/include/sglab/vsgl.hpp: the VSGL sums against closed-form moments, the
// incoming-radiance SG (Eq. 7) against the direct product in 50 digits, the single-VPL limit of
// the shading, and the specular receiver against specular.hpp's `asg` method.
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <utility>
#include <vector>

#include "sglab/clamped_cosine.hpp"
#include "sglab/reference.hpp"
#include "sglab/specular.hpp"
#include "sglab/vsgl.hpp"
#include "test_util.hpp"
#include "sglab/reference_mp50.hpp"

namespace sglab {
namespace {

using V3 = Vec3<double>;
using C3 = Rgb<double>;

V3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  V3 v;
  do v = V3(g(rng), g(rng), g(rng));
  while (v.norm() < 1e-3);
  return v.normalized();
}

double log_uniform(std::mt19937_64& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(std::log10(lo), std::log10(hi));
  return std::pow(10.0, u(rng));
}

// ---- sums ------------------------------------------------------------------------------------

// Three symmetric pairs μ0 ± a e_x (weight w1 each), μ0 ± b e_y (w2), μ0 ± c e_z (w3):
// μ = μ0 and σ² = (w1 a² + w2 b² + w3 c²)/(w1 + w2 + w3) in closed form.
// Tolerance: the documented bound of vsgl.hpp, a few ε·(‖μ − o‖² + σ²)/σ².
template <class T>
void check_symmetric_pairs(const Vec3<T>& origin) {
  const Vec3<T> mu0(T(0.75), T(-1.5), T(2.25));
  const T a = T(0.5), b = T(0.25), c = T(1.0);
  const T w1 = T(1), w2 = T(2), w3 = T(0.5);
  std::vector<std::pair<T, Vec3<T>>> vpls = {{w1, mu0 + Vec3<T>(a, 0, 0)}, {w1, mu0 - Vec3<T>(a, 0, 0)},
                                             {w2, mu0 + Vec3<T>(0, b, 0)}, {w2, mu0 - Vec3<T>(0, b, 0)},
                                             {w3, mu0 + Vec3<T>(0, 0, c)}, {w3, mu0 - Vec3<T>(0, 0, c)}};
  VsglPositionSums<T> all, first_half, second_half;
  for (std::size_t i = 0; i < vpls.size(); ++i) {
    add_position(all, vpls[i].first, vpls[i].second, origin);
    add_position(i < 3 ? first_half : second_half, vpls[i].first, vpls[i].second, origin);
  }
  const double var = double((w1 * a * a + w2 * b * b + w3 * c * c) / (w1 + w2 + w3));
  const double rel_tol = 4 * double(std::numeric_limits<T>::epsilon()) * (double((mu0 - origin).squaredNorm()) + var) /
                         var;
  VsglPositionSums<T> merged = first_half;
  merged += second_half;  // sums are additive (mip levels and clusters add them)
  for (const auto* s : {&all, &merged}) {
    const VsglPosition<T> p = vsgl_position(*s, origin);
    EXPECT_LE(double((p.mean - mu0).norm()), rel_tol * double(mu0.norm()));
    EXPECT_LE(test::relative_error(double(p.variance), var), rel_tol) << double(p.variance) << " vs " << var;
    // The public code's per-axis convention is half the total.
    EXPECT_LE(test::relative_error(double(vsgl_position(*s, origin, VarianceConvention::per_axis).variance), var / 2),
              rel_tol);
  }
}

TEST(VsglSums, SymmetricPairsGiveTheClosedFormMoments) {
  check_symmetric_pairs<double>(Vec3<double>::Zero());
  check_symmetric_pairs<double>(Vec3<double>(0.3, -0.2, 0.1));
  check_symmetric_pairs<float>(Vec3<float>::Zero());
  check_symmetric_pairs<float>(Vec3<float>(0.3f, -0.2f, 0.1f));
}

// An n × n grid of spacing h on a plane far from the origin, uniform weights:
// σ² = 2h²(n² − 1)/12 (the variance of n equispaced points, twice), μ = the grid centre.
// far + i·h must be exact in T (h a power of two), so that the inputs are the ideal grid.
template <class T>
void check_far_coplanar(double far, double h, double rel_tol) {
  const int n = 8;
  const Vec3<T> corner = Vec3<T>::Constant(T(far));
  std::vector<Vec3<T>> pts;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) pts.push_back(corner + Vec3<T>(T(i * h), T(j * h), T(0)));
  const Vec3<T> origin = pts.front();  // any point near the set
  VsglPositionSums<T> s;
  for (const auto& y : pts) add_position(s, T(0.5), y, origin);
  const VsglPosition<T> p = vsgl_position(s, origin);
  const double var = 2 * h * h * (n * n - 1) / 12.0;
  EXPECT_GE(double(p.variance), 0.0);
  EXPECT_LE(test::relative_error(double(p.variance), var), rel_tol) << "far " << far;
  const double centre = far + h * (n - 1) / 2.0;
  EXPECT_LE(std::abs(double(p.mean(0)) - centre), 4 * double(std::numeric_limits<T>::epsilon()) * far);
  // What the reference point buys: the same sums relative to 0 (printed, not asserted).
  VsglPositionSums<T> naive;
  for (const auto& y : pts) add_position(naive, T(0.5), y, Vec3<T>::Zero());
  std::printf("far %g, h %g (%s): variance rel. error %.2e relative to a point of the set, %.2e relative to 0\n", far,
              h, sizeof(T) == 4 ? "float" : "double", test::relative_error(double(p.variance), var),
              test::relative_error(double(vsgl_position(naive, Vec3<T>::Zero()).variance), var));
}

TEST(VsglSums, CoplanarFarFromTheOriginKeepTheirVariance) {
  // double: 1e6 + k·2^-10 needs 30 bits; the naive sums lose all digits (ε·far²/σ² ≈ 4e3).
  check_far_coplanar<double>(1e6, 0x1.0p-10, 1e-12);
  // float: 1e4 + k·0.25 is exact (10 fraction bits left).
  check_far_coplanar<float>(1e4, 0.25, 2e-6);
}

TEST(VsglSums, CoincidentVplsHaveZeroVarianceNeverNegative) {
  const Vec3<double> y(1e6 + 0.1, -3e5, 7.3);
  const Vec3<float> yf(1e4f + 0.1f, -3e3f, 7.3f);
  VsglPositionSums<double> s;
  VsglPositionSums<float> sf;
  for (int i = 0; i < 7; ++i) {
    add_position(s, 0.1 * (i + 1), y, Vec3<double>::Zero());  // the worst origin
    add_position(sf, 0.1f * float(i + 1), yf, Vec3<float>::Zero());
  }
  const auto p = vsgl_position(s, Vec3<double>::Zero());
  const auto pf = vsgl_position(sf, Vec3<float>::Zero());
  EXPECT_GE(p.variance, 0.0);
  EXPECT_GE(pf.variance, 0.0f);
  // Rounding residue only: ε‖y‖² at most (the exact value is 0).
  EXPECT_LE(p.variance, 8 * 2.2e-16 * y.squaredNorm());
  EXPECT_LE((p.mean - y).norm(), 4e-16 * y.norm());
}

// ---- intensity SG ---------------------------------------------------------------------------

TEST(VsglIntensity, OneLobeIsReturnedUnchanged) {
  const C3 power(0.3, 0.5, 0.2);
  const V3 axis = V3(1, 2, -2).normalized();
  for (auto e : {SharpnessEstimator::toksvig, SharpnessEstimator::banerjee}) {
    for (double l : test::log_grid(-6, 6, 2)) {
      VsglLobeSums<double> s;
      add_lobe(s, power, axis, vsgl_mean_length(l, e));
      const VsglIntensity<double> v = vsgl_intensity(s, e);
      // λ → r → λ: the condition number of r ↦ λ is ≈ λ near r = 1.
      EXPECT_LE(test::relative_error(v.sharpness, l), 2e-15 * (4 + l)) << l;
      EXPECT_LE((v.axis - axis).norm(), 4e-16);
      const C3 expected = power / sg_integral(l);
      EXPECT_LE(((v.amplitude - expected).abs() / expected).maxCoeff(), 2e-15 * (4 + l)) << l;
    }
  }
  // A lobe sharper than the cap (α → 0 specular VPL): clamped, finite.
  VsglLobeSums<double> s;
  add_lobe(s, power, axis, vsgl_mean_length(1e16, SharpnessEstimator::toksvig));
  EXPECT_EQ(vsgl_intensity(s).sharpness, kMaxFilteredSharpness);
  EXPECT_TRUE(vsgl_intensity(s).amplitude.isFinite().all());
  // No lobe at all: zero amplitude, no NaN.
  const VsglIntensity<double> empty = vsgl_intensity(VsglLobeSums<double>{});
  EXPECT_TRUE((empty.amplitude == 0).all());
  EXPECT_EQ(empty.sharpness, 0.0);
}

TEST(VsglIntensity, TwoLobesGiveTheToksvigMeanInClosedForm) {
  // Lobes of sharpness λ at axes ±θ/2 from z, powers P1 (luminance w1) and P2 (w2):
  // ξ̄_v = r(λ)(w1 n1 + w2 n2)/(w1 + w2), whose length and direction are elementary.
  const double l = 2.2925;
  const double theta = 1.1;
  const V3 n1(std::sin(theta / 2), 0, std::cos(theta / 2)), n2(-std::sin(theta / 2), 0, std::cos(theta / 2));
  const C3 p1(1, 0, 0), p2(0, 0, 1);  // pure red and pure blue: weights 0.2126 and 0.0722 (Rec. 709)
  const double w1 = 0.2126, w2 = 0.0722;
  VsglLobeSums<double> s;
  add_lobe(s, p1, n1, vmf_mean_length_toksvig(l));
  add_lobe(s, p2, n2, vmf_mean_length_toksvig(l));
  const VsglIntensity<double> v = vsgl_intensity(s);
  const double r0 = l / (l + 1);
  const double x = r0 * (w1 - w2) * std::sin(theta / 2) / (w1 + w2), z = r0 * std::cos(theta / 2);
  const double r = std::hypot(x, z);
  EXPECT_LE(test::relative_error(v.sharpness, r / (1 - r)), 1e-14);
  EXPECT_LE((v.axis - V3(x / r, 0, z / r)).norm(), 1e-15);
  EXPECT_LE(((v.amplitude - (p1 + p2) / sg_integral(r / (1 - r))).abs()).maxCoeff(), 1e-15);
}

// ---- incoming radiance (Eq. 7) -----------------------------------------------------------------

// c_v/(2πσ²)·G(ω; −ξ_v, λ_v)·G(ω; ξ_μ, λ_σ) evaluated directly from the definitions in 50 digits.
mp50 direct_incoming(const V3& mean, double variance, const V3& yp, const V3& axis, double sharpness, const V3& omega) {
  using std::exp;
  const Vec3<mp50> d = (mean - yp).cast<mp50>();
  const mp50 d2 = d.squaredNorm();
  const Vec3<mp50> xi_mu = d / sqrt(d2);
  const mp50 lambda_sigma = d2 / mp50(variance);
  const Vec3<mp50> w = omega.cast<mp50>();
  const mp50 g1 = exp(mp50(sharpness) * (w.dot(-axis.cast<mp50>()) - 1));
  const mp50 g2 = exp(lambda_sigma * (w.dot(xi_mu) - 1));
  return g1 * g2 / (two_pi<mp50>() * mp50(variance));
}

TEST(VsglIncoming, EqualsTheDirectProductAtRandomDirections) {
  auto rng = test::seeded_rng(7001);
  std::uniform_real_distribution<double> box(-1.0, 1.0);
  double worst = 0, worst_float = 0;
  int compared = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const V3 mean(box(rng), box(rng), box(rng)), yp(box(rng), box(rng), box(rng));
    const double variance = log_uniform(rng, 1e-4, 1.0);
    const V3 axis = random_unit(rng);
    const double sharpness = log_uniform(rng, 1e-3, 1e3);
    const VsglIncomingSg<double> in = vsgl_incoming_sg(vsgl_positional_sg(mean, variance, yp), axis, sharpness);
    const VsglIncomingSg<float> inf = vsgl_incoming_sg(
        vsgl_positional_sg<float>(mean.cast<float>(), float(variance), yp.cast<float>()),
        Vec3<float>(axis.cast<float>()), float(sharpness));
    const double lambda_sigma = (mean - yp).squaredNorm() / variance;
    for (int k = 0; k < 8; ++k) {
      // Half of the directions near the product's axis, where the value is not negligible.
      V3 omega = random_unit(rng);
      if (k % 2 == 0) omega = (in.axis + omega / std::sqrt(1 + in.sharpness)).normalized();
      const mp50 ref = direct_incoming(mean, variance, yp, axis, sharpness, omega);
      if (ref < mp50(1e-250)) continue;
      const double value = std::exp(in.log_scale) * sg_eval(omega, in.axis, in.sharpness);
      // Rounding of the exponents: ~ε(λ_v + λ_σ) relative.
      const double err = test::relative_error(value, double(ref)) / (1 + sharpness + lambda_sigma);
      worst = std::max(worst, err);
      EXPECT_LE(err, 4e-15) << "trial " << trial << " value " << value << " ref " << double(ref);
      const Vec3<float> of = omega.cast<float>();
      const float vf = std::exp(inf.log_scale) * sg_eval(of, inf.axis, inf.sharpness);
      if (double(ref) > 1e-30) {
        const double ef = test::relative_error(double(vf), double(ref)) / (1 + sharpness + lambda_sigma);
        worst_float = std::max(worst_float, ef);
        EXPECT_LE(ef, 4e-6) << "float trial " << trial;
      }
      ++compared;
    }
  }
  std::printf("compared %d points; worst error / (1 + λ_v + λ_σ): double %.2e, float %.2e\n", compared, worst,
              worst_float);
  EXPECT_GT(compared, 1000);
}

TEST(VsglIncoming, ShadingPointOnTheMean) {
  // λ_σ = 0: L_in = c_v/(2πσ²)·G(ω; −ξ_v, λ_v) exactly, whatever ξ_μ.
  const V3 mean(0.2, 0.3, -0.1), axis = V3(0, 0.6, 0.8);
  const double variance = 0.04, sharpness = 3.5;
  const VsglIncomingSg<double> in = vsgl_incoming_sg(vsgl_positional_sg(mean, variance, mean), axis, sharpness);
  EXPECT_EQ(in.sharpness, sharpness);
  EXPECT_LE((in.axis + axis).norm(), 4e-16);
  for (const V3& w : {V3(0, 0, 1), V3(0, -0.6, -0.8), V3(1, 0, 0)}) {
    const double expected = sg_eval(w, V3(-axis), sharpness) / (two_pi<double>() * variance);
    EXPECT_LE(test::relative_error(std::exp(in.log_scale) * sg_eval(w, in.axis, in.sharpness), expected), 1e-15);
  }
  // float: finite and the same.
  const auto inf = vsgl_incoming_sg(vsgl_positional_sg<float>(mean.cast<float>(), 0.04f, mean.cast<float>()),
                                    Vec3<float>(axis.cast<float>()), 3.5f);
  EXPECT_TRUE(std::isfinite(inf.log_scale));
  EXPECT_NEAR(inf.sharpness, 3.5f, 1e-6f);
}

TEST(VsglIncoming, ZeroVarianceIsAPointLight) {
  // σ² = 0: λ_σ is capped at 1e8 (σ² floored at d²·1e-8). The incoming radiance then integrates
  // to c_v G(ξ_μ; −ξ_v, λ_v)/d², the point light, up to O((1 + λ_v)/λ_σ): the product with
  // G(ω; −ξ_v, λ_v) shifts and widens the SG by that much.
  const V3 mean(0.1, 0.2, 0.3), yp(1.1, -0.7, 2.0), axis = V3(-0.48, 0.6, -0.64);
  const double sharpness = 12.0;
  const V3 d = mean - yp;
  for (double variance : {0.0, 1e-300, 1e-20}) {
    const VsglPositionalSg<double> pos = vsgl_positional_sg(mean, variance, yp);
    EXPECT_EQ(pos.sharpness, kMaxPositionalSharpness);
    const VsglIncomingSg<double> in = vsgl_incoming_sg(pos, axis, sharpness);
    const double integral = std::exp(in.log_scale) * sg_integral(in.sharpness);
    const double point = sg_eval(V3(d.normalized()), V3(-axis), sharpness) / d.squaredNorm();
    EXPECT_LE(test::relative_error(integral, point), 2e-8 * (1 + sharpness)) << variance;
    // float: finite.
    const auto inf = vsgl_incoming_sg(vsgl_positional_sg<float>(mean.cast<float>(), float(variance), yp.cast<float>()),
                                      Vec3<float>(axis.cast<float>()), 12.0f);
    const float integral_f = std::exp(inf.log_scale) * sg_integral(inf.sharpness);
    EXPECT_LE(test::relative_error(double(integral_f), point), 1e-5) << variance;
  }
  // σ² = 0 and the shading point on the VPL: no defined direction; contributes nothing (no NaN).
  const VsglPositionalSg<double> on = vsgl_positional_sg(mean, 0.0, mean);
  EXPECT_TRUE(on.empty);
  const VsglIncomingSg<double> none = vsgl_incoming_sg(on, axis, sharpness);
  EXPECT_EQ(
      vsgl_clamped_cosine(none, V3(0, 0, 1), [](double l, double c) { return clamped_cosine_tokuyoshi2024(l, c); }),
      0.0);
}

TEST(VsglIncoming, TinyVarianceDoesNotOverflow) {
  // c_v/(2πσ²) overflows float for σ² < 5e-40 and double for σ² < 1e-309; kept as a log and
  // combined with the small factor in log space. The shading point is close enough to μ that the
  // cap does not apply (λ_σ = d²/σ² < 1e8): double d = 1e-12, σ² = 1e-31 (finite either way);
  // float d = 1e-17, σ² = 1e-40 (subnormal): 1/(2πσ²) = e^{90.3} > FLT_MAX = e^{88.7}, while the
  // radiance itself, ≈ G/d² ≈ 1e34, is representable.
  const V3 mean(0, 0, 0), yp(1e-12, 0, 0), axis(1, 0, 0), n(-1, 0, 0);
  auto method = [](auto l, auto c) { return clamped_cosine_punctual(l, c); };
  const VsglIncomingSg<double> in = vsgl_incoming_sg(vsgl_positional_sg(mean, 1e-31, yp), axis, 2.0);
  const double d = vsgl_clamped_cosine(in, n, method);
  EXPECT_TRUE(std::isfinite(d) && d > 0) << d;
  const VsglIncomingSg<float> inf = vsgl_incoming_sg(
      vsgl_positional_sg<float>(Vec3<float>::Zero(), 1e-40f, Vec3<float>(1e-17f, 0, 0)), Vec3<float>(1, 0, 0), 2.0f);
  const float df = vsgl_clamped_cosine(inf, Vec3<float>(-1, 0, 0), method);
  EXPECT_TRUE(std::isfinite(df) && df > 0) << df;
  EXPECT_GT(inf.log_scale, 89.0f);  // e^{log_scale} alone would overflow float
}

// ---- the single-VPL limit ----------------------------------------------------------------------

// Four VPLs at y ± s e1, y ± s e2 in the VPL plane (normal n_v), equal power: a cluster whose
// intensity SG is exactly each VPL's own lobe (same normals: r = r(λ_d), λ_v = λ_d) and whose
// positional variance is s². As s → 0 its shading converges to the point light
//   I(−ξ_μ)·ρ̃(ξ_μ)/d²,   I(ω) = ΣΦ_iR_i G(ω; n_v, λ_d)/A(λ_d)  (the VPLs' own SG intensity),
// ρ̃ = the receiver's lobe model in the limit λ_in → ∞: R_d/π⟨ξ_μ·n_p⟩ for reference, punctual,
// punctual-approx, tokuyoshi2024; R_d/π·πG(ξ_μ; n_p, λ_d)/A(λ_d) for sg-cosine (its SG cosine);
// M(ξ_μ)Ĝ(ξ_μ)/(πα²) for the ASG specular. The relative error is O(s²/d²) (measured: 1.1e-2 at
// s/d = 0.064 for the exact D, 3.2e-2 for the specular); at s = 0 (σ² = 0, λ_σ capped at 1e8) it
// is O((1 + λ)/1e8) plus the method's own error at λ = 1e8.
TEST(VsglSingleVplLimit, ShadingConvergesToThePointLight) {
  const double lambda_d = 2.292504;
  const V3 y(0.3, -0.2, 0.0), nv = V3(0.1, 0.2, 1.0).normalized();
  const V3 e1 = nv.unitOrthogonal(), e2 = nv.cross(e1);
  const V3 yp(0.9, 0.4, 1.3), np = V3(-0.3, -0.2, -1.0).normalized(), view = V3(0.2, 0.1, -1).normalized();
  const double alpha = 0.3;
  const C3 phi_r(0.8, 0.6, 0.4);  // Φ R_d of each of the four VPLs
  const V3 d = y - yp;
  const V3 xi_mu = d.normalized();
  const double intensity = sg_eval(V3(-xi_mu), nv, lambda_d) / sg_integral(lambda_d);  // per unit ΦR
  const double d2 = d.squaredNorm();
  // Point-light references (per unit ΦR, R_d = 1 at the receiver, without the 1/π of R_d/π for diffuse).
  const double cos_p = std::max(0.0, xi_mu.dot(np));
  const double point_cosine = 4 * intensity * cos_p / d2;
  const double point_sg_cosine = 4 * intensity * pi<double>() * sg_eval(xi_mu, np, lambda_d) / sg_integral(lambda_d) /
                                 d2;
  const VsglSpecularReceiver<double> rec = vsgl_specular_receiver(np, view, alpha);
  const V3 xi_local(xi_mu.dot(rec.tangent), xi_mu.dot(rec.bitangent), xi_mu.dot(rec.normal));
  const double point_specular = 4 * intensity * brdf_factor_m(rec.roughness, 1.0, rec.view_local, xi_local) *
                                asg_eval(xi_local, rec.lobe) * rec.ndf_amplitude / d2;
  ASSERT_GT(cos_p, 0.3);
  ASSERT_GT(point_specular, 0.0);

  struct Method {
    const char* name;
    std::function<double(double, double)> d;
    double point;
    double tol_at_zero;  // at σ² = 0: 1e-7 + the method's own error at λ = 1e8
  };
  const std::vector<Method> methods = {
      {"reference", [](double l, double c) { return clamped_cosine_reference(l, c); }, point_cosine, 1e-7},
      {"punctual-approx", [](double l, double c) { return clamped_cosine_punctual_approx(l, c); }, point_cosine, 1e-7},
      {"tokuyoshi2024", [](double l, double c) { return clamped_cosine_tokuyoshi2024(l, c); }, point_cosine, 1e-7},
      {"sg-cosine", [&](double l, double c) { return clamped_cosine_sg_cosine(l, c, lambda_d); }, point_sg_cosine,
       1e-7},
  };
  // The four VPLs at ±s along e1 and e2 around y, summed, as their intensity SG and the incoming
  // SG at the receiver.
  const auto cluster = [&](double s) {
    VsglSums<double> sums;
    for (const V3& off : {V3(s * e1), V3(-s * e1), V3(s * e2), V3(-s * e2)}) {
      add_position(sums.position, luminance(phi_r), V3(y + off), y);
      add_lobe(sums.diffuse, phi_r, nv, vmf_mean_length_toksvig(lambda_d));
    }
    const VsglPosition<double> p = vsgl_position(sums.position, y);
    EXPECT_LE(test::relative_error(p.variance, s * s), 1e-12);
    const VsglIntensity<double> v = vsgl_intensity(sums.diffuse);
    EXPECT_LE(test::relative_error(v.sharpness, lambda_d), 1e-14);
    return std::pair(v, vsgl_incoming_sg(vsgl_positional_sg(p.mean, p.variance, yp), v.axis, v.sharpness));
  };
  // Quadratic convergence: each tenfold shrink of s divides the error by ≈ 100 (≤ 1/80 asserted;
  // linear convergence would give 1/10), until λ_σ = d²/s² reaches the 1e8 cap (s ≤ 1.6e-4 here),
  // from where the cluster is the capped point light of σ² = 0, within tol_at_zero.
  const auto expect_converges = [](const char* name, double tol_at_zero,
                                   const std::function<double(double)>& error_at) {
    double previous = 1;
    for (double s : {1e-1, 1e-2, 1e-3, 1e-4, 0.0}) {
      const double err = error_at(s);
      std::printf("%-16s s = %-6g rel. error %.3e\n", name, s, err);
      if (s == 1e-2 || s == 1e-3) {
        EXPECT_LE(err, previous / 80) << name << " s " << s;
      }
      if (s < 1.6e-4) {
        EXPECT_LE(err, tol_at_zero) << name << " s " << s;
      }
      previous = err;
    }
  };
  for (const auto& m : methods) {
    expect_converges(m.name, m.tol_at_zero, [&](double s) {
      const auto [v, in] = cluster(s);
      const C3 diffuse = v.amplitude * vsgl_clamped_cosine(in, np, m.d);
      return ((diffuse / phi_r - m.point).abs()).maxCoeff() / m.point;
    });
  }
  // Specular at a glossy receiver (f0 = 1: M's Fresnel is 1).
  expect_converges("asg specular", 1e-6, [&](double s) {
    const auto [v, in] = cluster(s);
    const VsglSpecularFactor<double> f = vsgl_specular(in, rec);
    return std::abs(f.at_f0_one * v.amplitude(0) / phi_r(0) - point_specular) / point_specular;
  });
}

// ---- the specular receiver in an arbitrary frame ---------------------------------------------

TEST(VsglSpecular, MatchesTheRegisteredAsgMethodInAnyFrame) {
  // vsgl_specular works in the shading point's frame (t, b, n); specular.hpp's `asg` in the
  // canonical one (n = z, view in the xz plane). Same SG light, same answer.
  auto rng = test::seeded_rng(7002);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const V3 n = random_unit(rng);
    const V3 t = n.unitOrthogonal(), b = n.cross(t);
    const double view_cos = 0.05 + 0.95 * u(rng), phi_v = 2 * M_PI * u(rng);
    const double sv = std::sqrt(1 - view_cos * view_cos);
    const V3 view = view_cos * n + sv * (std::cos(phi_v) * t + std::sin(phi_v) * b);
    const double light_cos = -0.3 + 1.3 * u(rng), phi_l = 2 * M_PI * u(rng);
    const double sl = std::sqrt(1 - light_cos * light_cos);
    const V3 xi = light_cos * n + sl * (std::cos(phi_v + phi_l) * t + std::sin(phi_v + phi_l) * b);
    const double alpha = log_uniform(rng, 0.02, 1.0), lambda = log_uniform(rng, 1e-2, 1e4), f0 = u(rng);
    VsglIncomingSg<double> in;
    in.axis = xi;
    in.sharpness = lambda;
    in.log_scale = 0;
    const VsglSpecularFactor<double> f = vsgl_specular(in, vsgl_specular_receiver(n, view, alpha));
    const double value = f.at_f0_zero + f0 * (f.at_f0_one - f.at_f0_zero);
    const double expected = specular_asg(SpecularInput<double>{alpha, lambda, light_cos, view_cos, phi_l, f0});
    const double scale = std::max(expected, 1e-300);
    const double err = std::abs(value - expected) / scale;
    if (expected > 1e-200) worst = std::max(worst, err);
    EXPECT_LE(std::abs(value - expected), 1e-11 * scale + 1e-300) << trial;
  }
  std::printf("worst relative difference to specular_asg: %.2e\n", worst);
}

TEST(VsglSpecular, VplLobeIsTheSphericalWarpInAnyFrame) {
  auto rng = test::seeded_rng(7003);
  for (int trial = 0; trial < 100; ++trial) {
    const V3 n = random_unit(rng);
    V3 incoming = random_unit(rng);
    if (incoming.dot(n) < 0) incoming = -incoming;
    const double alpha = log_uniform(rng, 1e-3, 1.0);
    const SgLobe<double> lobe = vpl_specular_lobe(n, incoming, alpha);
    // The canonical frame's spherical_warp (brdf.hpp).
    const V3 t = n.unitOrthogonal(), b = n.cross(t);
    const V3 local(incoming.dot(t), incoming.dot(b), incoming.dot(n));
    const SgLobe<double> ref = spherical_warp(ggx_ndf_sg(alpha), local);
    EXPECT_LE(test::relative_error(lobe.sharpness, ref.sharpness), 1e-14);
    EXPECT_LE((V3(lobe.axis.dot(t), lobe.axis.dot(b), lobe.axis.dot(n)) - ref.axis).norm(), 1e-14);
  }
}

// ---- stiff inputs in float ---------------------------------------------------------------------

TEST(VsglStiff, FloatShadingIsFiniteAndNonNegative) {
  using F = float;
  using V = Vec3<F>;
  auto method = [](F l, F c) { return clamped_cosine_tokuyoshi2024(l, c); };
  const V n(0, 0, 1);
  const VsglSpecularReceiver<F> rec = vsgl_specular_receiver(n, V(0.6f, 0, 0.8f), F(1e-4));
  const VsglSpecularReceiver<F> grazing = vsgl_specular_receiver(n, V(1, 0, 0), F(0.5));
  for (F variance : {F(0), F(1e-38), F(1e-10), F(1), F(1e30)}) {
    for (const V& mean : {V(0, 0, 0), V(0, 0, 1e-3f), V(0.3f, 0.1f, 2), V(1e15f, 0, 1)}) {
      for (F sharpness : {F(0), F(1e-8), F(2.29f), F(1e8)}) {
        const auto in = vsgl_incoming_sg(vsgl_positional_sg(mean, variance, V(0, 0, 0)), V(0, 0, -1), sharpness);
        const F d = vsgl_clamped_cosine(in, n, method);
        EXPECT_TRUE(std::isfinite(d) && d >= 0) << variance << " " << mean.transpose() << " " << sharpness;
        for (const auto* r : {&rec, &grazing}) {
          const auto s = vsgl_specular(in, *r);
          EXPECT_TRUE(std::isfinite(s.at_f0_zero) && s.at_f0_zero >= 0 && std::isfinite(s.at_f0_one) &&
                      s.at_f0_one >= 0)
              << variance << " " << mean.transpose() << " " << sharpness;
        }
      }
    }
  }
}

}  // namespace
}  // namespace sglab
