// tests for experiments/stability_atlas.{hpp,cpp} (`sglab stability`): the counting logic on a
// fake method with known NaN/Inf/negative/wrong/thrown/out-of-domain cells, the grids (the next
// float past ±1 really reaches a float method), the cartesian indexing and peaks against direct
// recomputation, the stiff-case quantities against closed forms, the sharpness grid reaching
// FLT_MAX and DBL_MAX with no NaN or Inf from any method there, and the registry as the atlas's
// only method list (a quantity given as registry data reaches the atlas and its tables).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>

#include <gtest/gtest.h>

#include "sglab/stiff_cases.hpp"
#include "stability_atlas.hpp"
#include "sglab/registry_mp50.hpp"

namespace sglab::experiments::atlas {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A (sharpness, cosine) quantity whose one method misbehaves at known cells of a 3 × 4 grid
// λ ∈ {0, 1, 10} × c ∈ {−1, −0.5, 0.5, 1}; reference(λ, c) = (1 + λ)(1 + c) + 1e-3 (positive,
// largest at c = 1 on each λ line).
double fake_reference(double l, double c) { return (1 + l) * (1 + c) + 1e-3; }

template <class T>
T fake_value(std::span<const T> a) {
  const double l = double(a[0]), c = double(a[1]);
  const double ref = fake_reference(l, c);
  if (l == 1 && c == -0.5) return T(std::numeric_limits<double>::quiet_NaN());
  if (l == 10 && c == -0.5) return T(std::numeric_limits<double>::infinity());
  if (l == 10 && c == 0.5) return T(-0.25);                 // negative (and wrong)
  if (l == 1 && c == 1) return T(ref * 1.05);               // 5 % wrong against the peak (= ref here)
  if (l == 1 && c == -1) return T(ref * 1.5);               // 50 % of a small value: 0.05 % of the peak
  if (l == 10 && c == 1) throw std::runtime_error("fake");  // an evaluator that throws
  return T(ref);
}

Quantity fake_quantity() {
  Quantity q;
  q.name = "fake";
  q.columns = {{"sharpness", ColumnKind::sharpness, ""}, {"cosine", ColumnKind::cosine, ""}};
  Method m;
  m.name = "fake";
  // λ = 0 with c = −1 is outside the domain.
  m.domain_error = [](std::span<const double> a) -> std::optional<std::string> {
    if (a[0] == 0 && a[1] == -1) return std::string("outside");
    return std::nullopt;
  };
  m.eval_float = [](std::span<const float> a) { return fake_value(a); };
  m.eval_double = [](std::span<const double> a) { return fake_value(a); };
  // The "50-digit" form differs from the double one by a relative 1e-3 at (λ, c) = (0, 1) only.
  m.eval_mp50 = [](std::span<const mp50> a) {
    const double l = static_cast<double>(a[0]), c = static_cast<double>(a[1]);
    if (l == 1 || l == 10) return mp50(fake_value(std::span<const double>(std::vector<double>{l, c})));
    return mp50(fake_reference(l, c) * (l == 0 && c == 1 ? 1.001 : 1.0));
  };
  q.methods.push_back(m);
  return q;
}

// The counts of the fake method on its 3 × 4 grid, against the fake reference on every row.
void expect_fake_counts(const Tally& t) {
  EXPECT_EQ(t.points, 12);
  EXPECT_EQ(t.out_of_domain, 1);
  EXPECT_EQ(t.nan, 1);
  EXPECT_EQ(t.inf, 1);
  EXPECT_EQ(t.throws, 1);
  EXPECT_EQ(t.negative, 1);
  // Compared: every finite, evaluated output: 12 − dom − NaN − Inf − throw = 8.
  EXPECT_EQ(t.compared, 8);
  // > 1 % of |ref|: the negative one, the 5 % one, the 50 % one. > 1 % of the peak: not the 50 %
  // one (its reference is 1e-3, 5e-4 off, against a peak of (1 + 1)(1 + 1) + 1e-3 on the λ = 1 line).
  EXPECT_EQ(t.wrong_relative, 3);
  EXPECT_EQ(t.wrong_peak, 2);
  EXPECT_EQ(t.worst_flag, Flag::nan);
}

Grid fake_grid() { return make_grid({"sharpness", "cosine"}, {{0.0, 1.0, 10.0}, {-1.0, -0.5, 0.5, 1.0}}, 0, 1, true); }

TEST(StabilityAtlas, FakeMethodGetsExactlyItsCounts) {
  const Quantity q = fake_quantity();
  const Grid g = fake_grid();
  ASSERT_EQ(g.rows, 12u);
  std::vector<double> reference(g.rows);
  for (std::size_t r = 0; r < g.rows; ++r) reference[r] = fake_reference(g.row(r)[0], g.row(r)[1]);
  const std::vector<double> peak = line_peaks(g, reference);
  const std::vector<char> rounding(g.rows, 1);
  for (Precision p : {Precision::float32, Precision::float64}) {
    std::vector<Evaluation> ev = evaluate(q, q.methods[0], p, g, reference, peak, rounding);
    const Tally t = tally(ev, tiny_of(p));
    expect_fake_counts(t);
    EXPECT_EQ(g.row(t.worst_flag_row), (std::vector<double>{1.0, -0.5}));
    // The worst relative error: the negative output, |−0.25 − ref| / ref at (10, 0.5).
    const double ref_neg = fake_reference(10, 0.5);
    EXPECT_NEAR(t.rel_error.error, (0.25 + ref_neg) / ref_neg, 1e-6);
    EXPECT_EQ(g.row(t.rel_error.row), (std::vector<double>{10.0, 0.5}));
    // Rounding: the 50-digit form differs only at (0, 1), by a relative 1e-3 (float: plus ≤ 1 ulp).
    EXPECT_NEAR(t.rounding_rel.error, 1e-3 / 1.001, p == Precision::float32 ? 2e-7 : 1e-12);
    EXPECT_EQ(g.row(t.rounding_rel.row), (std::vector<double>{0.0, 1.0}));
    // Rounding is measured where the output is finite and the method did not throw: 8 rows.
    EXPECT_EQ(t.rounding_points, 8);

    // Cells: one row each here, so each cell's flag is that row's verdict.
    const auto cs = cells(g, ev, tiny_of(p));
    ASSERT_EQ(cs.size(), 12u);
    auto flag_at = [&](std::size_t i, std::size_t j) { return cs[i * 4 + j].flag; };
    EXPECT_EQ(flag_at(0, 0), Flag::out_of_domain);
    EXPECT_EQ(flag_at(1, 1), Flag::nan);
    EXPECT_EQ(flag_at(2, 1), Flag::inf);
    EXPECT_EQ(flag_at(2, 2), Flag::negative);
    EXPECT_EQ(flag_at(1, 3), Flag::wrong);
    EXPECT_EQ(flag_at(1, 0), Flag::wrong_relative);
    EXPECT_EQ(flag_at(2, 3), Flag::throws);
    EXPECT_EQ(flag_at(0, 3), Flag::ok);
    EXPECT_EQ(cs[0 * 4 + 3].compared, 1);  // compared with its reference
    EXPECT_EQ(cs[1 * 4 + 1].compared, 0);  // NaN: nothing to compare
    EXPECT_EQ(cs[0 * 4 + 0].compared, 0);  // outside the domain
    long total = 0;
    for (const auto& c : cs) total += c.points;
    EXPECT_EQ(total, 12);
  }
}

TEST(StabilityAtlas, AssessTreatsUnderflowAsNoError) {
  // A true value below the smallest normal number, returned as 0: not "100 % wrong".
  Evaluation e;
  e.value = 0;
  e.reference = 1e-310;
  e.exact = 1e-320;
  const Assessment a = assess(e, tiny_of(Precision::float64));
  EXPECT_EQ(a.flag, Flag::ok);
  EXPECT_LT(a.rel_error, 1e-2);
  EXPECT_LT(a.rounding_rel, 1e-2);
  // … but a normal-range true value returned as 0 is 100 % wrong.
  e.reference = 1e-300;
  EXPECT_EQ(assess(e, tiny_of(Precision::float64)).flag, Flag::wrong);
  // In float the same 1e-300 is far below FLT_MIN: no error.
  EXPECT_EQ(assess(e, tiny_of(Precision::float32)).flag, Flag::ok);
}

TEST(StabilityAtlas, NextFloatPastOneReachesFloatMethods) {
  // The cosine values every float method sees on the clamped-cosine grid, recorded by a method.
  const Quantity* cc = find_quantity("clamped-cosine");
  ASSERT_NE(cc, nullptr);
  for (bool quick : {false, true}) {
    const Grid g = registry_grid(*cc, quick);
    ASSERT_EQ(g.y_column, 1);
    const std::vector<double>& cosines = g.values[1];
    const std::set<double> cs(cosines.begin(), cosines.end());
    for (double v : {1.0, -1.0, 0.0, stiff::float_after_one(), -stiff::float_after_one(), stiff::float_before_one(),
                     -stiff::float_before_one(), stiff::double_after_one(), -stiff::double_after_one(),
                     stiff::double_before_one(), -stiff::double_before_one()})
      EXPECT_EQ(cs.count(v), 1u) << v << (quick ? " (quick)" : "");
    EXPECT_EQ(stiff::float_after_one(), 1.0 + std::ldexp(1.0, -23));
    EXPECT_EQ(stiff::float_before_one(), 1.0 - std::ldexp(1.0, -24));
    EXPECT_TRUE(std::is_sorted(cosines.begin(), cosines.end()));
    EXPECT_EQ(g.values[0].front(), 0.0);
    EXPECT_EQ(g.values[0][1], 1e-8);
    EXPECT_NE(std::find(g.values[0].begin(), g.values[0].end(), 1e8), g.values[0].end());
    EXPECT_EQ(g.values[0].back(), std::numeric_limits<double>::max());

    // A float method sees the rounded cosines; record them (evaluate runs in parallel).
    Quantity q;
    q.name = "recorder";
    q.columns = cc->columns;
    Method m;
    m.name = "recorder";
    const Grid small = make_grid(g.column_names, {{1.0}, cosines}, 0, 1, true);
    std::vector<float> got;
    std::mutex mu;
    m.eval_float = [&](std::span<const float> a) {
      std::lock_guard<std::mutex> lock(mu);
      got.push_back(a[1]);
      return 1.0f;
    };
    evaluate(q, m, Precision::float32, small, {}, {}, {});
    const std::set<float> fs(got.begin(), got.end());
    EXPECT_EQ(fs.count(std::nextafter(1.0f, 2.0f)), 1u);
    EXPECT_EQ(fs.count(-std::nextafter(1.0f, 2.0f)), 1u);
    EXPECT_EQ(fs.count(std::nextafter(1.0f, 0.0f)), 1u);
    EXPECT_EQ(got.size(), cosines.size());  // all within the 1e-6 slack: none rejected
  }
}

TEST(StabilityAtlas, GridIndexingMatchesNestedLoops) {
  const Grid g = make_grid({"a", "b", "c"}, {{1, 2}, {10, 20, 30}, {100, 200, 300, 400}}, 0, 2, true);
  ASSERT_EQ(g.rows, 24u);
  std::size_t r = 0;
  for (std::size_t i = 0; i < 2; ++i)
    for (std::size_t j = 0; j < 3; ++j)
      for (std::size_t k = 0; k < 4; ++k, ++r) {
        EXPECT_EQ(g.row(r), (std::vector<double>{g.values[0][i], g.values[1][j], g.values[2][k]}));
        EXPECT_EQ(g.x_index(r), i);
        EXPECT_EQ(g.y_index(r), k);
        const auto line = g.y_line(r);
        ASSERT_EQ(line.size(), 4u);
        for (std::size_t kk = 0; kk < 4; ++kk) EXPECT_EQ(line[kk], r - k + kk);
      }
  // Peaks: the max of |reference| over the y line, and NaN on a line with an unknown reference.
  std::vector<double> ref(g.rows);
  for (std::size_t q = 0; q < g.rows; ++q) ref[q] = -double((q * 7) % 11);
  ref[5] = kNaN;  // line of rows 4–7
  const auto peak = line_peaks(g, ref);
  for (std::size_t q = 0; q < g.rows; ++q) {
    if (q >= 4 && q < 8) {
      EXPECT_TRUE(std::isnan(peak[q]));
      continue;
    }
    double m = 0;
    for (std::size_t k = (q / 4) * 4; k < (q / 4) * 4 + 4; ++k) m = std::max(m, std::fabs(ref[k]));
    EXPECT_EQ(peak[q], m) << q;
  }
}

TEST(StabilityAtlas, SpreadSubsetPicksExactlyNEligibleRows) {
  std::vector<char> eligible(1000, 0);
  for (std::size_t r = 0; r < eligible.size(); r += 3) eligible[r] = 1;  // 334 eligible
  for (std::size_t n : {0u, 1u, 10u, 333u}) {
    const auto s = spread_subset(eligible, n);
    std::size_t count = 0;
    for (std::size_t r = 0; r < s.size(); ++r) {
      if (s[r]) {
        EXPECT_TRUE(eligible[r]) << r;
      }
      count += s[r] ? 1 : 0;
    }
    EXPECT_EQ(count, n);
  }
  const auto all = spread_subset(eligible, 5000);
  EXPECT_EQ(all, eligible);
  // Spread: 10 of 334 leave no gap wider than a third of the range.
  const auto ten = spread_subset(eligible, 10);
  std::size_t last = 0, widest = 0;
  for (std::size_t r = 0; r < ten.size(); ++r)
    if (ten[r]) {
      widest = std::max(widest, r - last);
      last = r;
    }
  EXPECT_LT(widest, 334u);
}

TEST(StabilityAtlas, AtlasFindsHillNegativesLikeADirectCount) {
  // The published flaw of hill-fitted (negative for λ ≲ 1), counted by the atlas and by a plain
  // loop over the same rows.
  const Quantity* cc = find_quantity("clamped-cosine");
  ASSERT_NE(cc, nullptr);
  const Method* hill = cc->find("hill-fitted");
  ASSERT_NE(hill, nullptr);
  const Grid g = registry_grid(*cc, true);
  const auto ev = evaluate(*cc, *hill, Precision::float64, g, {}, {}, {});
  const Tally t = tally(ev, tiny_of(Precision::float64));
  long negatives = 0, rejected = 0;
  for (std::size_t r = 0; r < g.rows; ++r) {
    const auto row = g.row(r);
    if (hill->domain_error(row)) {
      ++rejected;
      continue;
    }
    if (hill->eval_double(row) < 0) ++negatives;
  }
  std::printf("hill-fitted on the quick grid: %ld negative, %ld out of domain of %zu\n", negatives, rejected, g.rows);
  EXPECT_GT(negatives, 0);
  EXPECT_EQ(t.negative, negatives);
  EXPECT_EQ(t.out_of_domain, rejected);
  EXPECT_EQ(rejected, long(g.y_size()));  // λ = 0: one row per cosine
}

TEST(StabilityAtlas, StiffQuantitiesAgreeWithClosedForms) {
  // The stiff cases of docs/math.md §10 are registry quantities (core/src/registry_stiff.cpp).
  // Exactly opposite axes of equal sharpness: the product is the constant e^{−2λ}, ∫ = 4π e^{−2λ}.
  const Quantity* opp = find_quantity("sg-product-opposite");
  ASSERT_NE(opp, nullptr);
  for (double l : {0.0, 1e-3, 1.0, 30.0}) {
    const std::vector<double> a{l, 0.0};
    const double exact = 4 * M_PI * std::exp(-2 * l);
    for (const char* name : {"definition", "sg_product", "product_integral_exact"})
      EXPECT_NEAR(opp->find(name)->eval_double(a) / exact, 1.0, 1e-14) << name << " at λ = " << l;
  }
  // Nearly opposite (δ = 0.1): ∫ = e^{λ3−2λ}·2π(1 − e^{−2λ3})/λ3 with λ3 = 2λ sin(δ/2).
  for (double l : {0.5, 20.0}) {
    const double d = 0.1, l3 = 2 * l * std::sin(d / 2);
    const double exact = std::exp(l3 - 2 * l) * 2 * M_PI * (-std::expm1(-2 * l3)) / l3;
    const std::vector<double> a{l, d};
    EXPECT_NEAR(opp->find("sg_product")->eval_double(a) / exact, 1.0, 1e-12);
  }
  // A 3 × 3 patch of spacing h has σ² = 4h²/3; at the origin both reference points get it to
  // rounding, and a single point far away has σ² = 0 exactly with o at the first VPL.
  const Quantity* var = find_quantity("vsgl-variance");
  ASSERT_NE(var, nullptr);
  for (const char* name : {"origin-zero", "origin-first-vpl"})
    EXPECT_NEAR(var->find(name)->eval_double(std::vector<double>{0.0, 1.0}), 4.0 / 3.0, 1e-14) << name;
  EXPECT_EQ(var->find("origin-first-vpl")->eval_double(std::vector<double>{1e8, 0.0}), 0.0);
}

TEST(StabilityAtlas, SharpnessGridReachesTheLargestFiniteValueOfEachType) {
  const double fmax = double(std::numeric_limits<float>::max()), dmax = std::numeric_limits<double>::max();
  for (Level level : {Level::full, Level::coarse, Level::minimal})
    for (ColumnKind kind : {ColumnKind::sharpness, ColumnKind::nonnegative}) {
      const auto v = column_values(kind, level);
      EXPECT_TRUE(std::is_sorted(v.begin(), v.end()));
      EXPECT_EQ(v.back(), dmax);
      EXPECT_NE(std::find(v.begin(), v.end(), fmax), v.end());
    }
  // Float evaluates the rows up to FLT_MAX and skips the larger ones (they are not float inputs);
  // double evaluates every row. A method that records its inputs sees both maxima.
  const Quantity* sgi = find_quantity("sg-integral");
  ASSERT_NE(sgi, nullptr);
  const Grid g = registry_grid(*sgi, true);
  std::mutex mu;
  float seen_float = 0;
  double seen_double = 0;
  Method m = *sgi->find("exact");
  const Method exact = m;
  m.eval_float = [&](std::span<const float> a) {
    std::lock_guard<std::mutex> lock(mu);
    seen_float = std::max(seen_float, a[0]);
    return exact.eval_float(a);
  };
  m.eval_double = [&](std::span<const double> a) {
    std::lock_guard<std::mutex> lock(mu);
    seen_double = std::max(seen_double, a[0]);
    return exact.eval_double(a);
  };
  const auto ef = evaluate(*sgi, m, Precision::float32, g, {}, {}, {});
  const auto ed = evaluate(*sgi, m, Precision::float64, g, {}, {}, {});
  EXPECT_EQ(seen_float, std::numeric_limits<float>::max());
  EXPECT_EQ(seen_double, dmax);
  long skipped_float = 0;
  for (std::size_t r = 0; r < g.rows; ++r) {
    skipped_float += ef[r].skipped ? 1 : 0;
    EXPECT_FALSE(ed[r].skipped);
    EXPECT_EQ(ef[r].skipped, g.row(r)[0] > fmax) << describe_row(g, r, Precision::float64);
  }
  EXPECT_GT(skipped_float, 0);
  // A(λ) = 2π(1 − e^{−2λ})/λ is 2π/λ at the maxima (independent closed form; normal numbers).
  for (std::size_t r = 0; r < g.rows; ++r) {
    const double l = g.row(r)[0];
    if (l == fmax) {
      EXPECT_NEAR(ef[r].value / (2 * M_PI / fmax), 1.0, 1e-6);
    }
    if (l == dmax) {
      EXPECT_NEAR(ed[r].value / (2 * M_PI / dmax), 1.0, 1e-14);
    }
  }
}

TEST(StabilityAtlas, LargeLambdaLimitsMatchTheQuadratureAtItsReach) {
  // The references past λ = 1e8 are the closed-form limits (Quantity::reference_reach); where the quadrature still runs
  // (λ = 1e8, 1e7) they agree with it to O(1/λ + λc⁴), across the horizon transition c ~ 1/√λ.
  const Quantity* h = find_quantity("hemispherical");
  const Quantity* d = find_quantity("clamped-cosine");
  ASSERT_NE(h, nullptr);
  ASSERT_NE(d, nullptr);
  for (double l : {1e7, kQuadratureMaxSharpness})
    for (double c : {-1.0, -1e-3, -1e-4, -1e-8, 0.0, 1e-8, 1e-4, 0.5, 1.0}) {
      const std::vector<double> a{l, c};
      const double hq = h->find("reference")->eval_double(a), dq = d->find("reference")->eval_double(a);
      ASSERT_TRUE(h->reference_reach.limit && d->reference_reach.limit);
      const double hl = h->reference_reach.limit(a), dl = d->reference_reach.limit(a);
      const double tol = 5 / l + l * c * c * c * c;  // O(1/λ) and the θ⁴ term of cos θ in the tail
      EXPECT_LE(std::fabs(hl - hq), tol * std::max(std::fabs(hq), 1e-300)) << "H at λ = " << l << ", c = " << c;
      EXPECT_LE(std::fabs(dl - dq), tol * std::max(std::fabs(dq), 1e-300)) << "D at λ = " << l << ", c = " << c;
    }
}

TEST(StabilityAtlas, NoMethodGivesNaNOrInfUpToTheMaxima) {
  // Every method of every quantity of the (quick) atlas, float and double, over grids that reach
  // FLT_MAX and DBL_MAX: no NaN and no Inf anywhere (a published pole is a domain error instead).
  // The reference method runs where the atlas runs it (the quadratures stop at λ = 1e8).
  const std::vector<Case> cases = registry_cases(true);
  for (const Case& c : cases)
    for (const Method& m : c.quantity.methods) {
      const bool is_ref = m.name == c.quantity.reference_method;
      const std::span<const char> rows = is_ref ? std::span<const char>(c.reference_rows) : std::span<const char>();
      for (Precision p : {Precision::float32, Precision::float64}) {
        const auto ev = evaluate(c.quantity, m, p, c.grid, {}, {}, {}, rows);
        const Tally t = tally(ev, tiny_of(p));
        EXPECT_EQ(t.nan, 0) << c.quantity.name << "/" << m.name << " (" << precision_name(p) << ") first at "
                            << (t.worst_flag_row < c.grid.rows ? describe_row(c.grid, t.worst_flag_row, p) : "");
        EXPECT_EQ(t.inf, 0) << c.quantity.name << "/" << m.name << " (" << precision_name(p) << ")";
        EXPECT_GT(t.points, 0) << c.quantity.name << "/" << m.name;
      }
    }
}

TEST(StabilityAtlas, AtlasMethodsAreTheRegistrysMethods) {
  // No method list of its own: the atlas's cases are the registry's quantities and methods, in order.
  const auto& all = quantities();
  for (bool quick : {false, true}) {
    const auto cases = registry_cases(quick);
    ASSERT_EQ(cases.size(), all.size());
    for (std::size_t i = 0; i < all.size(); ++i) {
      EXPECT_EQ(cases[i].quantity.name, all[i].name);
      ASSERT_EQ(cases[i].quantity.methods.size(), all[i].methods.size()) << all[i].name;
      for (std::size_t k = 0; k < all[i].methods.size(); ++k)
        EXPECT_EQ(cases[i].quantity.methods[k].name, all[i].methods[k].name) << all[i].name;
      EXPECT_EQ(cases[i].grid.column_names.size(), all[i].columns.size()) << all[i].name;
      EXPECT_GT(cases[i].grid.rows, 0u) << all[i].name;
    }
  }
  for (const char* name : {"sg-product-opposite", "sg-product-opposite-value", "vsgl-variance", "vsgl-on-top"})
    EXPECT_NE(find_quantity(name), nullptr) << name;
  // vsgl-on-top wraps every clamped-cosine method: a diffuse method added to the registry reaches it too.
  const Quantity* cc = find_quantity("clamped-cosine");
  const Quantity* top = find_quantity("vsgl-on-top");
  ASSERT_NE(cc, nullptr);
  ASSERT_NE(top, nullptr);
  EXPECT_EQ(top->reference_method, cc->reference_method);
  ASSERT_EQ(top->methods.size(), cc->methods.size());
  for (std::size_t k = 0; k < cc->methods.size(); ++k) EXPECT_EQ(top->methods[k].name, cc->methods[k].name);
}

// A quantity that exists only in this test, handed to the atlas as registry data: the fake method
// above, a reference method that cannot run past λ = 5 (it throws there), and the closed form
// standing in past that reach. Its columns carry their stiff values.
Quantity test_only_quantity() {
  Quantity q = fake_quantity();
  q.name = "test-only";
  q.columns[0].stiff_values = {0.0, 1.0, 10.0};
  q.columns[1].stiff_values = {-1.0, -0.5, 0.5, 1.0};
  q.reference_method = "ref";
  Method ref;
  ref.name = "ref";
  set_evaluators(ref, [](auto a) {
    using T = typename decltype(a)::value_type;
    if (static_cast<double>(a[0]) > 5) throw std::runtime_error("past the reference's reach");
    return T(fake_reference(static_cast<double>(a[0]), static_cast<double>(a[1])));
  });
  q.methods.push_back(ref);
  q.reference_reach.max_sharpness = 5;
  q.reference_reach.limit = [](std::span<const double> a) { return fake_reference(a[0], a[1]); };
  q.reference_reach.limit_formula = "(the fake reference)";
  return q;
}

TEST(StabilityAtlas, AQuantityGivenAsRegistryDataReachesTheAtlas) {
  const std::vector<Quantity> registry{test_only_quantity()};
  Options o;
  o.quick = true;
  const Result r = compute(o, registry);
  ASSERT_EQ(r.quantities.size(), 1u);
  const QuantityResult& q = r.quantities[0];
  EXPECT_EQ(q.grid.rows, 12u);  // the columns' stiff values, 3 × 4
  EXPECT_NE(q.note.find("(the fake reference)"), std::string::npos) << q.note;
  ASSERT_EQ(q.methods.size(), 2u);
  EXPECT_EQ(q.methods[0].name, "fake");
  ASSERT_EQ(q.methods[0].precisions.size(), 2u);
  // The counts of FakeMethodGetsExactlyItsCounts: the reference is known on every row, from the
  // reference method within its reach and from the closed form past it.
  for (const PrecisionResult& p : q.methods[0].precisions) {
    expect_fake_counts(p.tally);
    EXPECT_EQ(p.worst_flag_at, "sharpness=1; cosine=-0.5");
  }
  // The reference method ran only within its reach: λ ∈ {0, 1}, 8 rows, none thrown.
  EXPECT_TRUE(q.methods[1].is_reference);
  EXPECT_EQ(q.methods[1].precisions[1].tally.points, 8);
  EXPECT_EQ(q.methods[1].precisions[1].tally.throws, 0);
  // The tables carry it.
  EXPECT_NE(summary_csv(r).find("\ntest-only,fake,float,12,1,1,1,1,1,8,3,2,"), std::string::npos) << summary_csv(r);
  EXPECT_NE(cells_csv(r).find("\ntest-only,fake,double,sharpness,"), std::string::npos);
  EXPECT_NE(markdown(r, "").find("## test-only"), std::string::npos);
}

TEST(StabilityAtlas, UnknownQuantityIsRefusedBeforeComputing) {
  Options o;
  o.only = {"no-such-quantity"};
  EXPECT_THROW(compute(o), std::invalid_argument);
}

}  // namespace
}  // namespace sglab::experiments::atlas
