// `sglab export` (shader/): the tracing type records the very formula sglab evaluates; the
// exported C, GLSL and HLSL compile (cc; glslang → SPIR-V → spirv-val) and, run (dlopen; Vulkan
// compute on lavapipe), match the quadrature reference within each method's stated tolerance; a
// refit constant set changes the literals and the executed values; bad input exits 2 with no
// output.
#include <cmath>
#include <cstring>
#include <map>

#include <gtest/gtest.h>

#include "emit.hpp"
#include "shader_export.hpp"
#include "sglab/registry.hpp"
#include "sglab/stiff_cases.hpp"
#include "test_util.hpp"
#include "toolchain.hpp"

namespace sglab {
namespace {

using shader::Language;

// The float inputs the trace is checked on: a log grid of λ (with 0 and the stiff extremes) ×
// the stiff cosines.
std::vector<float> check_rows() {
  std::vector<float> rows;
  std::vector<double> ls = stiff::sharpnesses(3);
  for (double l : {0.3, 0.7, 0.99, 1.0, 1.01, 1.5, 3.0, 9999.0, 10001.0, 1e12, 1e20, 1e30, 3.4e38}) ls.push_back(l);
  for (double l : ls)
    for (double c : stiff::cosines(16)) rows.insert(rows.end(), {float(l), float(c)});
  return rows;
}

bool same_float(float a, float b) {
  return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0 || (a == 0 && b == 0);
}

// A refit set for tokuyoshi2024's t(λ) (A…E moved by a few per cent) and Hill's c0.
ConstantSet refit_set() {
  ConstantSet set;
  const char* prov = "test set: tokuyoshi2024-t refit by hand";
  set.set({"tokuyoshi2024-t", "A", 2.9, prov});
  set.set({"tokuyoshi2024-t", "B", 16.5, prov});
  set.set({"tokuyoshi2024-t", "E", 80.25, prov});
  set.set({"hill-irradiance", "c0", 0.41, "test set: hill-irradiance c0"});
  return set;
}

// The traced graph, run by its interpreter, is sglab's float evaluation bit for bit: the trace
// recorded the same operations in the same order (the selects chose what the branches chose),
// on every exportable method, published and refit, including λ = 0, FLT_MAX and c past ±1.
TEST(Trace, InterpreterIsSglabFloatBitForBit) {
  const std::vector<float> rows = check_rows();
  const std::vector<std::string> names = shader::exportable_methods();
  ASSERT_GE(names.size(), 11u);  // 8 clamped-cosine (all but the reference and punctual-approx) + 3 hemispherical
  for (const ConstantSet& set : {ConstantSet{}, refit_set()})
    for (const auto& name : names) {
      const auto ref = shader::find_exportable(name);
      const shader::TracedMethod t = shader::trace_method(*ref.quantity, *ref.method, set);
      const Method bound = bind(*ref.method, set);
      long mismatches = 0;
      for (std::size_t k = 0; k + 1 < rows.size(); k += 2) {
        const std::span<const float> a(&rows[k], 2);
        const float want = bound.eval_float(a), got = t.evaluate(a);
        if (!same_float(want, got) && ++mismatches <= 3)
          ADD_FAILURE() << name << " at λ = " << a[0] << ", c = " << a[1] << ": traced " << got << ", sglab float " << want;
      }
      EXPECT_EQ(mismatches, 0) << name << (set.empty() ? " (published)" : " (refit)");
    }
}

// A branch on an input that is not a select cannot be traced: the method is refused by name.
TEST(Trace, ValueDependentBranchIsRefused) {
  TraceGraph g;
  TraceRecording rec(g);
  const Trace x = Trace::input(0);
  EXPECT_THROW((void)static_cast<bool>(x > 1.0), TraceBranchError);
  // A branch on constants only is decided while tracing.
  const Trace p = Trace::parameter(0, 2.0f);
  EXPECT_TRUE(static_cast<bool>(p > 1.0));
  // select records both sides; the interpreter picks per input.
  const Trace s = select(x > 1.0, [&] { return x * 2.0; }, [&] { return x - 5.0; });
  const float in0[1] = {3.f}, in1[1] = {0.5f};
  EXPECT_EQ(g.evaluate(s.id, in0), 6.f);
  EXPECT_EQ(g.evaluate(s.id, in1), -4.5f);
}

TEST(ShaderExport, NotExportableAndUnknownAreRefusedByName) {
  try {
    shader::find_exportable("clamped-cosine/reference");
    ADD_FAILURE() << "the quadrature reference was exported";
  } catch (const runner::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("clamped-cosine/reference cannot be exported"), std::string::npos) << e.what();
  }
  EXPECT_THROW(shader::find_exportable("clamped-cosine/no-such-method"), runner::InputError);
  EXPECT_THROW(shader::find_exportable("tokuyoshi2024"), runner::InputError);
}

// The measurement behind paper_tables/shader_export.md, on the quick grid: every exportable
// method in C, GLSL and HLSL compiles (and validates) and runs; its error against the reference
// is sglab float's within the method's tolerance, and it stays within the stated ulps of sglab
// float (ulps of the larger of the value and the reference at c = 1). Tolerances, with reasons:
//  • C: the same operations and the C library functions sglab's float path calls — 0 ulps and
//    the same error.
//  • GLSL/HLSL: lavapipe's exp/log/sqrt/division and the written helpers (sglab_expm1: Taylor
//    series below |x| = 0.5; sglab_erf/erfc: Numerical Recipes' erfcc, 1.2e-7 relative) differ
//    from glibc's by a few ulps (measured ≤ 8): ≤ 16 ulps, error within 1e-5 of D(λ, 1) of sglab
//    float's — except
//      tokuyoshi2022 (clamped-cosine), whose two terms cancel by design (×2364: its λc trades
//      float error for approximation error, Tokuyoshi 2022): ≤ 2364·16 ulps, error within 1e-3;
//      meder (clamped-cosine), 32.7·H − 31.7·H (the cancellation loses ~5 bits): ≤ 32·16 ulps…
//      measured 448, so ≤ 1024, error within 1e-4.
TEST(ShaderExport, EveryMethodCompilesRunsAndMatchesTheReference) {
  if (!shader::vulkan_available()) GTEST_SKIP() << "no Vulkan device (install mesa-vulkan-drivers)";
  cli::shader_export::Options o;
  o.quick = true;
  const auto result = cli::shader_export::compute(o);
  std::printf("device: %s\n", result.device.c_str());
  std::map<std::string, cli::shader_export::Row> own;
  for (const auto& r : result.rows)
    if (r.evaluator == "sglab float") own[r.method] = r;
  EXPECT_GE(own.size(), 11u);  // the exportable methods (punctual-approx is not: a branch)
  for (const auto& r : result.rows) {
    if (r.evaluator == "sglab float") continue;
    const auto& f = own.at(r.method);
    std::printf("%-40s %-5s instr %5ld  max error %.3e (sglab float %.3e)  ulps %.0f  stiff neg %ld nan %ld\n", r.method.c_str(),
                r.evaluator.c_str(), r.instructions, r.max_error, f.max_error, r.max_ulps, r.stiff_negatives, r.stiff_non_finite);
    ASSERT_TRUE(r.compiles) << r.method << " " << r.evaluator << ": " << r.error;
    const bool cancels = r.method == "clamped-cosine/tokuyoshi2022";
    const bool meder = r.method == "clamped-cosine/meder";
    const bool c = r.evaluator == "c";
    const double error_tol = c ? 0 : cancels ? 1e-3 : meder ? 1e-4 : 1e-5;
    const double ulps_tol = c ? 0 : cancels ? 2364 * 16 : meder ? 1024 : 16;
    EXPECT_LE(r.max_error, f.max_error + error_tol) << r.method << " " << r.evaluator;
    EXPECT_LE(r.max_ulps, ulps_tol) << r.method << " " << r.evaluator;
    EXPECT_EQ(r.grid_non_finite, f.grid_non_finite) << r.method << " " << r.evaluator;
    // cosine-lobe-sg on lavapipe: NaN at λ = FLT_MAX for the six stiff cosines at c ≥ 1 − 2⁻²⁴
    // (the C and sglab float are finite there; lavapipe's arithmetic at the top of the float
    // range, cause not isolated — the table reports it).
    const long nan_tol = r.method == "clamped-cosine/cosine-lobe-sg" && r.evaluator != "c" ? 6 : 0;
    EXPECT_LE(r.stiff_non_finite, f.stiff_non_finite + nan_tol) << r.method << " " << r.evaluator;
    if (!shader::find_exportable(r.method).method->may_be_negative) {
      EXPECT_EQ(r.stiff_negatives, 0) << r.method << " " << r.evaluator;
    }
  }
}

// A refit constant set: the exported literals and the provenance change, and so do the values
// the shader computes — to sglab float's with the same set.
TEST(ShaderExport, RefitConstantsChangeLiteralsAndValues) {
  if (!shader::vulkan_available()) GTEST_SKIP() << "no Vulkan device (install mesa-vulkan-drivers)";
  const auto ref = shader::find_exportable("clamped-cosine/tokuyoshi2024");
  const ConstantSet set = refit_set();
  const shader::TracedMethod published = shader::trace_method(*ref.quantity, *ref.method, ConstantSet{});
  const shader::TracedMethod refit = shader::trace_method(*ref.quantity, *ref.method, set);
  const std::string src_pub = shader::emit(std::span(&published, 1), Language::glsl, "test");
  const std::string src_fit = shader::emit(std::span(&refit, 1), Language::glsl, "test");
  EXPECT_NE(src_pub.find("const float c_A = 2.7360833f;"), std::string::npos) << src_pub;
  EXPECT_NE(src_fit.find("const float c_A = 2.9f;"), std::string::npos) << src_fit;
  EXPECT_NE(src_fit.find("const float c_E = 80.25f;"), std::string::npos) << src_fit;
  EXPECT_NE(src_fit.find("test set: tokuyoshi2024-t refit by hand"), std::string::npos);
  EXPECT_NE(src_pub.find("published: Tokuyoshi et al. 2024"), std::string::npos);

  std::vector<float> rows;
  for (double l : {0.05, 0.5, 2.0, 8.0, 30.0})
    for (double c : {-0.6, -0.2, 0.1, 0.5}) rows.insert(rows.end(), {float(l), float(c)});
  shader::VulkanCompute gpu;
  auto run = [&](const shader::TracedMethod& t, const std::string& src) {
    return shader::run_compute(gpu, shader::compile_to_spirv(shader::compute_shader_source(src, t, Language::glsl), Language::glsl),
                               rows, 2);
  };
  const std::vector<float> v_pub = run(published, src_pub), v_fit = run(refit, src_fit);
  const Method bound = bind(*ref.method, set);
  double moved = 0;
  for (std::size_t k = 0; k < v_fit.size(); ++k) {
    const std::span<const float> a(&rows[2 * k], 2);
    const float want = bound.eval_float(a);
    EXPECT_NEAR(v_fit[k], want, 1e-5 * std::fabs(want) + 1e-6) << "λ = " << a[0] << ", c = " << a[1];
    moved = std::max(moved, std::fabs(double(v_fit[k]) - double(v_pub[k])) / (std::fabs(double(v_pub[k])) + 1e-6));
  }
  EXPECT_GT(moved, 1e-3) << "the refit constants did not change the executed values";
}

class ExportCommand : public test::TempDirTest {};

TEST_F(ExportCommand, WritesPasteableSourceAndRefusesBadInput) {
  auto r = sglab("export clamped-cosine/tokuyoshi2024 hemispherical/meder --lang hlsl --out x.hlsl");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string src = test::read_file(path("x.hlsl"));
  EXPECT_NE(src.find("float sglab_clamped_cosine_tokuyoshi2024(float sharpness, float cosine)"), std::string::npos) << src;
  EXPECT_NE(src.find("float sglab_hemispherical_meder(float sharpness, float cosine)"), std::string::npos);
  EXPECT_NE(src.find("float sglab_erfc(float x)"), std::string::npos);
  r = sglab("export clamped-cosine/sglab --lang c");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("#include <math.h>"), std::string::npos);
  EXPECT_NE(r.out.find("erfcf("), std::string::npos);

  expect_bad_input(sglab("export clamped-cosine/nope --lang glsl --out o.glsl"), "unknown method", "unknown method 'clamped-cosine/nope'",
                   {"o.glsl"});
  expect_bad_input(sglab("export clamped-cosine/reference --lang glsl --out o.glsl"), "not exportable",
                   "clamped-cosine/reference cannot be exported", {"o.glsl"});
  expect_bad_input(sglab("export clamped-cosine/sglab --lang glsl --constants missing.json --out o.glsl"), "bad constant set",
                   "missing.json", {"o.glsl"});
  expect_bad_input(sglab("export clamped-cosine/sglab --lang cuda --out o.glsl"), "bad language", "cuda", {"o.glsl"});
  r = sglab("export clamped-cosine/nope --lang glsl");
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
}

}  // namespace
}  // namespace sglab
