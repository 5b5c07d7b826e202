// tests for core/include/sglab/glossy_reference.hpp: convergence against a finer rule,
// agreement with seeded importance-sampled Monte Carlo (≥ 1e6 samples) within 4 standard errors,
// the θ nodes integrate_sphere keeps across meridians against Boost's rule, to the bit, and the
// rule's nodes evaluated at once (on vector registers) against Boost's rule and the integrand
// node by node, to the bit.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "sglab/glossy_reference.hpp"
#include "sglab/simd.hpp"
#include "test_util.hpp"

namespace sglab {
namespace {

const double kPi = M_PI;

// A rule's integrand of θ nodes (ThetaNodes::rule takes all of a rule's nodes at once) from an
// integrand of one node.
template <class G>
auto node_by_node(const G& g) {
  return [&g](const detail::ThetaNode* t, double* out, std::size_t n) {
    for (std::size_t k = 0; k < n; ++k) out[k] = g(t[k]);
  };
}
const SpecularConfig kConfigs[] = {
    {1.0, 1.0, 0.5, 0.5, kPi, 0.04},      // broad both
    {0.3, 100.0, 0.5, 0.5, kPi, 0.04},    // light at the mirror direction
    {0.01, 1e4, 0.5, 0.5, 3.0, 0.04},     // sharp both, separated
    {0.01, 100.0, 0.9, 0.2, 1.0, 0.04},   // sharp BRDF, far light
    {0.05, 1000.0, -0.1, 0.3, kPi, 0.9},  // light just behind the surface
    {0.2, 50.0, 0.05, 0.02, 3.0, 0.04},   // grazing view and light
    {0.1, 1e4, 0.3, 0.05, kPi, 0.04},     // grazing view, sharp light
};

TEST(GlossyReference, ConvergesAgainstAFinerRule) {
  SphereQuadrature fine;
  fine.tolerance = 1e-8;
  fine.ratio = 1.5;
  fine.max_depth = 12;
  for (const auto& c : kConfigs) {
    const double r = specular_reference(c), rf = specular_reference(c, fine);
    std::printf("alpha=%g lambda=%g lc=%g v=%g phi=%g: ref %.12e fine %.12e rel %.2e\n", c.roughness, c.light_sharpness,
                c.light_cos, c.view_cos, c.light_azimuth, r, rf, r / rf - 1);
    EXPECT_NEAR(r / rf, 1.0, 1e-8);
  }
  // The sharpest case the specular sweep uses: α = 0.01, λ = 1e4, light on the mirror direction.
  const SpecularConfig sharp{0.01, 1e4, 0.5, 0.5, kPi, 0.04};
  EXPECT_NEAR(specular_reference(sharp) / specular_reference(sharp, fine), 1.0, 1e-8);
}

TEST(GlossyReference, AgreesWithMonteCarlo) {
  const std::uint64_t seed = 20261122;
  const std::uint64_t n = 1000000;
  std::printf("Monte Carlo seed %llu, %llu samples per configuration\n", (unsigned long long)seed,
              (unsigned long long)n);
  for (const auto& c : kConfigs) {
    const double r = specular_reference(c);
    const auto mc = specular_monte_carlo(c, n, seed);
    const double z = (mc.mean - r) / mc.standard_error;
    std::printf("alpha=%g lambda=%g: ref %.10e  MC %.10e ± %.2e (rel se %.1e, %+.2f se)\n", c.roughness,
                c.light_sharpness, r, mc.mean, mc.standard_error, mc.standard_error / mc.mean, z);
    EXPECT_LT(std::abs(z), 4.0);
    EXPECT_LT(mc.standard_error / mc.mean, 0.05);  // the estimator is informative (light behind: 2%)
  }
}

// integrate_sphere keeps each θ panel's nodes for the next meridian (detail::ThetaNodes). A rule
// through the store must be Boost's rule on the integrand computed from θ, to the bit, whether its
// nodes are computed or kept, and a panel seen before must not compute its nodes again.
TEST(GlossyReference, KeptThetaNodesGiveTheRuleOfTheIntegrandToTheBit) {
  using boost::math::quadrature::gauss_kronrod;
  const double lambda = 37.5;
  const auto pole = [lambda](double one_minus_cos) { return std::exp(-lambda * one_minus_cos); };
  // The integrand from a node, and the same from θ alone (the independent form).
  const auto from_node = [](const detail::ThetaNode& t) {
    return t.pole_factor * (1.5 + t.cos) * t.sin + 0.25 * t.sin_half;
  };
  const auto from_theta = [&](double theta) {
    const double h = std::sin(0.5 * theta);
    return pole(2 * h * h) * (1.5 + std::cos(theta)) * std::sin(theta) + 0.25 * h;
  };
  const auto without_pole = [](double theta) {
    return (1.5 + std::cos(theta)) * std::sin(theta) + 0.25 * std::sin(0.5 * theta);
  };
  const std::uint64_t seed = 20261205;
  std::printf("seed %llu\n", (unsigned long long)seed);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, kPi);
  std::vector<std::pair<double, double>> panels;
  for (int i = 0; i < 40; ++i) {
    const double a = u(rng), b = u(rng);
    panels.emplace_back(std::min(a, b), std::max(a, b));
  }
  detail::ThetaNodes<decltype(pole)> nodes(pole);
  detail::ThetaNodes<std::nullptr_t> plain(nullptr);
  for (int round = 0; round < 3; ++round) {
    for (const auto& [a, b] : panels) {
      double err = 0, err_ref = 0, err_plain = 0, err_plain_ref = 0;
      const double kept = nodes.rule(node_by_node(from_node), a, b, &err);
      const double ref = gauss_kronrod<double, 15>::integrate(from_theta, a, b, 0, 0.0, &err_ref);
      EXPECT_EQ(std::bit_cast<std::uint64_t>(kept), std::bit_cast<std::uint64_t>(ref))
          << "round " << round << " [" << a << ", " << b << "]: " << kept << " vs " << ref;
      EXPECT_EQ(std::bit_cast<std::uint64_t>(err), std::bit_cast<std::uint64_t>(err_ref));
      // Without a pole factor the node's is 1.
      const auto plain_node = [](const detail::ThetaNode& t) {
        return t.pole_factor * ((1.5 + t.cos) * t.sin + 0.25 * t.sin_half);
      };
      const double p = plain.rule(node_by_node(plain_node), a, b, &err_plain);
      const double p_ref = gauss_kronrod<double, 15>::integrate(without_pole, a, b, 0, 0.0, &err_plain_ref);
      EXPECT_EQ(std::bit_cast<std::uint64_t>(p), std::bit_cast<std::uint64_t>(p_ref)) << "round " << round;
    }
    // Every panel's 15 nodes were computed in the first round and only then.
    EXPECT_EQ(nodes.computed(), 15 * panels.size()) << "round " << round;
    EXPECT_EQ(plain.computed(), 15 * panels.size()) << "round " << round;
  }
  // Half of a panel is a panel of its own (the adaptive rule's bisection): its nodes are new.
  const auto [a, b] = panels.front();
  const double m = 0.5 * (a + b);
  double err = 0, err_ref = 0;
  const double half = nodes.rule(node_by_node(from_node), a, m, &err);
  const double half_ref = gauss_kronrod<double, 15>::integrate(from_theta, a, m, 0, 0.0, &err_ref);
  EXPECT_EQ(std::bit_cast<std::uint64_t>(half), std::bit_cast<std::uint64_t>(half_ref));
  EXPECT_EQ(nodes.computed(), 15 * panels.size() + 15);
}

// The store is bounded (detail::kMaxThetaPanels): past the bound new panels are computed and not
// kept, with the same values, and the panels kept before the bound still are.
TEST(GlossyReference, ThetaNodesPastTheBoundAreComputedNotKept) {
  using boost::math::quadrature::gauss_kronrod;
  const auto from_node = [](const detail::ThetaNode& t) { return t.cos * t.sin + t.sin_half; };
  const auto from_theta = [](double theta) { return std::cos(theta) * std::sin(theta) + std::sin(0.5 * theta); };
  detail::ThetaNodes<std::nullptr_t> nodes(nullptr);
  const std::size_t n = detail::kMaxThetaPanels + 10;
  const auto panel = [&](std::size_t i) { return std::pair{double(i) / double(n), double(i + 1) / double(n)}; };
  // The first round every panel; the second a sample of them and the last 20, past the bound.
  std::vector<std::size_t> second;
  for (std::size_t i = 0; i < n; i += 997) second.push_back(i);
  for (std::size_t i = n - 20; i < n; ++i) second.push_back(i);
  std::vector<std::size_t> first(n);
  for (std::size_t i = 0; i < n; ++i) first[i] = i;
  for (const auto* round : {&first, &second}) {
    for (const std::size_t i : *round) {
      const auto [a, b] = panel(i);
      double err = 0, err_ref = 0;
      const double v = nodes.rule(node_by_node(from_node), a, b, &err);
      const double ref = gauss_kronrod<double, 15>::integrate(from_theta, a, b, 0, 0.0, &err_ref);
      ASSERT_EQ(std::bit_cast<std::uint64_t>(v), std::bit_cast<std::uint64_t>(ref)) << "panel " << i;
    }
    if (round == &first) {
      EXPECT_EQ(nodes.computed(), 15 * n);
    }
  }
  // Of the second round's panels, those past the bound were computed again.
  std::size_t past = 0;
  for (const std::size_t i : second) past += i >= detail::kMaxThetaPanels ? 1 : 0;
  EXPECT_EQ(past, 10u);
  EXPECT_EQ(nodes.computed(), 15 * (n + past));
}

// detail::gauss_kronrod_at_once is Boost's gauss_kronrod<double, 15>::integrate(f, a, b, 0, 0, err)
// with the nodes handed over at once: the same nodes in the same order, value and error estimate to
// the bit, on smooth, kinked, peaked, oscillating and zero integrands and on intervals from 1e-12
// wide to [−π, π]; an empty interval gives 0 and leaves the error as it was, a reversed one the
// negated rule of the ordered one (Boost's own cases); an infinite or NaN end is refused.
TEST(GlossyReference, RuleWithItsNodesAtOnceIsBoostsToTheBit) {
  using boost::math::quadrature::gauss_kronrod;
  const std::vector<std::function<double(double)>> integrands = {
      [](double x) { return std::cos(x) * std::sin(3 * x) + 0.5; },
      [](double x) { return std::abs(x - 0.3); },
      [](double x) { return std::exp(-1e4 * (x - 0.1) * (x - 0.1)); },
      [](double x) { return std::sqrt(std::abs(x)) * std::sin(40 * x); },
      [](double) { return 0.0; },
  };
  auto rng = test::seeded_rng(20261205);
  std::uniform_real_distribution<double> u(-kPi, kPi), width(-12, 0.5);
  int compared = 0;
  for (const auto& f : integrands) {
    const auto at_once = [&](const double* x, double* fx) {
      for (unsigned k = 0; k < detail::kSphereRulePoints; ++k) fx[k] = f(x[k]);
    };
    for (int i = 0; i < 300; ++i) {
      const double a = i == 0 ? -kPi : u(rng), b = i == 0 ? kPi : a + std::pow(10.0, width(rng));
      double err = -1, err_boost = -2;
      const double v = detail::gauss_kronrod_at_once(at_once, a, b, &err);
      const double v_boost = gauss_kronrod<double, 15>::integrate(f, a, b, 0, 0.0, &err_boost);
      ASSERT_EQ(std::bit_cast<std::uint64_t>(v), std::bit_cast<std::uint64_t>(v_boost)) << "[" << a << ", " << b << "]";
      ASSERT_EQ(std::bit_cast<std::uint64_t>(err), std::bit_cast<std::uint64_t>(err_boost))
          << "[" << a << ", " << b << "]";
      double rev = -1, rev_boost = -2;
      const double r = detail::gauss_kronrod_at_once(at_once, b, a, &rev);
      const double r_boost = gauss_kronrod<double, 15>::integrate(f, b, a, 0, 0.0, &rev_boost);
      ASSERT_EQ(std::bit_cast<std::uint64_t>(r), std::bit_cast<std::uint64_t>(r_boost));
      ASSERT_EQ(std::bit_cast<std::uint64_t>(rev), std::bit_cast<std::uint64_t>(rev_boost));
      ++compared;
    }
    double err = -1, err_boost = -1;
    EXPECT_EQ(detail::gauss_kronrod_at_once(at_once, 0.25, 0.25, &err), 0.0);
    const double empty_boost = gauss_kronrod<double, 15>::integrate(f, 0.25, 0.25, 0, 0.0, &err_boost);
    EXPECT_EQ(empty_boost, 0.0);
    EXPECT_EQ(err, -1.0);
    EXPECT_EQ(err_boost, -1.0);
  }
  // An infinite end (Boost maps it onto a finite interval; this rule does not) is refused.
  const auto zero = [](const double*, double* fx) { std::fill(fx, fx + detail::kSphereRulePoints, 0.0); };
  EXPECT_THROW(detail::gauss_kronrod_at_once(zero, 0.0, INFINITY, nullptr), std::domain_error);
  EXPECT_THROW(detail::gauss_kronrod_at_once(zero, NAN, 1.0, nullptr), std::domain_error);
  std::printf("compared %d rules and their reversals\n", compared);
}

// ggx_brdf_cosine_points is ggx_brdf_cosine at each direction, to the bit, on every instruction set
// and at every count (whole registers and a padded last one): seeded directions over the whole
// sphere and the horizon (ω_z = 0 and −0, where the value is 0), ω = −ωo at a grazing view (the half
// vector's degenerate case), roughness from 1e-3 to 1, views from normal to grazing and below.
TEST(GlossyReference, GgxPointsAreTheTemplateToTheBit) {
  auto rng = test::seeded_rng(20261206);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> u(0, 1);
  const simd::Isa initial = simd::active_isa();
  std::size_t compared = 0;
  for (const auto isa : simd::supported_isas()) {
    simd::force_isa(isa);
    for (const double view_cos : {1.0, 0.7, 0.05, 0.0, -0.2}) {
      const Vec3d wo(std::sqrt(std::max(0.0, 1 - view_cos * view_cos)), 0, view_cos);
      for (std::size_t n : {1u, 7u, 8u, 15u, 16u, 17u, 100u}) {
        const double alpha = std::pow(10.0, -3 * u(rng)), f0 = u(rng);
        std::vector<double> x(n), y(n), z(n), out(n);
        for (std::size_t k = 0; k < n; ++k) {
          Vec3d w = Vec3d(normal(rng), normal(rng), normal(rng)).normalized();
          if (k % 5 == 1) w(2) = k % 2 ? 0.0 : -0.0;
          if (k % 7 == 3) w = -wo;
          x[k] = w(0), y[k] = w(1), z[k] = w(2);
        }
        ggx_brdf_cosine_points(alpha, f0, wo, x.data(), y.data(), z.data(), out.data(), n);
        for (std::size_t k = 0; k < n; ++k) {
          const double want = ggx_brdf_cosine(alpha, f0, wo, Vec3d(x[k], y[k], z[k]));
          ASSERT_EQ(std::bit_cast<std::uint64_t>(out[k]), std::bit_cast<std::uint64_t>(want))
              << simd::isa_name(isa) << " n " << n << " point " << k << ": " << out[k] << " vs " << want;
          ++compared;
        }
      }
    }
  }
  simd::force_isa(initial);
  std::printf("compared %zu values\n", compared);
}

// specular_reference evaluates each rule's nodes at once (GgxCosine::points); it is the reference
// computed one node at a time (the same h without `points`), to the bit, on every instruction set:
// the configurations above and seeded ones over roughness 0.01–1, sharpness 0–1e4 and every angle.
TEST(GlossyReference, SpecularReferenceAtOnceIsNodeByNode) {
  auto rng = test::seeded_rng(20261207);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<SpecularConfig> configs(std::begin(kConfigs), std::end(kConfigs));
  for (int i = 0; i < 6; ++i)
    configs.push_back({std::pow(10.0, -2 * u(rng)), u(rng) < 0.2 ? 0.0 : std::pow(10.0, 4 * u(rng)), 2 * u(rng) - 1,
                       u(rng), kPi * (2 * u(rng) - 1), u(rng)});
  const simd::Isa initial = simd::active_isa();
  for (const auto isa : simd::supported_isas()) {
    simd::force_isa(isa);
    for (const SpecularConfig& c : configs) {
      const GgxCosine g{c.roughness, c.f0, specular_view(c.view_cos)};
      const auto one_at_a_time = [&g](const Vec3d& w) { return g(w); };
      const double at_once = specular_reference(c);
      const double node_by_node = specular_reference_of(c, one_at_a_time, SphereQuadrature{});
      ASSERT_EQ(std::bit_cast<std::uint64_t>(at_once), std::bit_cast<std::uint64_t>(node_by_node))
          << simd::isa_name(isa) << " α " << c.roughness << " λ " << c.light_sharpness << ": " << at_once << " vs "
          << node_by_node;
    }
  }
  simd::force_isa(initial);
}

TEST(GlossyReference, StiffCasesFiniteNonNegative) {
  for (const SpecularConfig& c : {SpecularConfig{0.01, 1e4, -0.5, 0.5, 0.0, 0.04},  // light behind: underflows to 0
                                  SpecularConfig{0.01, 0.0, 0.0, 0.0, 0.0, 0.04},   // grazing view, uniform light
                                  SpecularConfig{1.0, 0.0, 1.0, 1.0, 0.0, 1.0}}) {
    const double r = specular_reference(c);
    EXPECT_TRUE(std::isfinite(r) && r >= 0) << r;
  }
}

}  // namespace
}  // namespace sglab
