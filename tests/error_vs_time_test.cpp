// error-vs-time as a library (experiments/error_vs_time.hpp): the errors it reports for the
// clamped-cosine methods against an independent quadrature of D(λ, c) on the same grid.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "clamped_cosine_quadrature.hpp"
#include "error_vs_time.hpp"
#include "sglab/registry.hpp"

namespace evt = sglab::experiments::error_vs_time;

namespace {

const evt::Result& quick_result() {
  static const evt::Result r = [] {
    evt::Options o;
    o.quantities = {"clamped-cosine"};
    o.quick = true;
    return evt::compute(o);
  }();
  return r;
}

// The independent quadrature on the quick result's grid, computed once for the tests below (it is
// most of their time): D(λ, c) at every point, and D(λ, 1) per λ (the grid's points share a λ
// across its cosines, so that scale takes one quadrature per λ, not one per point).
struct GridQuadrature {
  std::vector<double> exact, pole;  // per grid point
};

const GridQuadrature& grid_quadrature() {
  static const GridQuadrature g = [] {
    const evt::Section& s = quick_result().sections[0];
    GridQuadrature q;
    std::map<double, double> at_pole;
    for (std::size_t k = 0; k < s.points(); ++k) {
      const double l = s.args[2 * k], c = s.args[2 * k + 1];
      q.exact.push_back(sglab::test::clamped_cosine_quadrature(l, c));
      auto it = at_pole.find(l);
      if (it == at_pole.end()) it = at_pole.emplace(l, sglab::test::clamped_cosine_quadrature(l, 1.0)).first;
      q.pole.push_back(it->second);
    }
    return q;
  }();
  return g;
}

}  // namespace

TEST(ErrorVsTime, GridAndProvenance) {
  const evt::Result& r = quick_result();
  ASSERT_EQ(r.sections.size(), 1u);
  const evt::Section& s = r.sections[0];
  EXPECT_EQ(s.quantity, "clamped-cosine");
  EXPECT_EQ(s.arity, 2u);
  EXPECT_GT(s.points(), 100u);
  EXPECT_EQ(r.provenance.command, "sglab error-vs-time --quantity clamped-cosine --quick");
  EXPECT_EQ(r.provenance.mode(), "quick run");
  const evt::Tables t = evt::tables(r);
  // One CSV row per method row, after the header.
  std::size_t lines = 0;
  for (char ch : t.csv) lines += ch == '\n';
  EXPECT_EQ(lines, s.rows.size() + 1);
  EXPECT_NE(t.markdown.find("## clamped-cosine"), std::string::npos);
}

// Every double row's RMSE and max error, recomputed here against the independent quadrature
// (error = |m − D|/D(λ, 1), the registry's method evaluated on the result's own grid points).
TEST(ErrorVsTime, ErrorsMatchAnIndependentReference) {
  const evt::Section& s = quick_result().sections[0];
  const sglab::Quantity* q = sglab::find_quantity("clamped-cosine");
  ASSERT_NE(q, nullptr);
  const std::vector<double>& exact = grid_quadrature().exact;
  const std::vector<double>& pole = grid_quadrature().pole;
  int checked = 0;
  for (const evt::Row& row : s.rows) {
    if (row.precision != "double" || row.method == s.reference_method) continue;
    const sglab::Method* m = q->find(row.method);
    ASSERT_NE(m, nullptr) << row.method;
    double sum_sq = 0, max_error = 0;
    long counted = 0;
    for (std::size_t k = 0; k < s.points(); ++k) {
      const std::span<const double> a(&s.args[2 * k], 2);
      if (m->domain_error && m->domain_error(a)) continue;
      const double v = m->eval_double(a);
      if (!std::isfinite(v)) continue;
      const double e = std::fabs(v - exact[k]) / pole[k];
      sum_sq += e * e;
      max_error = std::max(max_error, e);
      ++counted;
    }
    const double rmse = std::sqrt(sum_sq / double(counted));
    // The reference agrees with the quadrature to ~1e-12 of D(λ, 1): the reported errors agree to far
    // better than their own size.
    EXPECT_NEAR(row.rmse, rmse, 1e-9 + 1e-6 * rmse) << row.method;
    EXPECT_NEAR(row.max_error, max_error, 1e-9 + 1e-6 * max_error) << row.method;
    ++checked;
  }
  EXPECT_GE(checked, 8);
}

// punctual-approx, (2π/λ)⟨c⟩, written here: its reported max error is the quadrature's.
TEST(ErrorVsTime, PunctualApproxFromItsFormula) {
  const evt::Section& s = quick_result().sections[0];
  const GridQuadrature& q = grid_quadrature();
  double max_error = 0;
  for (std::size_t k = 0; k < s.points(); ++k) {
    const double l = s.args[2 * k], c = s.args[2 * k + 1];
    const double v = 2 * std::numbers::pi / l * std::max(c, 0.0);
    max_error = std::max(max_error, std::fabs(v - q.exact[k]) / q.pole[k]);
  }
  for (const evt::Row& row : s.rows)
    if (row.method == "punctual-approx" && row.precision == "double") {
      EXPECT_NEAR(row.max_error, max_error, 1e-6 * max_error);
    }
}

// The poster's speed claims are judged from interleaved runs with a noise margin: a ratio inside the
// margin is "within noise", not a verdict either way.
TEST(ErrorVsTime, SpeedVerdictsHaveANoiseMargin) {
  evt::SpeedComparison c{"a", "b", "sglab batch"};
  c.margin = 0.05;
  for (const auto& [ratio, verdict] :
       {std::pair{0.90, "holds"}, std::pair{0.96, "within noise"}, std::pair{1.0, "within noise"},
        std::pair{1.049, "within noise"}, std::pair{1.06, "does not hold"}}) {
    c.ratio = ratio;
    EXPECT_EQ(c.faster_verdict(), verdict) << ratio;
  }
  const evt::Section& s = quick_result().sections[0];
  ASSERT_EQ(s.speed.size(), 4u) << "tokuyoshi2022 vs meder and hill-fitted vs tokuyoshi2022, batch and port";
  for (const auto& x : s.speed) {
    EXPECT_TRUE(std::isfinite(x.ratio) && x.ratio > 0) << x.a << " / " << x.b;
    EXPECT_GE(x.margin, 0.03);
    EXPECT_GE(x.rounds, 5);
  }
  const std::string md = evt::tables(quick_result()).markdown;
  EXPECT_NE(md.find("interleaved runs each; noise margin ±"), std::string::npos);
}
