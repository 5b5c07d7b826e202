// The vectorized batch evaluators (core/src/simd, docs/simd.md) against the scalar templates they
// instantiate on SIMD lanes, on every instruction set this CPU runs (forced one at a time), in float and double,
// with the published constants and with other (bound) constants: over the stiff grid of
// docs/math.md §10 (with the extreme sharpnesses up to the type's largest value), the error grid of
// `sglab error-vs-time`, and seeded random points.
//
// Tolerance: |batch − scalar| ≤ k·ε·max(|D(λ, 1)|, |scalar|, Σ|terms|), ε the type's machine
// epsilon: k ulps of the value at c = 1 for the same λ (the normalization of every error in
// paper_tables/error_vs_time.md, so the allowance is in the "max rounding error" column's unit),
// or, for two forms that subtract larger terms by design (hill-fitted, meder), of the sum of the
// terms' magnitudes (the formula's own condition number; term_magnitude); tokuyoshi2022's
// designed ×2364 amplification is in its k. The two paths differ only in the transcendental functions (glibc libmvec's
// vector exp, expm1, erf, erfc against glibc's scalar ones; glibc states ≤ 4 ulp for libmvec, and
// the scalar ones are within 1–2) and in the Horner sum of the bound series below λ = 1: k = 4
// unless kToleranceUlps says otherwise, with the reason. Values below the smallest normal number are compared
// absolutely (xsimd does returns exp and erfc results below the smallest normal number as 0, a difference < 2·min
// normal). Also: no NaN, Inf or negative value where the scalar path has none (for the two methods published as going
// negative, meder and hill-fitted, a sign flip is accepted only where the scalar value is itself within the allowance
// of 0).
#include <cfloat>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sglab/clamped_cosine.hpp"
#include "sglab/exp_batch.hpp"
#include "sglab/hemispherical_meder.hpp"
#include "sglab/registry.hpp"
#include "sglab/simd.hpp"
#include "simd_test_util.hpp"
#include "test_util.hpp"

namespace {

using namespace sglab;

// k of the header, per "quantity/method", with the reason.
const test::UlpsTable kToleranceUlps{
    // Products of one exp/expm1 with exact arithmetic: the two libraries' ulps add.
    {"clamped-cosine/punctual", 4},
    {"clamped-cosine/punctual-approx", 4},
    {"clamped-cosine/sg-cosine", 4},
    {"clamped-cosine/cosine-lobe-sg", 4},
    // hill-fitted and meder return a difference of larger terms; they are measured against the
    // sum of the terms' magnitudes instead (their condition number; see term_magnitude). Each
    // meder term is itself a product of ~6 transcendental results: 8 ulps.
    {"clamped-cosine/hill-fitted", 4},
    {"clamped-cosine/meder", 8},
    // α(term1 − term0) with α ≈ 1182 and each term ≈ H(λ, ·) ≈ D(λ, 1)·2/α at small λ: 4 ulps of
    // each term are 8·1182 ≈ 4·2364 ulps of D(λ, 1) by design of λc (docs/math.md §3), and inside
    // each term the factor ½ + ½ erf(kc)/erf(k) cancels near c = −1 (measured: up to 656 ulps of
    // D(λ, 1) at λ = 10, c = −1; 1.1e4 at λ = 1e-3): 8·2364.
    {"clamped-cosine/tokuyoshi2022", 8 * 2364},
    // lerp(lower, upper, f) with f from two erfc, exp, expm1 (each ≤ 2 ulp apart), and the
    // Horner sum of the bounds: ≤ 4.
    {"clamped-cosine/tokuyoshi2024", 4},
    {"clamped-cosine/sglab", 4},
    {"hemispherical/meder", 4},
    {"hemispherical/tokuyoshi2022", 4},
    {"hemispherical/vmf-tokuyoshi2024", 4},
};

// For the forms that return a difference of larger terms, Σ|term| (in double, with the method's
// constants p as bound): the rounding of each term, not of the small difference, is what both
// paths carry. hill-fitted: (scale·y + bias)·2π/λ, with scale = 1 + 2e^{−2λ} − 1/λ and
// bias = (e^{−λ} − e^{−2λ})/λ − e^{−2λ}, each summand's magnitude; meder: a·H(product) + b·H.
// 0 for every other method (the value itself is the scale).
double term_magnitude(const std::string& name, const std::vector<double>& p, double l, double cosine) {
  const double c = std::clamp(cosine, -1.0, 1.0);
  if (name == "clamped-cosine/hill-fitted") {
    const double c0 = p[0], c1 = 1 / (4 * c0), eml = std::exp(-l), em2l = eml * eml, rl = 1 / l;
    const double x = std::sqrt(std::max(rl - 2 * em2l, 0.0)), x0 = c0 * c, x1 = c1 * x;
    const double y = std::fabs(x0) <= x1 ? (x0 + x1) * (x0 + x1) / x : std::clamp(c, 0.0, 1.0);
    return (y * (1 + 2 * em2l + rl) + (eml + em2l) * rl + em2l) * two_pi<double>() * rl;
  }
  if (name == "clamped-cosine/meder") {
    auto hemi = [&](double ll, double cc) { return hemispherical_meder(ll, cc, p[3], p[4], p[5], p[6]); };
    return p[0] * hemispherical_product(l, c, p[1], 0.0, hemi) + p[2] * hemi(l, c);
  }
  return 0;
}

struct Point {
  double l, c;
};

// The stiff grid (docs/math.md §10: λ = 0, 1e-8 … 1e8 and the extreme tail to DBL_MAX; cosines
// with the rounding steps around ±1), the error grid of `sglab error-vs-time` (λ ∈ [1e-3, 1e4],
// 4 per decade, × 41 cosines) and 4096 seeded random points (λ log-uniform, c uniform).
std::vector<Point> points() {
  std::vector<Point> out;
  std::vector<double> ls = test::stiff_sharpnesses(4);
  for (double l : stiff::extreme_sharpnesses()) ls.push_back(l);
  for (double l : ls)
    for (double c : test::stiff_cosines(32)) out.push_back({l, c});
  for (int i = 0; i <= 28; ++i)
    for (int j = 0; j <= 40; ++j) out.push_back({std::pow(10.0, -3 + i / 4.0), -1 + 2.0 * j / 40});
  auto rng = test::seeded_rng(20261201);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 4096; ++k) out.push_back({std::pow(10.0, -3 + 7 * u(rng)), -1 + 2 * u(rng)});
  return out;
}

struct Worst {
  double ulps = 0;
  Point at{};
  double scalar = 0, batch = 0;
};

template <class T>
void check(const std::string& name, const Method& m, const std::vector<double>& params, const std::vector<Point>& pts,
           double k, const std::string& label) {
  std::vector<T> args;
  std::vector<T> ref, peak;
  std::vector<Point> used;
  for (const auto& p : pts) {
    if (p.l > double(std::numeric_limits<T>::max())) continue;  // not a T
    const T a[2] = {T(p.l), T(p.c)};
    const double row[2] = {double(a[0]), double(a[1])};
    if (m.domain_error && m.domain_error(row)) continue;
    const T one[2] = {a[0], T(1)};
    args.insert(args.end(), {a[0], a[1]});
    used.push_back(p);
    if constexpr (std::is_same_v<T, float>) {
      ref.push_back(m.eval_float(a));
      peak.push_back(m.eval_float(one));
    } else {
      ref.push_back(m.eval_double(a));
      peak.push_back(m.eval_double(one));
    }
  }
  std::vector<T> out(ref.size());
  test::batch_as<T>(m, args, 2, out);
  const double eps = std::numeric_limits<T>::epsilon(), tiny = std::numeric_limits<T>::min();
  Worst w;
  int failures = 0;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    const double s = ref[i], v = out[i];
    const auto where = [&] {
      return ::testing::Message() << label << " at λ = " << used[i].l << ", c = " << used[i].c << ": scalar " << s
                                  << ", batch " << v;
    };
    if (std::isfinite(s) && !std::isfinite(v)) {
      if (++failures <= 5) ADD_FAILURE() << where() << " (new NaN/Inf)";
      continue;
    }
    if (!std::isfinite(s)) continue;  // the scalar path's own (none expected on these grids)
    const double scale = std::max({std::fabs(double(peak[i])), std::fabs(s),
                                   term_magnitude(name, params, double(args[2 * i]), double(args[2 * i + 1]))});
    // A method whose published form goes negative (meder, hill-fitted) returns a difference that
    // cancels to ~0: within its rounding allowance of 0 the sign is rounding, not a new negative.
    const bool signless = m.may_be_negative && s <= k * eps * scale;
    if (s >= 0 && v < 0 && !signless && ++failures <= 5) ADD_FAILURE() << where() << " (new negative value)";
    const double d = std::fabs(v - s);
    if (d < 2 * tiny) continue;  // subnormal results are returned as 0 (docs/simd.md)
    const double ulps = d / (eps * scale);
    if (ulps > w.ulps) w = {ulps, used[i], s, v};
    if (ulps > k && ++failures <= 5) ADD_FAILURE() << where() << ": " << ulps << " ulps of max(|D(λ, 1)|, |D|) > " << k;
  }
  std::printf("[ simd     ] %-40s %-7s %zu points, max %.3g ulps (tolerance %g) at λ = %g, c = %g\n", label.c_str(),
              sizeof(T) == 4 ? "float" : "double", ref.size(), w.ulps, k, w.at.l, w.at.c);
}

// Every vectorized method × every supported instruction set × float and double, published
// constants and a bound set (each constant × 1.1).
TEST(Simd, EveryKernelMatchesItsScalarTemplate) {
  const auto pts = points();
  const auto isas = simd::supported_isas();
  ASSERT_FALSE(isas.empty());
  for (const auto isa : isas) {
    simd::force_isa(isa);
    ASSERT_EQ(simd::active_isa(), isa);
    for (const auto& name : simd::vectorized_methods()) {
      const auto [q, m] = test::find_quantity_method(name);
      ASSERT_NE(m, nullptr);
      if (q->columns.size() != 2) continue;  // the specular kernels: tests/simd_specular_test.cpp
      const double k = test::ulps_for(kToleranceUlps, name);
      const std::string label = std::string(simd::isa_name(isa)) + " " + name;
      std::vector<double> published, values;
      for (const auto& p : m->parameters) {
        published.push_back(p.published);
        values.push_back(p.published * 1.1);
      }
      check<float>(name, *m, published, pts, k, label);
      check<double>(name, *m, published, pts, k, label);
      if (m->bind) {
        const Method b = m->bind(values);
        check<float>(name, b, values, pts, k, label + " [bound ×1.1]");
        check<double>(name, b, values, pts, k, label + " [bound ×1.1]");
      }
    }
  }
  simd::force_isa(isas.back());
}

// The batch evaluators handle every length (the partial last vector) and leave nothing else
// written: a row's value does not depend on its position in the batch.
// A diffuse kernel (rows of 2) and a specular one (rows of 6, core/src/simd/simd_specular.hpp).
TEST(Simd, PartialBatchesAndPositions) {
  const Method* diffuse = find_quantity("clamped-cosine")->find("tokuyoshi2024");
  const Method* specular = find_quantity("specular")->find("sg-warp-dvn");
  for (const auto isa : simd::supported_isas()) {
    simd::force_isa(isa);
    for (const Method* m : {diffuse, specular}) {
      const std::size_t arity = m == diffuse ? 2 : 6;
      for (std::size_t n : {1u, 3u, 7u, 15u, 17u, 33u}) {
        std::vector<double> args;
        for (std::size_t i = 0; i < n; ++i) {
          if (m == diffuse) args.insert(args.end(), {0.5 + double(i), 0.1});
          else args.insert(args.end(), {0.1 + 0.02 * double(i), 10.0, 0.6, 0.7, 3.0, 0.04});
        }
        std::vector<double> out(n + 1, -7.0);
        m->batch_double(args, arity, std::span<double>(out.data(), n));
        EXPECT_EQ(out[n], -7.0) << simd::isa_name(isa) << " wrote past the batch, n = " << n;
        std::vector<double> single(1);
        for (std::size_t i = 0; i < n; ++i) {
          m->batch_double(std::span<const double>(args.data() + arity * i, arity), arity, single);
          EXPECT_EQ(single[0], out[i]) << simd::isa_name(isa) << " " << m->name << " row " << i << " of " << n;
        }
      }
    }
  }
  simd::force_isa(simd::supported_isas().back());
}

// The column evaluators (Method::columns_float/double: the same kernels reading the rows as
// columns in place) give the batch evaluators' values bit for bit, for every vectorized method
// (and its bound version) on every instruction set, at every length of the partial last vector,
// a broadcast column among them; the scalar methods have none.
template <class T>
void check_columns_are_the_batch(const Quantity& q, const Method& m, std::size_t n, std::mt19937_64& rng) {
  const std::size_t k = q.columns.size();
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<T> rows(n * k), columns(n * k);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < k; ++j) {
      double v = u(rng);
      switch (q.columns[j].kind) {
        case ColumnKind::sharpness: v = std::pow(10.0, -3 + 7 * v); break;
        case ColumnKind::cosine: v = -1 + 2 * v; break;
        case ColumnKind::positive: v = std::pow(10.0, -2 * v); break;
        case ColumnKind::angle: v = 7 * v; break;
        default: break;
      }
      if (j == k - 1 && i > 0 && n % 2 == 1) v = double(rows[j]);  // the last column broadcast
      rows[i * k + j] = columns[j * n + i] = T(v);
    }
  std::vector<const T*> pointers;
  for (std::size_t j = 0; j < k; ++j) pointers.push_back(columns.data() + j * n);
  std::vector<T> batch(n), by_columns(n + 1, T(-7));
  if constexpr (std::is_same_v<T, float>) {
    m.batch_float(rows, k, batch);
    m.columns_float(pointers, std::span<T>(by_columns.data(), n));
  } else {
    m.batch_double(rows, k, batch);
    m.columns_double(pointers, std::span<T>(by_columns.data(), n));
  }
  EXPECT_EQ(by_columns[n], T(-7)) << "wrote past the batch, n = " << n;
  for (std::size_t i = 0; i < n; ++i)
    EXPECT_EQ(std::memcmp(&batch[i], &by_columns[i], sizeof(T)), 0)
        << "row " << i << " of " << n << ": " << batch[i] << " by rows, " << by_columns[i] << " by columns";
}

TEST(Simd, ColumnEvaluatorsAreTheBatchEvaluatorsBitForBit) {
  std::mt19937_64 rng(20261203);
  std::printf("[ simd     ] column evaluators: seed 20261203\n");
  for (const auto isa : simd::supported_isas()) {
    simd::force_isa(isa);
    for (const auto& q : quantities())
      for (const auto& m : q.methods) {
        const bool vectorized = m.batch_path == BatchPath::vectorized;
        EXPECT_EQ(bool(m.columns_float), vectorized) << q.name << "/" << m.name;
        EXPECT_EQ(bool(m.columns_double), vectorized) << q.name << "/" << m.name;
        if (!vectorized) continue;
        SCOPED_TRACE(q.name + "/" + m.name + " on " + std::string(simd::isa_name(isa)));
        std::vector<Method> variants{m};
        if (m.bind) {
          std::vector<double> published;
          for (const auto& p : m.parameters) published.push_back(p.published);
          variants.push_back(m.bind(published));
        }
        for (const Method& v : variants)
          for (std::size_t n : {1u, 2u, 3u, 5u, 8u, 15u, 16u, 17u, 31u, 33u, 1000u}) {
            check_columns_are_the_batch<float>(q, v, n, rng);
            check_columns_are_the_batch<double>(q, v, n, rng);
          }
      }
  }
  simd::force_isa(simd::supported_isas().back());
}

// The suite compares every instruction set this CPU runs, so it needs all of them built
// (SGLAB_SIMD_KERNELS=host or all; scripts/setup.sh --tests configures host). A build configured
// with `best` has only the widest, and the checks above and in the other simd tests would quietly
// cover one set. The CPU's sets are read here with the compiler's own test, not the library's.
TEST(Simd, TheSuiteHasEveryKernelSetThisCpuRuns) {
  __builtin_cpu_init();
  const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  const bool avx512 = avx2 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
                      __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
                      __builtin_cpu_supports("avx512vl");
  std::vector<simd::Isa> runs{simd::Isa::sse2};
  if (avx2) runs.push_back(simd::Isa::avx2);
  if (avx512) runs.push_back(simd::Isa::avx512);
  EXPECT_EQ(simd::supported_isas(), runs)
      << "this build lacks a kernel set this CPU runs: configure the test build with "
         "-DSGLAB_SIMD_KERNELS=host (scripts/setup.sh --tests does), not best";
}

TEST(Simd, IsaNamesAndForcing) {
  EXPECT_EQ(simd::parse_isa("avx2"), simd::Isa::avx2);
  EXPECT_FALSE(simd::parse_isa("avx3"));
  EXPECT_TRUE(simd::isa_supported(simd::Isa::sse2));
  for (const auto isa : {simd::Isa::sse2, simd::Isa::avx2, simd::Isa::avx512})
    if (!simd::isa_supported(isa)) {
      // Refused with the reason: the CPU, or a build without those kernels (SGLAB_SIMD_KERNELS=host).
      try {
        simd::force_isa(isa);
        ADD_FAILURE() << simd::isa_name(isa) << " was forced on a machine that cannot run it";
      } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        EXPECT_TRUE(what.find("this CPU cannot run it") != std::string::npos ||
                    what.find("SGLAB_SIMD_KERNELS") != std::string::npos)
            << what;
      }
    }
  std::printf("[ simd     ] this CPU runs, of this build's kernels:");
  for (const auto isa : simd::supported_isas()) std::printf(" %s", std::string(simd::isa_name(isa)).c_str());
  std::printf("\n");
}

// exp_batch is std::exp to the bit on every instruction set: its vectorized copy of glibc's exp
// (simd_exp.hpp) on avx2 and avx512, the scalar loop on sse2. Points: uniform over [−760, 720]
// (overflow, subnormal results, the underflow to 0), over [−40, 1], random bit patterns (every
// exponent field, NaN and ±inf among them) and |x| from 2^-60 to 2^9 (the fast path's lower end),
// at every offset and length up to 17 (the partial vectors' scalar tail).
TEST(Simd, ExpBatchIsStdExpToTheBit) {
  auto rng = test::seeded_rng(20261205);
  std::uniform_real_distribution<double> wide(-760, 720), fits(-40, 1), unit(-1, 1);
  std::vector<double> x(1 << 18);
  for (std::size_t i = 0; i < x.size(); ++i) {
    switch (i % 4) {
      case 0: x[i] = wide(rng); break;
      case 1: x[i] = fits(rng); break;
      case 2: {
        const std::uint64_t b = rng();
        std::memcpy(&x[i], &b, sizeof b);
        break;
      }
      default: x[i] = std::ldexp(unit(rng), int(rng() % 70) - 60); break;
    }
  }
  const auto same = [](double a, double b) {
    return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b));
  };
  for (const auto isa : simd::supported_isas()) {
    simd::force_isa(isa);
    // glibc's FMA exp is what the copy reproduces; on sse2 exp_batch is the loop of std::exp.
    EXPECT_EQ(exp_batch_vectorized(), isa != simd::Isa::sse2) << simd::isa_name(isa);
    std::vector<double> out(x.size());
    exp_batch(x.data(), out.data(), x.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
      if (!same(out[i], std::exp(x[i])) && ++differ <= 5)
        ADD_FAILURE() << simd::isa_name(isa) << ": exp(" << x[i] << ") = " << out[i] << ", std::exp " << std::exp(x[i]);
    EXPECT_EQ(differ, 0u) << simd::isa_name(isa);
    for (std::size_t offset = 0; offset < 8; ++offset)
      for (std::size_t n = 0; n <= 17; ++n) {
        std::vector<double> part(n + 1, -1.0);
        exp_batch(x.data() + offset, part.data(), n);
        for (std::size_t i = 0; i < n; ++i) EXPECT_TRUE(same(part[i], std::exp(x[offset + i])));
        EXPECT_EQ(part[n], -1.0) << "written past n = " << n;
      }
    // In place.
    std::vector<double> y(x.begin(), x.begin() + 1000);
    exp_batch(y.data(), y.data(), y.size());
    for (std::size_t i = 0; i < y.size(); ++i) EXPECT_TRUE(same(y[i], std::exp(x[i])));
  }
  simd::force_isa(simd::supported_isas().back());
}

}  // namespace
