// The method registry (core/include/sglab/registry.hpp) and its stability requirement (docs/math.md §10): no
// method returns NaN, Inf or a negative value in float or double over λ ∈ {0} ∪ [1e-8, 1e8],
// c ∈ [−1, 1] (±1 exactly and a rounding step past them) — except where the published form
// itself goes negative (`may_be_negative`, which must still be finite), and except points a
// method declares outside its domain (which must then say why). Enumerates the registry, so a new
// method is covered the moment it is registered.
#include <algorithm>
#include <map>
#include <set>

#include "sglab/registry.hpp"
#include "sglab/simd.hpp"
#include "test_util.hpp"

namespace sglab {
namespace {

std::vector<std::vector<double>> stiff_rows(const Quantity& q) {
  std::vector<std::vector<double>> rows{{}};
  for (const auto& col : q.columns) {
    std::vector<double> values;
    switch (col.kind) {
      case ColumnKind::sharpness: values = test::stiff_sharpnesses(2); break;
      case ColumnKind::cosine: values = test::stiff_cosines(8); break;
      case ColumnKind::mean_length: values = stiff::mean_lengths(); break;
      default: return {};  // quantities of other modules test their own domains
    }
    std::vector<std::vector<double>> next;
    for (const auto& r : rows)
      for (double v : values) {
        auto n = r;
        n.push_back(v);
        next.push_back(n);
      }
    rows = std::move(next);
  }
  return rows;
}

TEST(Registry, EveryMethodFiniteAndNonNegativeOnStiffInputs) {
  int checked = 0;
  for (const auto& q : quantities()) {
    const auto rows = stiff_rows(q);
    for (const auto& m : q.methods) {
      for (const auto& row : rows) {
        // Rows outside ±1 by more than the accepted slack are rejected before any method runs.
        bool valid = true;
        for (std::size_t k = 0; k < row.size(); ++k) valid = valid && !column_value_error(q.columns[k], row[k]);
        if (!valid) continue;
        if (m.domain_error) {
          if (auto why = m.domain_error(row)) {
            EXPECT_FALSE(why->empty());
            continue;
          }
        }
        std::vector<float> rf(row.begin(), row.end());
        const double vd = m.eval_double(row);
        const float vf = m.eval_float(rf);
        ++checked;
        EXPECT_TRUE(std::isfinite(vd)) << q.name << "/" << m.name << " double at " << ::testing::PrintToString(row)
                                       << " = " << vd;
        EXPECT_TRUE(std::isfinite(vf)) << q.name << "/" << m.name << " float at " << ::testing::PrintToString(row)
                                       << " = " << vf;
        if (!m.may_be_negative) {
          EXPECT_GE(vd, 0.0) << q.name << "/" << m.name << " double at " << ::testing::PrintToString(row);
          EXPECT_GE(vf, 0.0f) << q.name << "/" << m.name << " float at " << ::testing::PrintToString(row);
        }
      }
    }
  }
  std::printf("checked %d (quantity, method, point) triples in float and double\n", checked);
  EXPECT_GT(checked, 1000);
}

TEST(Registry, NamesAreUniqueAndReferencesExist) {
  std::set<std::string> quantity_names;
  for (const auto& q : quantities()) {
    EXPECT_TRUE(quantity_names.insert(q.name).second) << q.name;
    std::set<std::string> names;
    for (const auto& m : q.methods) {
      EXPECT_TRUE(names.insert(m.name).second) << q.name << "/" << m.name;
      EXPECT_FALSE(m.source.empty()) << q.name << "/" << m.name;
      EXPECT_TRUE(m.eval_float && m.eval_double && m.eval_mp50 && m.batch_float && m.batch_double);
    }
    if (!q.reference_method.empty()) {
      EXPECT_NE(q.find(q.reference_method), nullptr) << q.name;
    }
  }
  // The quantities and methods the registry must provide.
  const std::map<std::string, std::vector<std::string>> required{
      {"sg-integral", {"exact", "approx"}},
      {"hemispherical", {"reference", "meder", "tokuyoshi2022", "vmf-tokuyoshi2024"}},
      {"clamped-cosine",
       {"reference", "punctual", "punctual-approx", "sg-cosine", "cosine-lobe-sg", "hill-fitted", "meder",
        "tokuyoshi2022", "tokuyoshi2024"}},
      {"product-integral", {"exact", "iwasaki"}},
      {"vmf-sharpness", {"toksvig", "banerjee"}},
      {"vmf-mean-length", {"banerjee"}}};
  for (const auto& [qn, methods] : required) {
    const Quantity* q = find_quantity(qn);
    ASSERT_NE(q, nullptr) << qn;
    for (const auto& mn : methods) EXPECT_NE(q->find(mn), nullptr) << qn << "/" << mn;
  }
}

TEST(Registry, BatchEqualsSingleEvaluation) {
  const Quantity* q = find_quantity("clamped-cosine");
  ASSERT_NE(q, nullptr);
  const std::vector<double> args{0.5, 0.3, 10.0, -0.2, 1e4, 0.99};
  const auto& vectorized = simd::vectorized_methods();
  for (const auto& m : q->methods) {
    std::vector<double> out(3);
    m.batch_double(args, 2, out);
    // The vectorized batch evaluators differ from the scalar definition in the last bits (their
    // tolerances and reasons: tests/simd_test.cpp); every other batch is the scalar loop itself.
    const bool simd = std::find(vectorized.begin(), vectorized.end(), q->name + "/" + m.name) != vectorized.end();
    for (int i = 0; i < 3; ++i) {
      const double single = m.eval_double(std::span<const double>(args.data() + 2 * i, 2));
      if (simd) EXPECT_NEAR(out[i], single, 1e-11 * std::max(1.0, std::fabs(single))) << m.name;
      else EXPECT_EQ(out[i], single) << m.name;
    }
  }
}

TEST(Registry, ColumnValidation) {
  const Column sharp{"sharpness", ColumnKind::sharpness, ""}, cos{"cosine", ColumnKind::cosine, ""};
  EXPECT_FALSE(column_value_error(sharp, 0.0));
  EXPECT_TRUE(column_value_error(sharp, -1e-300));
  EXPECT_TRUE(column_value_error(sharp, std::nan("")));
  EXPECT_FALSE(column_value_error(cos, 1 + 0.9e-6));
  EXPECT_TRUE(column_value_error(cos, 1 + 1.1e-6));
  EXPECT_TRUE(column_value_error(cos, -1 - 1.1e-6));
}

}  // namespace
}  // namespace sglab
