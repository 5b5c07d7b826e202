// error-map as a library (experiments/error_map.hpp): the reference and the signed errors on its
// grid against an independent quadrature of D(λ, c), and its summary against the per-point errors.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "clamped_cosine_quadrature.hpp"
#include "error_map.hpp"
#include "input_error.hpp"

namespace em = sglab::experiments::error_map;

namespace {

em::Result small_map() {
  em::Options o;
  o.size = 9;
  return em::compute(o);
}

}  // namespace

TEST(ErrorMap, ReferenceAndErrorsAgainstAnIndependentQuadrature) {
  const em::Result r = small_map();
  ASSERT_EQ(r.sharpness.size(), 9u);
  ASSERT_EQ(r.cosine.back(), 1.0);
  const std::size_t nc = r.cosine.size();
  for (std::size_t k = 0; k < r.points(); ++k) {
    const double l = r.sharpness[k / nc], c = r.cosine[k % nc];
    const double pole = sglab::test::clamped_cosine_quadrature(l, 1.0);
    EXPECT_NEAR(r.reference[k] / pole, sglab::test::clamped_cosine_quadrature(l, c) / pole, 1e-9)
        << "λ=" << l << " c=" << c;
  }
  // punctual-approx, (2π/λ)⟨c⟩ written here: its signed error and its summary.
  const auto it = std::find_if(r.methods.begin(), r.methods.end(),
                               [](const em::MethodMap& m) { return m.summary.method == "punctual-approx"; });
  ASSERT_NE(it, r.methods.end());
  double max_abs = 0;
  for (std::size_t k = 0; k < r.points(); ++k) {
    const double l = r.sharpness[k / nc], c = r.cosine[k % nc];
    const double e = (2 * std::numbers::pi / l * std::max(c, 0.0) - sglab::test::clamped_cosine_quadrature(l, c)) /
                     sglab::test::clamped_cosine_quadrature(l, 1.0);
    EXPECT_NEAR(r.error(*it, k), e, 1e-9) << "λ=" << l << " c=" << c;
    max_abs = std::max(max_abs, std::fabs(e));
  }
  EXPECT_NEAR(it->summary.max_abs, max_abs, 1e-9);
}

TEST(ErrorMap, TablesHaveOneSummaryRowPerMethod) {
  const em::Result r = small_map();
  const em::Tables t = em::tables(r);
  std::size_t lines = 0;
  for (char ch : t.summary_csv) lines += ch == '\n';
  EXPECT_EQ(lines, r.methods.size() + 1);
  for (const auto& m : r.methods)
    EXPECT_NE(t.markdown.find("| " + m.summary.method + " |"), std::string::npos) << m.summary.method;
  EXPECT_EQ(r.provenance.command, "sglab error-map --quantity clamped-cosine --size 9");
}

TEST(ErrorMap, BadSizeIsAnInputError) {
  em::Options o;
  o.size = 1;
  EXPECT_THROW(em::compute(o), sglab::runner::InputError);
}
