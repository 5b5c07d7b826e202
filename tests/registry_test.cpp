// The method registry (core/include/sglab/registry.hpp) and its stability requirement (docs/math.md §10): no
// method returns NaN, Inf or a negative value in float or double over λ ∈ {0} ∪ [1e-8, 1e8],
// c ∈ [−1, 1] (±1 exactly and a rounding step past them) — except where the published form
// itself goes negative (`may_be_negative`, which must still be finite), and except points a
// method declares outside its domain (which must then say why). Enumerates the registry, so a new
// method is covered the moment it is registered.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

#include "sglab/clamped_cosine.hpp"
#include "sglab/registry_mp50.hpp"
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

// The mp50 evaluator a Method holds without naming the type: empty until set (calling it then
// throws, as an empty std::function does), the function it was given once set, shared by copies.
TEST(Registry, TheMp50EvaluatorIsTheFunctionItWasGiven) {
  Method m;
  EXPECT_FALSE(m.eval_mp50);
  const std::array<mp50, 2> args{mp50("0.1"), mp50(3)};
  EXPECT_THROW(eval_as<mp50>(m, std::span<const mp50>(args)), std::bad_function_call);
  m.eval_mp50 = [](std::span<const mp50> a) { return a[0] * a[1]; };
  const Method copy = m;
  ASSERT_TRUE(copy.eval_mp50);
  // 0.1 × 3 to 50 digits: not the double product (0.30000000000000004).
  EXPECT_EQ(eval_as<mp50>(copy, std::span<const mp50>(args)), mp50("0.3"));
  EXPECT_EQ(m.eval_mp50(args), mp50("0.3"));
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

// Rows inside every column's domain (benign points: tests/simd_test.cpp and simd_specular_test.cpp
// hold the vectorized kernels to their templates on the stiff ones).
std::vector<double> benign_rows(const Quantity& q) {
  constexpr int kRows = 3;
  std::vector<double> args;
  for (int k = 0; k < kRows; ++k)
    for (const auto& col : q.columns) {
      switch (col.kind) {
        case ColumnKind::sharpness: args.push_back(std::array{0.5, 10.0, 1e4}[k]); break;
        case ColumnKind::cosine: args.push_back(std::array{0.3, -0.2, 0.99}[k]); break;
        case ColumnKind::angle: args.push_back(std::array{0.3, 1.0, 2.5}[k]); break;
        case ColumnKind::mean_length:
        case ColumnKind::unit_interval: args.push_back(std::array{0.5, 0.2, 0.9}[k]); break;
        case ColumnKind::positive:
        case ColumnKind::nonnegative: args.push_back(std::array{0.5, 2.0, 1.0}[k]); break;
      }
    }
  return args;
}

// Every method's batch evaluators against its scalar evaluators, and against its batch path: a method
// that says it is vectorized runs a vectorized kernel (and is listed by simd::vectorized_methods()),
// within the last bits of its template; every other one is the scalar loop, to the bit. Its bound
// version (published constants) says and does the same.
template <class T>
void check_batch_path(const Quantity& q, const Method& m, const std::vector<double>& rows) {
  const std::size_t arity = q.columns.size(), n = rows.size() / arity;
  const std::vector<T> args(rows.begin(), rows.end());
  std::vector<T> out(n);
  const auto before = simd::vectorized_batch_calls();
  if constexpr (std::is_same_v<T, float>) m.batch_float(args, arity, out);
  else m.batch_double(args, arity, out);
  const bool vectorized = m.batch_path == BatchPath::vectorized;
  EXPECT_EQ(simd::vectorized_batch_calls() > before, vectorized) << batch_path_name(m.batch_path);
  const auto& listed = simd::vectorized_methods();
  EXPECT_EQ(std::find(listed.begin(), listed.end(), q.name + "/" + m.name) != listed.end(), vectorized);
  // A loose allowance (about 84 ulps in float, 4.5e4 in double): this test checks which path runs
  // and that it computes the method; tests/simd_test.cpp and simd_specular_test.cpp hold each
  // vectorized kernel to its template within its own, tighter count of ulps.
  // tokuyoshi2022 returns α·(term1 − term0), α ≈ 1182: the two paths' last-bit differences in each
  // term reach the result ×2α by design of λc (docs/math.md §3), which is how far apart they are
  // allowed to be (seen on AVX2 without AVX-512: 1.1e-3 relative at λ = 2, c = 0.2 in float).
  const bool cancels = m.name == "tokuyoshi2022" && (q.name == "clamped-cosine" || q.name == "vsgl-on-top");
  const double designed_gain = cancels ? 2 * Tokuyoshi2022Cosine::alpha : 1;
  const double tol = (std::is_same_v<T, float> ? 1e-5 : 1e-11) * designed_gain;
  for (std::size_t i = 0; i < n; ++i) {
    const T single = eval_as<T>(m, std::span<const T>(args.data() + i * arity, arity));
    if (vectorized) EXPECT_NEAR(out[i], single, tol * std::max(1.0, std::fabs(double(single)))) << "row " << i;
    else EXPECT_EQ(out[i], single) << "row " << i;
  }
}

// reference_value keeps each quantity's reference per row: the kept value is the reference
// method's own, bit for bit, on the first call and the next; rows equal in bytes but of two
// quantities are two keys; a quantity without a reference is refused.
TEST(Registry, KeptReferenceValuesAreTheReferenceMethodsOwn) {
  const Quantity& specular = *find_quantity("specular");
  const Quantity& diffuse = *find_quantity("clamped-cosine");
  const Quantity& hemispherical = *find_quantity("hemispherical");
  const std::vector<std::vector<double>> specular_rows{{0.2, 100, 0.8, 0.9, 3.141592653589793, 0.04},
                                                       {0.5, 10, 0.3, 0.5, 0, 0.04}};
  for (int pass = 0; pass < 2; ++pass) {
    for (const auto& row : specular_rows)
      EXPECT_EQ(reference_value(specular, row), specular.find(specular.reference_method)->eval_double(row))
          << "pass " << pass;
    for (const std::vector<double>& row : {std::vector<double>{3, 0.25}, std::vector<double>{0.01, -0.5}}) {
      EXPECT_EQ(reference_value(diffuse, row), diffuse.find(diffuse.reference_method)->eval_double(row));
      EXPECT_EQ(reference_value(hemispherical, row),
                hemispherical.find(hemispherical.reference_method)->eval_double(row));
    }
  }
  const double row[2] = {3, 0.25};
  EXPECT_NE(reference_value(diffuse, row), reference_value(hemispherical, row));
  for (const auto& q : quantities())
    if (q.reference_method.empty()) {
      EXPECT_THROW(reference_value(q, std::span<const double>(row)), std::invalid_argument) << q.name;
    }
}

TEST(Registry, BatchPathIsWhatTheBatchEvaluatorsRun) {
  int vectorized = 0;
  for (const auto& q : quantities()) {
    const std::vector<double> all = benign_rows(q);
    for (const auto& m : q.methods) {
      SCOPED_TRACE(q.name + "/" + m.name);
      std::vector<double> rows;  // the rows inside the method's own domain
      for (std::size_t i = 0; i < all.size(); i += q.columns.size()) {
        const std::span<const double> row(all.data() + i, q.columns.size());
        if (!row_error(q, m, row)) rows.insert(rows.end(), row.begin(), row.end());
      }
      // A reference (a quadrature) is the scalar loop: one row is enough to see it.
      if (m.name == q.reference_method) rows.resize(std::min(rows.size(), q.columns.size()));
      check_batch_path<float>(q, m, rows);
      check_batch_path<double>(q, m, rows);
      if (m.bind) {
        std::vector<double> published;
        for (const auto& p : m.parameters) published.push_back(p.published);
        const Method b = m.bind(published);
        EXPECT_EQ(b.batch_path, m.batch_path);
        check_batch_path<double>(q, b, rows);
      }
      vectorized += m.batch_path == BatchPath::vectorized;
    }
  }
  EXPECT_EQ(std::size_t(vectorized), simd::vectorized_methods().size());
}

// A diffuse method whose formula is written with selects (exportable: it instantiates on the
// tracing type) instantiates on SIMD lanes too, so it has a vectorized batch evaluator: a new one
// gets it from one kernel-table entry (docs/architecture.md, "Adding a method"). Listed here: the
// quantities whose every such method is vectorized.
TEST(Registry, EveryExportableDiffuseMethodIsVectorized) {
  for (const char* name : {"clamped-cosine", "hemispherical"}) {
    const Quantity* q = find_quantity(name);
    ASSERT_NE(q, nullptr);
    for (const auto& m : q->methods) {
      if (!m.trace) continue;
      EXPECT_EQ(m.batch_path, BatchPath::vectorized)
          << q->name << "/" << m.name << " runs its scalar template row by row: add it to the kernel table "
          << "(core/src/simd/simd_kernels.hpp, docs/simd.md)";
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
