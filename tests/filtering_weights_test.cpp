// Lobe-aware filtering weights (core/include/sglab/filtering_weights.hpp) against the direct
// numerical integration of the similarity of the normalized lobes
// (core/include/sglab/filtering_reference.hpp).
//
// Tolerances, per scalar type:
//  • exact closed forms (Gaussian similarity of App. A, the diffuse q of App. D, the Tsai–Shih SG
//    similarity) against quadrature: double ≤ 1e-13 relative (the quadrature is ≤ 1e-15 on its
//    own, the closed forms lose a few ulps); mp50 against mp50 quadrature ≤ 1e-40; float against
//    the double quadrature ≤ 3e-6 (a few float ulps times the forms' condition);
//  • the paper's approximations (G(λ_c) for q, the Iwasaki form of Eq. (12), λ̄ = λκ/(λ + κ)):
//    bounds measured once over wide random samples and stated below with ≈ 30 % margin; they
//    are properties of the published formulas (the numbers paper_tables/filtering.md quotes), and a
//    wrong exponent, factor or sharpness misses them by far;
//  • identities (optimized = direct, diffuse lobe weight = normal weight): a few ulps × the size
//    of the exponent, per type.
#include <cmath>
#include <limits>
#include <random>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/quadrature/tanh_sinh.hpp>
#include <ceres/jet.h>

#include "sglab/filtering_reference.hpp"
#include "sglab/filtering_weights.hpp"
#include "sglab/reference.hpp"
#include "test_util.hpp"
#include "sglab/reference_mp50.hpp"

namespace sglab {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
const double kLambdaC = LobeAwareFiltering::lambda_c;

ZonalLobe<double> cosine_lobe() { return {ZonalLobeShape::clamped_cosine, 0.0}; }
ZonalLobe<double> sg_lobe(double sharpness) { return {ZonalLobeShape::sg, sharpness}; }

double log_uniform(std::mt19937_64& rng, double lo, double hi) {
  std::uniform_real_distribution<double> u(std::log10(lo), std::log10(hi));
  return std::pow(10.0, u(rng));
}

// ---- the reference itself -----------------------------------------------------------------------

TEST(FilteringReference, SmoothedRingIntegralMatchesAzimuthalQuadratureOfTheSmoothedProfile) {
  // The κ-smoothed lobes of the reference come from exchanging the order of integration (the
  // kernel's ring integral in closed form, then one integral over θ'). Check that step against
  // the definition: the ring integral ∫_0^{2π} c(cos θ cos φ + sin θ sin φ cos ϕ) dϕ of the
  // smoothed profile c, by Gauss–Kronrod over ϕ, with c independent of this header: for an SG,
  // the exact Tsai–Shih convolution c(t) = ∫G(ω'; ξ, λ)K(ω'·ω)dω' = e^{L}A(λ3)/A(κ) (sg.hpp);
  // for the clamped cosine, c(t) = D(κ, t)/A(κ) with the diffuse reference of reference.hpp.
  auto check = [](const ZonalLobe<double>& f, double kappa, double theta, double phi, const auto& profile, double tol) {
    const double ring = smoothed_ring_integral(f, theta, phi, kappa);
    auto g = [&](double az) {
      return profile(std::cos(theta) * std::cos(phi) + std::sin(theta) * std::sin(phi) * std::cos(az));
    };
    const double direct = 2 * boost::math::quadrature::gauss_kronrod<double, 61>::integrate(g, 0.0, pi<double>(), 12,
                                                                                            1e-13);
    EXPECT_LE(test::relative_error(ring, direct), tol) << "kappa=" << kappa << " theta=" << theta << " phi=" << phi;
  };
  for (double kappa : {3.0, 100.0}) {
    for (double lambda : {0.5, 40.0}) {
      auto sg_profile = [&](double t) { return product_integral_exact(lambda, kappa, t) / sg_integral(kappa); };
      for (const auto& [theta, phi] : {std::pair{0.0, 0.0}, std::pair{0.4, 0.3}, std::pair{1.2, 0.2}}) {
        check(sg_lobe(lambda), kappa, theta, phi, sg_profile, 1e-12);
      }
    }
    auto cos_profile = [&](double t) { return clamped_cosine_reference(kappa, t) / sg_integral(kappa); };
    for (const auto& [theta, phi] : {std::pair{0.0, 0.0}, std::pair{1.4, 0.5}, std::pair{2.0, 2.5}}) {
      check(cosine_lobe(), kappa, theta, phi, cos_profile, 1e-11);
    }
  }
}

// ---- App. A: Gaussian lobes in ℝ^m -----------------------------------------------------------

TEST(GaussianLobeWeight, SimilarityMatchesQuadratureOfSmoothedLobes) {
  // m = 1, 2, 3 with per-coordinate offsets: the reference is the product of 1D similarities
  // (Fubini), each a nested quadrature of the smoothing convolution and the inner product.
  auto rng = test::seeded_rng(701);
  std::uniform_real_distribution<double> offset(-3, 3);
  for (int n = 0; n < 6; ++n) {
    const int m = 1 + n % 3;
    const double ti = log_uniform(rng, 0.05, 5), tj = log_uniform(rng, 0.05, 5);
    const double nu = n % 4 == 0 ? 0.0 : log_uniform(rng, 0.01, 2);
    double d2 = 0, reference = 1;
    for (int k = 0; k < m; ++k) {
      const double dx = offset(rng);
      d2 += dx * dx;
      reference *= gaussian_similarity_reference_1d(dx, ti, tj, nu);
    }
    const double bi = smoothed_variance(ti, nu), bj = smoothed_variance(tj, nu);
    SCOPED_TRACE(testing::Message() << "m=" << m << " d2=" << d2 << " tau_i^2=" << ti << " tau_j^2=" << tj
                                    << " nu^2=" << nu);
    EXPECT_LE(test::relative_error(gaussian_lobe_similarity(d2, bi, bj, m), reference), 1e-13);
    for (double beta : {1.0, 4.0, 20.0}) {
      EXPECT_LE(test::relative_error(gaussian_lobe_weight(d2, bi, bj, beta, m), std::pow(reference, beta)),
                1e-13 * beta);
    }
    const float qf = gaussian_lobe_similarity(float(d2), float(bi), float(bj), m);
    EXPECT_LE(test::relative_error(qf, reference), 3e-6 * (1 + d2 / (bi + bj)));
  }
}

TEST(GaussianLobeWeight, EqualVariancesGiveTheGaussianWeightOfAppendixA) {
  // App. A: τ_i = τ_j = τ ⇒ w = g(x_i − x_j, 2τ²/β + 2ν²/β), against quadrature in 1D.
  auto rng = test::seeded_rng(702);
  for (int n = 0; n < 6; ++n) {
    const double tau = log_uniform(rng, 0.05, 5), nu = log_uniform(rng, 0.01, 2);
    const double d = std::uniform_real_distribution<double>(0, 3)(rng);
    const double beta = log_uniform(rng, 0.5, 50);
    const double reference = std::pow(gaussian_similarity_reference_1d(d, tau, tau, nu), beta);
    EXPECT_LE(test::relative_error(gaussian_lobe_weight_equal_variance(d * d, tau, nu, beta), reference), 1e-12 * beta)
        << "tau^2=" << tau << " nu^2=" << nu << " d=" << d << " beta=" << beta;
  }
}

// The unsmoothed 1D similarity ∫g_ig_j/√(∫g_i² ∫g_j²) (g_i = g(x, τ_i²), g_j = g(x − d, τ_j²)) by the
// trapezoid rule on x = kh over [−20, 20], for the 50-digit check below. For a Gaussian integrand
// over ℝ the rule's error is ≈ 2e^{−2π²σ²/h²} of the integral (σ² the integrand's variance, here
// ≥ τ_i²/2 = 0.15: below 1e-120 at h = 0.1), and the integrands are below 1e-80 of their peaks at
// ±20. Measured once: equal to h = 0.05 to 2e-50, and to the nested Gauss–Kronrod/tanh–sinh
// reference of filtering_reference.hpp (gaussian_similarity_reference_1d, ≈ 1.5 CPU s in 50
// digits) to 3e-51.
mp50 gaussian_similarity_trapezoid(const mp50& d, const mp50& ti, const mp50& tj, const mp50& h) {
  mp50 ij = 0, ii = 0, jj = 0;
  for (mp50 x = -20; x <= 20; x += h) {
    const mp50 gi = exp(-x * x / (2 * ti)), gj = exp(-(x - d) * (x - d) / (2 * tj));
    ij += gi * gj;
    ii += gi * gi;
    jj += gj * gj;
  }
  return ij / sqrt(ii * jj);
}

TEST(GaussianLobeWeight, Mp50ClosedFormMatchesMp50Quadrature) {
  // Unsmoothed (ν = 0), against the trapezoid rule above.
  for (const auto& [d, ti, tj] : {std::tuple{"0.7", "0.3", "1.9"}}) {
    const mp50 reference = gaussian_similarity_trapezoid(mp50(d), mp50(ti), mp50(tj), mp50("0.1"));
    const mp50 q = gaussian_lobe_similarity(mp50(d) * mp50(d), mp50(ti), mp50(tj), 1);
    EXPECT_LT(abs(q / reference - 1), mp50("1e-40")) << d << " " << ti << " " << tj;
  }
}

// ---- App. D: diffuse lobes ---------------------------------------------------------------------

TEST(DiffuseLobeSimilarity, ClosedFormMatchesQuadrature) {
  // q(φ) = (sin φ + (π − φ) cos φ)/π against ∫⟨n_i·ω⟩⟨n_j·ω⟩ / ∫⟨n·ω⟩² by quadrature, over the
  // stiff cosines (±1 exactly, rounding steps past ±1) and near-antipodal normals (q ~ ψ³).
  std::vector<double> cosines = test::stiff_cosines(24);
  for (double e : {1e-2, 1e-4, 1e-6, 1e-8}) cosines.push_back(-1 + e);
  for (double c : cosines) {
    const double reference = lobe_similarity_reference(cosine_lobe(), cosine_lobe(), c, kInf);
    const double q = diffuse_lobe_similarity(c);
    EXPECT_GE(q, 0.0) << c;
    EXPECT_LE(q, 1.0) << c;
    // Relative where q is representable well above the quadrature's absolute floor (1e-17).
    EXPECT_LE(std::fabs(q - reference), 1e-13 * reference + 1e-17) << c;
    const float qf = diffuse_lobe_similarity(float(c));
    EXPECT_LE(std::fabs(qf - reference), 3e-6 * reference + 1e-9) << c;
  }
}

TEST(DiffuseLobeSimilarity, Mp50ClosedFormMatchesMp50Quadrature) {
  const ZonalLobe<mp50> cosine{ZonalLobeShape::clamped_cosine, mp50(0)};
  for (const char* c : {"0.3", "-0.999"}) {
    const mp50 reference = lobe_similarity_reference(cosine, cosine, mp50(c),
                                                     mp50(std::numeric_limits<double>::infinity()));
    EXPECT_LT(abs(diffuse_lobe_similarity(mp50(c)) / reference - 1), mp50("1e-40")) << c;
  }
}

TEST(DiffuseLobeSimilarity, SgApproximationErrorIsThePapersFit) {
  // q ≈ G(n_i; n_j, λ_c) with λ_c = 0.9426 (App. D). Measured max |G − q| over φ ∈ [0, π]: 0.1574
  // at φ ≈ 2.64 (G keeps a tail of e^{−2λ_c} = 0.15 at antipodal normals where q = 0); with
  // β = 20, max |G^β − q^β| = 0.0067 (at φ ≈ 0.22). Bounds 0.16 and 0.009, against quadrature.
  double max_q = 0, max_w = 0;
  for (int i = 0; i <= 40; ++i) {
    const double phi = pi<double>() * i / 40, c = std::cos(phi);
    const double reference = lobe_similarity_reference(cosine_lobe(), cosine_lobe(), c, kInf);
    max_q = std::max(max_q, std::fabs(diffuse_lobe_similarity_sg(c, kLambdaC, kInf) - reference));
    max_w = std::max(max_w, std::fabs(diffuse_lobe_weight(c, kLambdaC, 20.0, kInf) - std::pow(reference, 20.0)));
  }
  std::printf("[ measured ] max |G(lambda_c) - q| = %.4g, beta = 20: %.4g\n", max_q, max_w);
  EXPECT_LE(max_q, 0.16);
  EXPECT_GT(max_q, 0.15);  // the tail is the approximation's, not a quadrature artefact
  EXPECT_LE(max_w, 0.009);
}

TEST(DiffuseLobeSimilarity, KernelSharpnessExtensionAgainstSmoothedLobes) {
  // q ≈ G(n_i; n_j, λ_cκ/(2λ_c + κ)) (App. D) against the similarity of the two clamped cosines
  // each convolved with the vMF kernel of sharpness κ, by quadrature. Measured (κ ∈ {10, 100,
  // 1000}, c ∈ [−0.9, 0.99]): |Δq| ≤ 0.159 (at c = −0.9, the tail as above), and for β = 20,
  // |Δw| ≤ 0.031 at κ = 10, ≤ 0.0041 at κ ≥ 100. κ = 1 is outside the paper's use: |Δw| = 0.35.
  for (double kappa : {10.0, 100.0}) {
    for (double c : {0.99, 0.9, 0.5, -0.9}) {
      const double reference = lobe_similarity_reference(cosine_lobe(), cosine_lobe(), c, kappa, 1e-9);
      const double q = diffuse_lobe_similarity_sg(c, kLambdaC, kappa);
      EXPECT_LE(std::fabs(q - reference), 0.17) << kappa << " " << c;
      const double dw = std::fabs(std::pow(q, 20.0) - std::pow(reference, 20.0));
      EXPECT_LE(dw, kappa >= 100 ? 0.0055 : 0.04) << kappa << " " << c;
    }
  }
}

TEST(DiffuseLobeWeight, ReducesToTheNormalWeightWithThePapersSigmaN2) {
  // The lobe-aware weight of a diffuse surface, q^β with q ≈ G(λ_cκ/(2λ_c + κ)), is the
  // normal-aware weight G(n_i; n_j, 1/σ_n²) with σ_n² = (2λ_c + κ)/(βλ_cκ) (App. D).
  EXPECT_NEAR(normal_weight_variance(kLambdaC, LobeAwareFiltering::beta, LobeAwareFiltering::kappa),
              LobeAwareFiltering::sigma_n2, 5e-9);  // published to 8 significant digits
  auto rng = test::seeded_rng(703);
  for (int n = 0; n < 200; ++n) {
    const double beta = log_uniform(rng, 0.1, 1e3), kappa = log_uniform(rng, 0.1, 1e5);
    const double c = std::uniform_real_distribution<double>(-1, 1)(rng);
    const double s2 = normal_weight_variance(kLambdaC, beta, kappa);
    const double w = diffuse_lobe_weight(c, kLambdaC, beta, kappa);
    // Same exponent computed two ways: a few ulps of |exponent| relative.
    const double exponent = (1 - c) / s2;
    EXPECT_LE(test::relative_error(w, normal_weight(c, s2)), 8e-16 * (1 + exponent))
        << beta << " " << kappa << " " << c;
  }
  // The same through the SG-lobe weight of Eq. (12)/App. E: a diffuse lobe as the SG of
  // sharpness 2λ_c on both pixels gives λ̄_iλ̄_j/(λ̄_i + λ̄_j) = λ_cκ/(2λ_c + κ) and mismatch 1.
  for (double kappa : {1.0, 100.0, kInf}) {
    for (double c : {1.0, 0.9, 0.2, -1.0}) {
      const double lbar = smoothed_lobe_sharpness(2 * kLambdaC, kappa);
      const double s2 = normal_weight_variance(kLambdaC, 20.0, kappa);
      EXPECT_LE(test::relative_error(sg_lobe_weight(c, lbar, lbar, 20.0), normal_weight(c, s2)),
                1e-14 * (1 + (1 - c) / s2))
          << kappa << " " << c;
    }
  }
  // And against quadrature: the exact smoothed diffuse similarity^β vs the normal weight at the
  // published σ_n² (β = 20, κ = 100): the App. D approximation's error in weight terms (measured
  // ≤ 0.0041, see the previous test).
  for (double c : {0.995, 0.95, 0.8}) {
    const double reference = lobe_similarity_reference(cosine_lobe(), cosine_lobe(), c, 100.0, 1e-9);
    EXPECT_NEAR(normal_weight(c, LobeAwareFiltering::sigma_n2), std::pow(reference, 20.0), 0.0055) << c;
  }
}

TEST(NormalWeight, VectorFormIsAccurateForNearlyEqualNormals) {
  // exp(−‖Δn‖²/(2σ²)) vs exp((c − 1)/σ²): for normals 1e-6 apart, c − 1 from the rounded dot
  // product has lost ~10 digits; the vector form keeps them. Reference: 50 digits.
  const double s2 = 1e-12;  // a sharp weight, so that the exponent is O(1)
  for (double angle : {1e-7, 1e-6, 3e-6}) {
    const Vec3<double> a(0, 0, 1), b(std::sin(angle), 0, std::cos(angle));
    const Vec3<mp50> am(0, 0, 1), bm(sin(mp50(angle)), 0, cos(mp50(angle)));
    const mp50 exact = exp(-(am - bm).squaredNorm() / (2 * mp50(s2)));
    EXPECT_LE(test::relative_error(normal_weight(a, b, s2), double(exact)), 1e-14) << angle;
  }
}

// ---- SG lobes: exact similarity, Eq. (12), App. E ----------------------------------------------

TEST(SgLobeSimilarity, ExactFormMatchesQuadrature) {
  // The Tsai–Shih similarity e^{L}A(λ3)/√(A(2λ_i)A(2λ_j)) against the quadrature of the
  // normalized SGs, λ from 1e-3 to 1e5, axes from equal to opposite.
  auto rng = test::seeded_rng(704);
  std::uniform_real_distribution<double> u(0, 1);
  for (int n = 0; n < 40; ++n) {
    const double li = log_uniform(rng, 1e-3, 1e5), lj = log_uniform(rng, 1e-3, 1e5);
    // Half the cosines near 1 (where similarities of sharp lobes are not negligible).
    const double c = n % 2 ? 1 - log_uniform(rng, 1e-8, 1) : 2 * u(rng) - 1;
    const double reference = lobe_similarity_reference(sg_lobe(li), sg_lobe(lj), c, kInf);
    const double q = sg_lobe_similarity_exact(c, li, lj);
    SCOPED_TRACE(testing::Message() << "li=" << li << " lj=" << lj << " c=" << c);
    if (reference > 1e-250) {
      EXPECT_LE(test::relative_error(q, reference), 1e-12);
    } else {
      EXPECT_LE(q, 1e-240);
    }
    // Float: against the quadrature at the float-rounded inputs (rounding c to float alone moves
    // q by λ·6e-8 relative near c = 1: input rounding, not the formula's).
    const float cf = float(c), lif = float(li), ljf = float(lj);
    const double reference_f = lobe_similarity_reference(sg_lobe(lif), sg_lobe(ljf), double(cf), kInf);
    const float qf = sg_lobe_similarity_exact(cf, lif, ljf);
    if (reference_f > 1e-30) {
      EXPECT_LE(test::relative_error(qf, reference_f), 3e-6);
    }
  }
}

TEST(SgLobeSimilarity, Mp50ExactFormMatchesMp50Quadrature) {
  // Opposite axes (the intermediate cosines are covered in double above): the normalization
  // A(2λ), the product sharpness λ3 = |λ_i − λ_j| and the log-amplitude L = −2 min(λ_i, λ_j), to
  // 40 digits. With ξ_j = −ξ_i every integral is over t = ω·ξ_i alone: ∫G_iG_j dω =
  // 2π∫_{−1}^{1} e^{λ_i(t − 1)}e^{−λ_j(t + 1)} dt, ∫G_i² dω = 2π∫_{−1}^{1} e^{2λ_i(t − 1)} dt, each by
  // tanh–sinh in 50 digits. Measured once: equal to lobe_similarity_reference (the zonal nested
  // quadrature of filtering_reference.hpp, ≈ 2.7 CPU s in 50 digits) to 7e-49.
  boost::math::quadrature::tanh_sinh<mp50> ts;
  auto integral = [&](const mp50& a, const mp50& b) {  // ∫_{−1}^{1} e^{a(t − 1) − b(t + 1)} dt
    return ts.integrate([&](const mp50& t) { return exp(a * (t - 1) - b * (t + 1)); }, mp50(-1), mp50(1),
                        mp50("1e-45"));
  };
  for (const auto& [li, lj] : {std::pair{"200", "50"}}) {
    const mp50 l_i(li), l_j(lj);
    const mp50 reference = integral(l_i, l_j) / sqrt(integral(2 * l_i, 0) * integral(2 * l_j, 0));
    const mp50 q = sg_lobe_similarity_exact(mp50(-1), l_i, l_j);
    EXPECT_LT(abs(q / reference - 1), mp50("1e-40")) << li << " " << lj;
  }
}

TEST(SgLobeSimilarity, Eq12ApproximationConvergesAsOneOverSharpness) {
  // Eq. (12) with β = 1 (the Iwasaki product integral, Eq. C.1) against the quadrature of the
  // exact similarity. Measured over 2·10^5 random pairs per decade of the smaller sharpness λ_min
  // (cosines uniform and near 1): max |Δq| = 0.116/λ_min (λ_min ≥ 10), 0.103/λ_min (≥ 100),
  // 0.105/λ_min (≥ 1000); β = 20: max |Δw| = 0.17/λ_min. Bounds 0.15/λ_min and 0.23/λ_min.
  auto rng = test::seeded_rng(705);
  for (int n = 0; n < 30; ++n) {
    const double li = log_uniform(rng, 10, 1e5), lj = log_uniform(rng, 10, 1e5);
    const double lmin = std::min(li, lj);
    const double c = std::cos(std::uniform_real_distribution<double>(0, 3)(rng) / std::sqrt(lmin));
    const double reference = lobe_similarity_reference(sg_lobe(li), sg_lobe(lj), c, kInf);
    SCOPED_TRACE(testing::Message() << "li=" << li << " lj=" << lj << " c=" << c);
    EXPECT_LE(std::fabs(sg_lobe_similarity(c, li, lj) - reference), 0.15 / lmin);
    EXPECT_LE(std::fabs(sg_lobe_weight(c, li, lj, 20.0) - std::pow(reference, 20.0)), 0.23 / lmin);
  }
}

TEST(SgLobeWeight, SmoothedLobesAgainstQuadratureOfConvolvedLobes) {
  // The whole chain of the paper: smoothing by Eq. (9)/(C.1), λ̄ = λκ/(λ + κ), then Eq. (12),
  // against the similarity of the two SGs each convolved with the vMF kernel of sharpness κ, by
  // quadrature. Measured over 40 random cases (κ ∈ [10, 1000], λ ∈ [10, 10^4]): |Δq| ≤ 0.11/λ̄_min.
  // Bound 0.15/λ̄_min.
  auto rng = test::seeded_rng(706);
  for (int n = 0; n < 3; ++n) {
    const double kappa = log_uniform(rng, 10, 1000);
    const double li = log_uniform(rng, 10, 1e4), lj = log_uniform(rng, 10, 1e4);
    const double bi = smoothed_lobe_sharpness(li, kappa), bj = smoothed_lobe_sharpness(lj, kappa);
    const double bmin = std::min(bi, bj);
    const double c = std::cos(std::uniform_real_distribution<double>(0, 2)(rng) / std::sqrt(bmin));
    const double reference = lobe_similarity_reference(sg_lobe(li), sg_lobe(lj), c, kappa, 1e-9);
    SCOPED_TRACE(testing::Message() << "kappa=" << kappa << " li=" << li << " lj=" << lj << " c=" << c);
    EXPECT_LE(std::fabs(sg_lobe_similarity(c, bi, bj) - reference), 0.15 / bmin);
    // The vector form (what a filter calls) is the same weight.
    const Vec3<double> a(0, 0, 1), b(std::sqrt((1 - c) * (1 + c)), 0, c);
    EXPECT_LE(test::relative_error(lobe_aware_weight(a, li, b, lj, 1.0, kappa), sg_lobe_similarity(c, bi, bj)),
              1e-13 * (1 + (1 - c) * bmin));
  }
}

TEST(SgLobeWeight, PaperBetaAgainstQuadratureOfConvolvedLobes) {
  // The weight a filter uses, at the paper's β = 20 and κ = 100 (App. D, Fig. D.2), against the
  // similarity of the two SGs each convolved with the vMF kernel of sharpness κ, by quadrature,
  // raised to β. Directions are chosen where the weight is mid-range (≈ 0.5), so a wrong exponent
  // shows (β applied twice gives ≈ 0.5^20 ≈ 1e-6; β = 1 gives ≈ 0.97; β = 21 moves w by 0.02).
  // The error is the Iwasaki approximation of Eq. (12) raised to β: measured |Δw| ≤ 0.17/λ̄_min
  // (0.0028 at λ̄_min = 60); bound 0.25/λ̄_min.
  const double beta = LobeAwareFiltering::beta, kappa = LobeAwareFiltering::kappa;
  const std::pair<double, double> sharpnesses[] = {{200, 1000}, {150, 150}};
  for (const auto& [li, lj] : sharpnesses) {
    const double bi = smoothed_lobe_sharpness(li, kappa), bj = smoothed_lobe_sharpness(lj, kappa);
    const double bmin = std::min(bi, bj), reduced = bi * bj / (bi + bj);
    // β·reduced·(1 − c) = ln 2: half the weight from the directions alone.
    const double c = 1 - std::log(2.0) / (beta * reduced);
    const double q = lobe_similarity_reference(sg_lobe(li), sg_lobe(lj), c, kappa, 1e-9);
    const double reference = std::pow(q, beta);
    const Vec3<double> a(0, 0, 1), b(std::sqrt((1 - c) * (1 + c)), 0, c);
    const double w = lobe_aware_weight(a, li, b, lj, beta, kappa);
    std::printf("λi %g λj %g: w %.6f, q^β by quadrature %.6f\n", li, lj, w, reference);
    EXPECT_GT(reference, 0.2);
    EXPECT_LT(reference, 0.8);
    EXPECT_LE(std::fabs(w - reference), 0.25 / bmin) << "λi " << li << " λj " << lj;
  }
}

TEST(SgLobeWeight, OptimizedFormEqualsDirectForm) {
  // App. E's exp(β/2·log(4u/v²) + βu/v(c − 1)) equals Eq. (12)'s
  // (2√u/v)^β G(ξ_i; ξ_j, βu/v). Both round independently: the direct form's pow raises the
  // few-ulp error of 2√u/v to the power β, and both exponentials carry the rounding of their
  // argument |log w|, so the bound is ε(8 + 4β + 2|log w|) per type (ε = 2.2e-16, 1.2e-7, 1e-50).
  auto rng = test::seeded_rng(707);
  std::uniform_real_distribution<double> u(0, 1);
  for (int n = 0; n < 2000; ++n) {
    const double li = log_uniform(rng, 1e-3, 1e6), lj = log_uniform(rng, 1e-3, 1e6);
    const double beta = log_uniform(rng, 0.1, 100);
    const double c = n % 2 ? 1 - log_uniform(rng, 1e-10, 2) : 2 * u(rng) - 1;
    const double direct = sg_lobe_weight_direct(c, li, lj, beta);
    const double optimized = sg_lobe_weight(c, li, lj, beta);
    const double log_w = -std::log(std::max(direct, 1e-300));
    SCOPED_TRACE(testing::Message() << "li=" << li << " lj=" << lj << " beta=" << beta << " c=" << c);
    if (direct > 1e-280) {
      EXPECT_LE(test::relative_error(optimized, direct), 2.3e-16 * (8 + 4 * beta + 2 * log_w));
      const float of = sg_lobe_weight(float(c), float(li), float(lj), float(beta));
      const float df = sg_lobe_weight_direct(float(c), float(li), float(lj), float(beta));
      if (log_w < 60) {
        EXPECT_LE(test::relative_error(of, df), 1.2e-7 * (8 + 4 * beta + 2 * log_w));
      }
    } else {
      EXPECT_LE(optimized, 1e-270);
    }
  }
  for (const auto& [li, lj, c, beta] :
       {std::tuple{"0.7", "300", "0.99", "20"}, std::tuple{"1e5", "2e4", "0.99999", "50"}}) {
    const mp50 direct = sg_lobe_weight_direct(mp50(c), mp50(li), mp50(lj), mp50(beta));
    const mp50 optimized = sg_lobe_weight(mp50(c), mp50(li), mp50(lj), mp50(beta));
    EXPECT_LT(abs(optimized / direct - 1), mp50("1e-45")) << li << " " << lj;
  }
}

TEST(SgLobeWeight, JetDerivativesMatchMp50Differences) {
  // d w/d c and d w/d λ̄_i of App. E's form by autodiff against central differences of the
  // 50-digit evaluation (step 1e-20: truncation ~1e-40).
  using J = ceres::Jet<double, 2>;
  for (const auto& [li, lj, c, beta] : {std::tuple{3.0, 40.0, 0.97, 20.0}, std::tuple{500.0, 80.0, 0.999, 5.0}}) {
    const J w = sg_lobe_weight(J(c, 0), J(li, 1), J(lj), J(beta));
    const mp50 h("1e-20");
    auto f = [&](const mp50& cc, const mp50& l) { return sg_lobe_weight(cc, l, mp50(lj), mp50(beta)); };
    const double dc = double((f(mp50(c) + h, mp50(li)) - f(mp50(c) - h, mp50(li))) / (2 * h));
    const double dl = double((f(mp50(c), mp50(li) + h) - f(mp50(c), mp50(li) - h)) / (2 * h));
    EXPECT_DOUBLE_EQ(w.a, sg_lobe_weight(c, li, lj, beta));
    EXPECT_LE(test::relative_error(w.v[0], dc), 1e-12) << li << " " << lj;
    EXPECT_LE(test::relative_error(w.v[1], dl), 1e-12) << li << " " << lj;
  }
}

// ---- identical lobes, stiff ends -----------------------------------------------------------------

template <class T>
void expect_identical_lobes_have_similarity_one() {
  const T inf = T(std::numeric_limits<double>::infinity());
  for (double l : test::stiff_sharpnesses(1)) {
    const T lam = T(l);
    EXPECT_EQ(sg_lobe_similarity(T(1), lam, lam), T(1)) << l;
    EXPECT_EQ(sg_lobe_weight(T(1), lam, lam, T(1e6)), T(1)) << l;
    // Eq. (12) as written: 2√λ√λ/(2λ) is 1 only up to rounding (then clamped to ≤ 1).
    EXPECT_LE(sg_lobe_weight_direct(T(1), lam, lam, T(20)), T(1)) << l;
    EXPECT_GE(sg_lobe_weight_direct(T(1), lam, lam, T(20)), T(1) - T(80 * epsilon<T>())) << l;
    // Exact form: a few roundings of the same numbers; clamped so it never exceeds 1.
    const T qe = sg_lobe_similarity_exact(T(1), lam, lam);
    EXPECT_LE(qe, T(1)) << l;
    EXPECT_GE(qe, T(1) - T(8 * epsilon<T>())) << l;
    const Vec3<T> axis(T(0.6), T(0), T(0.8));
    EXPECT_EQ(lobe_aware_weight(axis, lam, axis, lam, T(20), T(100)), T(1)) << l;
    EXPECT_EQ(lobe_aware_weight(axis, lam, axis, lam, T(20), inf), T(1)) << l;
    if (l > 0) {
      EXPECT_EQ(gaussian_lobe_similarity(T(0), lam, lam, 3), T(1)) << l;
      EXPECT_EQ(gaussian_lobe_weight(T(0), lam, lam, T(1e6), 2), T(1)) << l;
    }
  }
  EXPECT_EQ(diffuse_lobe_similarity(T(1)), T(1));
  EXPECT_EQ(diffuse_lobe_similarity_sg(T(1), T(kLambdaC), T(100)), T(1));
  EXPECT_EQ(normal_weight(T(1), T(0.05)), T(1));
  EXPECT_EQ(normal_weight(T(1), T(0)), T(1));
}

TEST(LobeSimilarity, IdenticalLobesHaveSimilarityOne) {
  expect_identical_lobes_have_similarity_one<float>();
  expect_identical_lobes_have_similarity_one<double>();
  expect_identical_lobes_have_similarity_one<mp50>();
  // And the quadrature agrees with itself through a different path: q(ξ, ξ) for identical lobes
  // given as two separately described lobes at cosine 1 (incl. κ smoothing).
  EXPECT_NEAR(lobe_similarity_reference(sg_lobe(37.0), sg_lobe(37.0), 1.0, 50.0), 1.0, 1e-12);
  EXPECT_NEAR(lobe_similarity_reference(cosine_lobe(), cosine_lobe(), 1.0, kInf), 1.0, 1e-14);
}

template <class T>
void expect_stiff_ends_finite_in_unit_interval() {
  const T inf = T(std::numeric_limits<double>::infinity());
  auto ok = [](const T& w) { return is_finite_value(w) && value_of(w) >= 0 && value_of(w) <= 1; };
  std::vector<double> sharpnesses = test::stiff_sharpnesses(1);
  if constexpr (!std::is_same_v<T, float>) sharpnesses.push_back(1e30);
  for (double li : sharpnesses) {
    for (double lj : {0.0, 1e-8, 1.0, 1e8}) {
      for (double c : test::stiff_cosines(4)) {
        for (double beta : {0.0, 1.0, 20.0, 1e6}) {
          SCOPED_TRACE(testing::Message() << "li=" << li << " lj=" << lj << " c=" << c << " beta=" << beta);
          EXPECT_TRUE(ok(sg_lobe_weight(T(c), T(li), T(lj), T(beta))));
          EXPECT_TRUE(ok(sg_lobe_weight_direct(T(c), T(li), T(lj), T(beta))));
          EXPECT_TRUE(ok(diffuse_lobe_weight(T(c), T(kLambdaC), T(beta), T(lj))));
          if (value_of(T(beta)) > 0) {
            EXPECT_TRUE(ok(normal_weight(T(c), T(normal_weight_variance(T(kLambdaC), T(beta), T(lj))))));
          }
          if (li > 0 && lj > 0) {
            EXPECT_TRUE(ok(gaussian_lobe_weight(T(c * c), T(li), T(lj), T(beta), 3)));
          }
        }
        EXPECT_TRUE(ok(sg_lobe_similarity(T(c), T(li), T(lj))));
        EXPECT_TRUE(ok(sg_lobe_similarity_exact(T(c), T(li), T(lj))));
        EXPECT_TRUE(ok(diffuse_lobe_similarity(T(c))));
      }
      // Antipodal axes, vector form, every κ including none and 0.
      const Vec3<T> a(T(0), T(0), T(1)), b(T(0), T(0), T(-1));
      for (double kappa : {0.0, 1.0, 100.0, 1e8, kInf}) {
        EXPECT_TRUE(ok(lobe_aware_weight(a, T(li), b, T(lj), T(20), T(kappa)))) << li << " " << lj;
      }
      EXPECT_TRUE(ok(lobe_aware_weight(a, T(li), b, T(lj), T(20), inf)));
    }
  }
  // Antipodal normals: q = 0 exactly; the SG approximation keeps its tail e^{−2λ_c}.
  EXPECT_EQ(diffuse_lobe_similarity(T(-1)), T(0));
}

TEST(LobeSimilarity, StiffEndsAreFiniteAndInUnitInterval) {
  expect_stiff_ends_finite_in_unit_interval<float>();
  expect_stiff_ends_finite_in_unit_interval<double>();
  expect_stiff_ends_finite_in_unit_interval<ceres::Jet<double, 2>>();
}

TEST(LobeSimilarity, StiffEndsMp50) {
  // A smaller grid in 50 digits (the same code path; mp50 is slow).
  for (double l : {0.0, 1e-8, 1e8, 1e30}) {
    for (const char* c : {"-1", "1", "0.5"}) {
      const mp50 w = sg_lobe_weight(mp50(c), mp50(l), mp50(1e8), mp50(1e6));
      EXPECT_TRUE(w >= 0 && w <= 1 && boost::multiprecision::isfinite(w)) << l << " " << c;
      const mp50 q = sg_lobe_similarity_exact(mp50(c), mp50(l), mp50(3));
      EXPECT_TRUE(q >= 0 && q <= 1 && boost::multiprecision::isfinite(q)) << l << " " << c;
    }
  }
}

}  // namespace
}  // namespace sglab
