// A method's scalar template as its own vectorized batch evaluator (core/src/simd/simd_lanes.hpp,
// docs/simd.md): a toy method written once, as every formula in core/include/sglab is (lane-wise
// math called unqualified, every branch on a value a select, a series summed to ε), gets its batch
// evaluator from the kernel driver the registry's kernels use, with no kernel code of its own.
// Compiled at the x86-64 baseline (SSE2: every CPU runs it); the registry's kernels are the same
// templates compiled once per instruction set (tests/simd_test.cpp checks those against the scalar
// path on every instruction set this CPU runs).
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <gtest/gtest.h>

// The unit's instruction set, named as the sse2 units name it.
#include "simd/simd_isa_sse2.hpp"
#include "simd/simd_libmvec.hpp"
#include "simd/simd_kernels.hpp"

namespace sglab {
namespace {

// The toy method: p·(e^{−λ}·√(1 + λ)·⟨c⟩ + (1 − e^{−λ})/λ + Σ_{n≥1} u^{n−1}/(n+1)!), u = −λc² where
// λc² < 1 (0 elsewhere), the series summed until its term no longer changes the sum.
template <class T>
T toy(const T& sharpness, const T& cosine, const T& p) {
  using std::exp;
  using std::sqrt;
  const T c = clamp_cosine(cosine);
  const T& l = sharpness;
  const T ramp = select(
      value_of(c) > 0, [&]() -> T { return c; }, []() -> T { return T(0); });
  const T lc2 = l * c * c;
  const T u = select(
      value_of(lc2) < 1, [&]() -> T { return -lc2; }, []() -> T { return T(0); });
  T term = T(0.5), series = term;
  for (int n = 2; n < 400; ++n) {
    term *= u / T(n + 1);
    series += term;
    if (series_converged(term, series, n)) break;
  }
  return p * (exp(-l) * sqrt(T(1) + l) * ramp + expm1_over_x(T(-l)) + series);
}

// Its whole vectorized path: one kernel-table entry's worth (simd_kernels.hpp FromTemplate).
struct ToyKernel : simd_detail::FromTemplate<ToyKernel> {
  static constexpr int kParams = 1;
  template <class T>
  static T formula(const T& l, const T& c, const T* p) {
    return toy(l, c, p[0]);
  }
};

template <class T>
void expect_batch_is_the_template(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<T> args;
  for (double l : {0.0, 1e-6, 0.5, 1.0, 30.0, 1e4})
    for (double c : {-1.0, -0.3, 0.0, 0.2, 1.0}) args.insert(args.end(), {T(l), T(c)});
  for (int i = 0; i < 997; ++i) args.insert(args.end(), {T(std::pow(10.0, -4 + 8 * u(rng))), T(-1 + 2 * u(rng))});
  const std::size_t n = args.size() / 2;  // not a multiple of the lanes: the driver pads the last batch
  const T params[simd_detail::kKernelParams] = {T(1.5)};
  std::vector<T> out(n);
  simd_detail::run<xsimd::sse2, T, ToyKernel>(args.data(), out.data(), n, params);
  double worst = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const T ref = toy(args[2 * i], args[2 * i + 1], params[0]);
    // libmvec's exp and expm1 (≤ 4 ulp stated) against libm's, a few terms of the result.
    const double ulps = std::fabs(double(out[i]) - double(ref)) /
                        (std::numeric_limits<T>::epsilon() * std::max(1.0, std::fabs(double(ref))));
    worst = std::max(worst, ulps);
    EXPECT_LE(ulps, 8) << "seed " << seed << " λ " << args[2 * i] << " c " << args[2 * i + 1] << ": " << out[i]
                       << " vs " << ref;
  }
  std::printf("toy method, %s: largest |batch − scalar| %.2f ulps (seed %llu)\n", sizeof(T) == 4 ? "float" : "double",
              worst, static_cast<unsigned long long>(seed));
}

TEST(SimdLanes, AToyTemplateIsItsOwnBatchEvaluator) {
  expect_batch_is_the_template<float>(20261203);
  expect_batch_is_the_template<double>(20261203);
}

// select on lanes runs a side only when some lane takes it, and joins lane by lane when they differ.
TEST(SimdLanes, SelectRunsTheSidesTheLanesTake) {
  using L = simd_lanes::Lanes<xsimd::batch<double, xsimd::sse2>>;
  int true_runs = 0, false_runs = 0;
  const auto pick = [&](const L& x) {
    return select(
        value_of(x) > 0, [&]() -> L { return ++true_runs, L(1); }, [&]() -> L { return ++false_runs, L(-1); });
  };
  const auto two = [](double a, double b) {
    alignas(16) const double v[2] = {a, b};
    return L(xsimd::batch<double, xsimd::sse2>::load_aligned(v));
  };
  alignas(16) double lanes[2];
  pick(two(2.0, 3.0)).v.store_aligned(lanes);
  EXPECT_EQ(true_runs, 1);
  EXPECT_EQ(false_runs, 0);
  EXPECT_EQ(lanes[0], 1.0);
  pick(two(2.0, -3.0)).v.store_aligned(lanes);
  EXPECT_EQ(true_runs, 2);
  EXPECT_EQ(false_runs, 1);
  EXPECT_EQ(lanes[0], 1.0);
  EXPECT_EQ(lanes[1], -1.0);
}

}  // namespace
}  // namespace sglab
