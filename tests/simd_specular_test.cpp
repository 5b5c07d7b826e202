// The vectorized batch evaluators of the specular methods (core/src/simd/simd_specular.hpp,
// docs/simd.md) against the scalar templates they transcribe (specular.hpp, gaussian_ndf.hpp), on
// every instruction set this CPU runs (forced one at a time), in float and double: over a stiff
// grid (roughness 1e-3 … 1 and the 1e-8 floor, light sharpness 0 … 1e8 and FLT_MAX/DBL_MAX,
// the light at, below and past the horizon, grazing and normal view, azimuths around the mirror
// direction, f0 = 0.04 and 1) and seeded random points spread like the error grid (roughness and
// λ log-uniform over [1e-3, 1] and [1e-3, 1e4], the cosines and azimuth uniform).
//
// Tolerance: |batch − scalar| ≤ k·ε·max(|scalar|, |peak|, Σ|terms|) + 2·S, ε the type's machine
// epsilon.
// - k ulps of the point's peak: the value for the same surface, view and light sharpness with the
//   light on the mirror direction (light_cos = view_cos, azimuth π), as the diffuse kernels are
//   held to k ulps of the value at c = 1 (tests/simd_test.cpp). In a lobe's tail the value is a
//   small remainder of quantities of the peak's size (the half vector of nearly opposite ωo and
//   ξ_m at grazing view, e^{L} of a subnormal L scaled back up by 1/(n·ωo)²), so ulps of the
//   value itself mean nothing there; what a renderer sums is the error relative to the peak.
//   The two paths run the same operations in the same order and differ in the libraries'
//   transcendental results (libmvec exp, expm1, sin, cos against glibc's scalar ones: ≤ 4 ulp
//   stated, 1–2 measured), in the contraction of a·b + c into one fused multiply-add where the
//   compiler chose it (AVX2, AVX-512 units), and in the subnormal results returned as 0.
//   Σ|terms| for sg-warp-meder: its cosine is 32.7·G − 31.7, a difference of larger terms, whose
//   own rounding is what both paths carry (term_magnitude below, computed in double).
// - S, the condition of the point: the largest change of the scalar value when one input moves
//   by 4 ulps (relative; the angle absolute 4ε·max(1, |φ|)), and twice the scalar path's own
//   error (against the same template in the next precision: double for float, mp50 for double;
//   computed only where the difference exceeds the rest of the allowance: mp50 is slow). The products exp(λ3 − λ1 − λ2)
//   have the condition number |L| (up to ~700 before underflow), and the lobe sharpness reaches 1e13 at α = 1e-3 at
//   grazing view: one ulp in the lobe's cosine (a 3-term dot product rounded twice by either path) moves the value by
//   λ_s·ε relative. No fixed ulp count can hold there; the scalar template's own sensitivity to its inputs' last bits
//   is the yardstick for the rounding of the intermediates that carry them.
// Also: no NaN, Inf or negative value where the scalar path has none (sg-warp-meder, published as
// going negative, may flip sign only within the allowance of 0). Results below the smallest
// normal number compare absolutely (libmvec's subnormal lanes are returned as 0, docs/simd.md).
#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <cstdint>
#include <map>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sglab/clamped_cosine.hpp"
#include "sglab/clamped_cosine_meder.hpp"
#include "sglab/gaussian_ndf.hpp"
#include "sglab/registry.hpp"
#include "sglab/simd.hpp"
#include "sglab/simd_specular_pair.hpp"
#include "sglab/specular_input.hpp"
#include "simd_test_util.hpp"
#include "test_util.hpp"
#include "sglab/registry_mp50.hpp"

namespace {

using namespace sglab;
using Row = std::array<double, 6>;  // roughness, light_sharpness, light_cos, view_cos, light_azimuth, f0

// k per method, with the reason (see the header).
const test::UlpsTable kToleranceUlps{
    // The exact product (one exp, one expm1), the warp and M (sqrt, divisions, Schlick's
    // fifth power) and sin/cos: 4 ulps for the libraries plus the short rational chain
    // (measured: ≤ 3.8 ulps in float, ≤ 5.7 in double).
    {"specular/sg-warp", 8},
    {"specular/sg-warp-product-axis", 8},
    {"specular/sg-warp-iwasaki", 8},
    {"specular/sg-warp-th2019", 8},
    {"specular/asg", 8},
    // The dominant visible normal, its reflection and the normalized product: two more norms.
    {"specular/sg-warp-dvn", 8},
    // sglab: one log1p and two exp (libmvec, 4 ulps each) feeding a product, and the
    // exponent's terms (the t power and the light ratio, each up to ~80 in magnitude), whose
    // rounding the exp turns into a relative error of that size in ulps (measured at λ ≥ 1e4 with
    // grazing view: ≤ 60 ulps in float, ≤ 66 in double with AVX2/AVX-512; the SSE2 double rows
    // up to 156 are within the allowance through their condition term): 96.
    {"specular/sglab", 96},
    {"specular-gaussian-ndf/sg-warp", 8},
    // Meder's cosine: two hemispherical integrals of ~6 transcendental results each, measured
    // against the sum of their magnitudes (measured: ≤ 14 ulps).
    {"specular-gaussian-ndf/sg-warp-meder", 16},
};

// Σ|terms| of sg-warp-meder: F/(π co²)·e^{L}·(a·H(product) + b·H(λ3, c3)) (gaussian_ndf.hpp), in
// double with the published Meder constants. 0 for every other method.
double term_magnitude(const std::string& name, const Row& r) {
  if (name != "specular-gaussian-ndf/sg-warp-meder") return 0;
  const SpecularInput<double> in{r[0], r[1], r[2], r[3], r[4], r[5]};
  return std::fabs(detail::specular_gaussian_ndf_with_cosine(in, [](double l, double c) {
    auto hemi = [](double ll, double cc) { return hemispherical_meder(ll, cc); };
    return MederCosineSg::amplitude * hemispherical_product(l, c, MederCosineSg::sharpness, 0.0, hemi) +
           MederCosineSg::offset * hemi(l, c);
  }));
}

std::vector<Row> stiff_rows() {
  std::vector<Row> out;
  const double pi = two_pi<double>() / 2;
  for (double a : {1e-8, 1e-3, 1e-2, 0.1, 0.3, 1.0})
    for (double l : {0.0, 1e-3, 0.1, 1.0, 10.0, 1e3, 1e4, 1e8, double(FLT_MAX), DBL_MAX})
      for (double lc : {-1.0, -0.5, -1e-8, 0.0, 1e-8, 0.3, 0.8, 1.0, stiff::float_after_one()})
        for (double v : {0.0, 1e-8, 1e-3, 0.5, 1.0})
          for (double phi : {0.0, pi / 2, pi, 3.0})
            for (double f0 : {0.04, 1.0}) out.push_back({a, l, lc, v, phi, f0});
  return out;
}

std::vector<Row> random_rows() {
  std::vector<Row> out;
  auto rng = test::seeded_rng(20261202);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 4096; ++k)
    out.push_back({std::pow(10.0, -3 * u(rng)), std::pow(10.0, -3 + 7 * u(rng)), -1 + 2 * u(rng), u(rng),
                   two_pi<double>() * u(rng), u(rng)});
  return out;
}

template <class T>
T eval(const Method& m, const std::array<T, 6>& a) {
  return eval_as<T>(m, std::span<const T>(a.data(), 6));
}

// The scalar values, their condition S and scale (see the header), for the rows T can represent.
template <class T>
struct Reference {
  std::vector<T> args;
  std::vector<Row> rows;
  std::vector<double> value, condition, scale;
};
template <class T>
Reference<T> reference(const std::string& name, const Method& m, const std::vector<Row>& rows) {
  Reference<T> ref;
  const double eps = std::numeric_limits<T>::epsilon();
  for (const Row& r : rows) {
    if (r[1] > double(std::numeric_limits<T>::max())) continue;
    std::array<T, 6> a;
    for (int j = 0; j < 6; ++j) a[j] = T(r[j]);
    const double s = eval(m, a);
    double cond = 0;
    for (int j = 0; j < 6; ++j)
      for (double sign : {-1.0, 1.0}) {
        std::array<T, 6> b = a;
        const double step = j == 4 ? 4 * eps * std::max(1.0, std::fabs(r[j])) : 4 * eps * std::fabs(double(a[j]));
        b[j] = T(double(a[j]) + sign * step);
        const double sb = eval(m, b);
        if (std::isfinite(sb)) cond = std::max(cond, std::fabs(sb - s));
      }
    ref.args.insert(ref.args.end(), a.begin(), a.end());
    ref.rows.push_back(r);
    ref.value.push_back(s);
    ref.condition.push_back(cond);
    // The point's peak: the same surface, view and light with the light on the mirror direction.
    std::array<T, 6> mirror = a;
    mirror[2] = a[3];
    mirror[4] = T(two_pi<double>() / 2);
    const double peak = eval(m, mirror);
    ref.scale.push_back(std::max({std::fabs(s), term_magnitude(name, r), std::isfinite(peak) ? std::fabs(peak) : 0.0}));
  }
  return ref;
}

// The scalar path's own rounding error at row i: the template in the next precision on the same
// inputs. Costly in mp50, so computed only for rows whose difference exceeds the rest of the
// allowance (the allowance is the same either way).
template <class T>
double own_error(const Method& m, const Reference<T>& ref, std::size_t i) {
  using Up = std::conditional_t<std::is_same_v<T, float>, double, mp50>;
  std::array<Up, 6> up;
  for (int j = 0; j < 6; ++j) up[j] = Up(double(ref.args[6 * i + j]));
  const double exact = static_cast<double>(eval(m, up));
  return std::isfinite(exact) ? std::fabs(ref.value[i] - exact) : 0.0;
}

// `out`, the values of the rows of `ref` by a vectorized path, against the scalar ones.
template <class T>
void check_values(const Method& m, const Reference<T>& ref, const std::vector<T>& out, double k,
                  const std::string& label) {
  const double eps = std::numeric_limits<T>::epsilon(), tiny = std::numeric_limits<T>::min();
  double worst = 0, worst_cond = 0;
  std::size_t at = 0;
  int failures = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double s = ref.value[i], v = out[i];
    const Row& r = ref.rows[i];
    const auto where = [&] {
      return ::testing::Message() << label << " at (α, λ, light_cos, view_cos, φ, f0) = (" << r[0] << ", " << r[1]
                                  << ", " << r[2] << ", " << r[3] << ", " << r[4] << ", " << r[5] << "): scalar " << s
                                  << ", batch " << v;
    };
    if (std::isfinite(s) && !std::isfinite(v)) {
      if (++failures <= 5) ADD_FAILURE() << where() << " (new NaN/Inf)";
      continue;
    }
    if (!std::isfinite(s)) continue;
    double allowance = k * eps * ref.scale[i] + 2 * ref.condition[i];
    const double d = std::fabs(v - s);
    if (d > allowance) allowance = k * eps * ref.scale[i] + 2 * std::max(ref.condition[i], 2 * own_error(m, ref, i));
    const bool signless = m.may_be_negative && s <= allowance;
    if (s >= 0 && v < 0 && !signless && ++failures <= 5) ADD_FAILURE() << where() << " (new negative value)";
    if (d < 2 * tiny) continue;  // subnormal results are returned as 0 (docs/simd.md)
    if (d > allowance && ++failures <= 5)
      ADD_FAILURE() << where() << ": |difference| " << d << " > " << allowance << " (" << k << " ulps of "
                    << ref.scale[i] << " + 2 × condition " << ref.condition[i] << ")";
    // Report in ulps of the scale where the condition term does not dominate.
    if (ref.condition[i] <= k * eps * ref.scale[i] && ref.scale[i] > 0) {
      const double ulps = d / (eps * ref.scale[i]);
      if (ulps > worst) worst = ulps, at = i;
    } else {
      worst_cond = std::max(worst_cond, d / allowance);
    }
  }
  std::printf(
      "[ simd     ] %-48s %-6s %6zu rows: well-conditioned max %.3g ulps (k = %g) at row %zu; "
      "ill-conditioned max %.3g of the allowance\n",
      label.c_str(), sizeof(T) == 4 ? "float" : "double", out.size(), worst, k, at, worst_cond);
}

// The batch evaluator against the scalar template.
template <class T>
void check(const Method& m, const Reference<T>& ref, double k, const std::string& label) {
  std::vector<T> out(ref.value.size());
  test::batch_as<T>(m, ref.args, 6, out);
  check_values(m, ref, out, k, label);
}

bool is_specular(const std::string& name) { return name.rfind("specular", 0) == 0; }

TEST(SimdSpecular, EveryKernelMatchesItsScalarTemplate) {
  std::vector<Row> rows = stiff_rows();
  for (const Row& r : random_rows()) rows.push_back(r);
  const auto isas = simd::supported_isas();
  int methods = 0;
  for (const auto& name : simd::vectorized_methods()) {
    if (!is_specular(name)) continue;
    ++methods;
    const Method* m = test::find_quantity_method(name).method;
    ASSERT_NE(m, nullptr);
    const double k = test::ulps_for(kToleranceUlps, name);
    const auto rf = reference<float>(name, *m, rows);
    const auto rd = reference<double>(name, *m, rows);
    for (const auto isa : isas) {
      simd::force_isa(isa);
      const std::string label = std::string(simd::isa_name(isa)) + " " + name;
      check<float>(*m, rf, k, label);
      check<double>(*m, rd, k, label);
    }
  }
  EXPECT_EQ(methods, 9);  // specular: 7, specular-gaussian-ndf: 2 (sg-warp-exact-cosine stays scalar)
  simd::force_isa(isas.back());
}

// The pair evaluators (sglab/simd_specular_pair.hpp) against the batch evaluator at f0 = 0 and
// f0 = 1, bit for bit (the claim: the same operations in the same order), on every instruction set,
// over the rows above (f0 dropped) less three, so that the last batch is partial.
TEST(SimdSpecular, PairIsTheBatchAtFresnelZeroAndOne) {
  std::vector<Row> rows = stiff_rows();
  for (const Row& r : random_rows()) rows.push_back(r);
  rows.resize(rows.size() - 3);
  const std::size_t n = rows.size();
  std::vector<double> args, at[2];
  for (const Row& r : rows) args.insert(args.end(), r.begin(), r.begin() + simd::kSpecularPairArity);
  for (double f0 : {0.0, 1.0}) {
    std::vector<double>& a = at[f0 == 0 ? 0 : 1];
    for (const Row& r : rows) {
      a.insert(a.end(), r.begin(), r.begin() + simd::kSpecularPairArity);
      a.push_back(f0);
    }
  }
  const auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v); };
  const Quantity& q = *find_quantity("specular");
  int methods = 0;
  for (const auto isa : simd::supported_isas()) {
    simd::force_isa(isa);
    for (const Method& m : q.methods) {
      const simd::SpecularPairFn pair = simd::specular_pair_evaluator(m);
      if (!pair) continue;
      ++methods;
      std::vector<double> got0(n), got1(n), want0(n), want1(n);
      pair(args, got0, got1);
      m.batch_double(at[0], 6, want0);
      m.batch_double(at[1], 6, want1);
      std::size_t bad = 0, first = n;
      for (std::size_t i = 0; i < n; ++i)
        if (bits(got0[i]) != bits(want0[i]) || bits(got1[i]) != bits(want1[i])) {
          ++bad;
          first = std::min(first, i);
        }
      EXPECT_EQ(bad, 0u) << simd::isa_name(isa) << " " << m.name << ": first at row " << first << " (" << got0[first]
                         << ", " << got1[first] << ") against (" << want0[first] << ", " << want1[first] << ")";
    }
  }
  // Every `specular` method but the quadrature reference, on each instruction set.
  EXPECT_EQ(methods, 7 * int(simd::supported_isas().size()));
  simd::force_isa(simd::supported_isas().back());
}

// The column evaluators (sglab/simd_specular_pair.hpp SpecularPairColumns: the light's axis by its
// components in place of light_cos and φ) against the scalar template at f0 = 0 and f0 = 1, with
// the batch evaluator's tolerance, on every instruction set, over the rows above; the axis as the
// scalar template forms it (specular_light_axis: std::cos, std::sin). The rows less three: the last
// batch is partial.
TEST(SimdSpecular, ColumnsMatchTheScalarTemplateAtFresnelZeroAndOne) {
  std::vector<Row> rows = stiff_rows();
  for (const Row& r : random_rows()) rows.push_back(r);
  rows.resize(rows.size() - 3);
  const Quantity& q = *find_quantity("specular");
  int methods = 0;
  for (const Method& m : q.methods) {
    if (!simd::specular_pair_columns_evaluator(m)) continue;
    const std::string name = "specular/" + m.name;
    const double k = test::ulps_for(kToleranceUlps, name);
    for (double f0 : {0.0, 1.0}) {
      std::vector<Row> at = rows;
      for (Row& r : at) r[5] = f0;
      const Reference<double> ref = reference<double>(name, m, at);
      std::vector<double> c[6];
      for (const Row& r : ref.rows) {
        for (int j = 0; j < 4; ++j) c[j].push_back(r[std::size_t(j)]);
        const Vec3<double> xi = specular_light_axis(r[2], r[4]);
        c[4].push_back(xi(0));
        c[5].push_back(xi(1));
      }
      const std::size_t n = ref.rows.size();
      for (const auto isa : simd::supported_isas()) {
        simd::force_isa(isa);
        std::vector<double> got0(n), got1(n);
        simd::specular_pair_columns_evaluator(m)(
            {n, c[0].data(), c[3].data(), c[1].data(), c[2].data(), c[4].data(), c[5].data()}, 1, got0.data(),
            got1.data());
        check_values(m, ref, f0 == 0 ? got0 : got1, k,
                     std::string(simd::isa_name(isa)) + " columns f0 = " + (f0 == 0 ? "0 " : "1 ") + name);
        ++methods;
      }
    }
  }
  EXPECT_EQ(methods, 2 * 7 * int(simd::supported_isas().size()));
  simd::force_isa(simd::supported_isas().back());
}

// Receivers shared by many lights (the renderer's layout: each receiver's part of the method
// computed once for all its lights) give the values of each row on its own receiver bit for bit, on
// every instruction set, for every number of receivers around the vector widths (partial batches
// of receivers) and of lights; seeded rows.
TEST(SimdSpecular, SharedReceiversAreEachRowOnItsOwn) {
  const Quantity& q = *find_quantity("specular");
  std::mt19937_64 rng(20261203);
  std::printf("[ simd     ] shared receivers: seed 20261203\n");
  std::uniform_real_distribution<double> u(0, 1);
  int methods = 0;
  for (const Method& m : q.methods) {
    const simd::SpecularPairColumnsFn pair = simd::specular_pair_columns_evaluator(m);
    if (!pair) continue;
    for (const auto isa : simd::supported_isas()) {
      simd::force_isa(isa);
      for (std::size_t receivers : {1u, 2u, 3u, 7u, 8u, 9u, 17u, 33u})
        for (std::size_t lights : {1u, 2u, 5u}) {
          const std::size_t n = receivers * lights;
          std::vector<double> roughness(receivers), view(receivers), rough_rows(n), view_rows(n), c[4];
          for (std::size_t g = 0; g < receivers; ++g) {
            roughness[g] = std::pow(10.0, -2 * u(rng));
            view[g] = u(rng);
          }
          for (std::size_t k = 0; k < n; ++k) {
            const double phi = 7 * u(rng);
            c[0].push_back(std::pow(10.0, -3 + 7 * u(rng)));
            c[1].push_back(-1 + 2 * u(rng));
            const Vec3<double> xi = specular_light_axis(c[1].back(), phi);
            c[2].push_back(xi(0));
            c[3].push_back(xi(1));
            rough_rows[k] = roughness[k % receivers];
            view_rows[k] = view[k % receivers];
          }
          std::vector<double> shared0(n), shared1(n), own0(n), own1(n);
          pair({receivers, roughness.data(), view.data(), c[0].data(), c[1].data(), c[2].data(), c[3].data()}, lights,
               shared0.data(), shared1.data());
          pair({n, rough_rows.data(), view_rows.data(), c[0].data(), c[1].data(), c[2].data(), c[3].data()}, 1,
               own0.data(), own1.data());
          for (std::size_t k = 0; k < n; ++k) {
            EXPECT_EQ(std::memcmp(&shared0[k], &own0[k], sizeof(double)), 0)
                << m.name << " " << simd::isa_name(isa) << " f0 = 0, row " << k << " of " << receivers << " × "
                << lights << ": " << shared0[k] << " vs " << own0[k];
            EXPECT_EQ(std::memcmp(&shared1[k], &own1[k], sizeof(double)), 0)
                << m.name << " " << simd::isa_name(isa) << " f0 = 1, row " << k << " of " << receivers << " × "
                << lights << ": " << shared1[k] << " vs " << own1[k];
          }
        }
      ++methods;
    }
  }
  EXPECT_EQ(methods, 7 * int(simd::supported_isas().size()));
  simd::force_isa(simd::supported_isas().back());
}

// Only the registry's own methods have one: a bound method, or a copy, is evaluated by its batch
// evaluator (its constants may differ from the published ones the pair kernel takes).
TEST(SimdSpecular, PairOnlyForTheRegistrysOwnMethodsAndRowsOfFive) {
  const Method& sglab = *find_quantity("specular")->find("sglab");
  ASSERT_TRUE(simd::specular_pair_evaluator(sglab));
  const Method copy = sglab;
  EXPECT_FALSE(simd::specular_pair_evaluator(copy));
  ASSERT_TRUE(simd::specular_pair_columns_evaluator(sglab));
  EXPECT_FALSE(simd::specular_pair_columns_evaluator(copy));
  std::vector<double> values;
  for (const auto& p : sglab.parameters) values.push_back(p.published);
  ASSERT_TRUE(sglab.bind);
  EXPECT_FALSE(simd::specular_pair_evaluator(sglab.bind(values)));
  EXPECT_FALSE(
      simd::specular_pair_evaluator(*find_quantity("specular")->find(find_quantity("specular")->reference_method)));
  std::vector<double> args(6, 0.5), out0(1), out1(1);
  EXPECT_THROW(simd::specular_pair_evaluator(sglab)(args, out0, out1), std::invalid_argument);
}

// Partial batches and row positions: tests/simd_test.cpp (PartialBatchesAndPositions).

// A batch called with the wrong row length is refused, naming it.
TEST(SimdSpecular, WrongArityIsRefused) {
  const Method* m = find_quantity("specular")->find("asg");
  std::vector<double> args(4, 0.5), out(2);
  EXPECT_THROW(m->batch_double(args, 2, out), std::invalid_argument);
}

}  // namespace
