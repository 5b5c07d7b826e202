// The environment-lighting bases (fit/envmap_basis.hpp, sglab/sh.hpp) and `sglab envmap bases`
// (experiments/envmap_bases.hpp): SH values against Sloan's closed forms, SH projection of a map
// that is an SH function, SH irradiance of one SG light against the exact clamped-cosine
// integral, NNLS against brute-force enumeration of the active sets, NNLS recovering a fixed-lobe
// map's amplitudes, the vMF EM honouring its iteration cap, and the tables' rows.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>

#include <Eigen/Cholesky>
#include <boost/math/quadrature/gauss.hpp>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "atomic_file.hpp"
#include "envmap.hpp"
#include "envmap_bases.hpp"
#include "envmap_basis.hpp"
#include "envmap_data.hpp"
#include "envmap_sparse.hpp"
#include "input_error.hpp"
#include "sglab/reference.hpp"
#include "sglab/render/environment.hpp"
#include "sglab/sh.hpp"
#include "test_util.hpp"

namespace {

using sglab::Vec3;
using V = Vec3<double>;
namespace fit = sglab::fit;

// An SH function's texel means (8 × 8 points per texel) as a map.
sglab::EnvMap sh_map(int order, const std::vector<std::array<double, 3>>& c, int width) {
  fit::EnvBasisFit f;
  f.sh_order = order;
  f.sh = c;
  sglab::EnvMap m{width, width / 2, std::vector<std::array<float, 3>>(std::size_t(width) * std::size_t(width / 2))};
  for (int v = 0; v < m.height; ++v)
    for (int u = 0; u < m.width; ++u) {
      std::array<double, 3> s{0, 0, 0};
      for (int sy = 0; sy < 8; ++sy)
        for (int sx = 0; sx < 8; ++sx) {
          const auto x = f.radiance(sglab::envmap_direction(m.width, m.height, u + (sx + 0.5) / 8, v + (sy + 0.5) / 8));
          for (int k = 0; k < 3; ++k) s[std::size_t(k)] += x[std::size_t(k)] / 64;
        }
      for (int k = 0; k < 3; ++k) m.texels[std::size_t(v * m.width + u)][std::size_t(k)] = float(s[std::size_t(k)]);
    }
  return m;
}

}  // namespace

// Sloan 2008, "Stupid spherical harmonics tricks", Appendix A2 (no Condon–Shortley phase).
TEST(Sh, ValuesMatchClosedFormsUpToOrderTwo) {
  std::mt19937_64 rng(7);
  std::printf("seed 7\n");
  std::normal_distribution<double> n;
  for (int trial = 0; trial < 20; ++trial) {
    const V w = V(n(rng), n(rng), n(rng)).normalized();
    double y[9];
    sglab::sh_eval(2, w, y);
    const double x = w(0), yy = w(1), z = w(2);
    const double expect[9] = {0.28209479177387814,
                              0.4886025119029199 * yy,
                              0.4886025119029199 * z,
                              0.4886025119029199 * x,
                              1.0925484305920792 * x * yy,
                              1.0925484305920792 * yy * z,
                              0.31539156525252005 * (3 * z * z - 1),
                              1.0925484305920792 * x * z,
                              0.5462742152960396 * (x * x - yy * yy)};
    for (int k = 0; k < 9; ++k) EXPECT_NEAR(y[k], expect[k], 1e-14) << "index " << k;
  }
}

// Orthonormality, so projection is meaningful at every order: ∫ Y_i Y_j dω by a product rule
// exact for these integrands (20-point Gauss–Legendre in z = cos θ: Y_i Y_j with equal |m| is
// (1 − z²)^m times a polynomial, degree ≤ 16; 32 equispaced φ: exact for cos/sin of degree < 32).
TEST(Sh, OrthonormalUpToOrderEight) {
  using G = boost::math::quadrature::gauss<double, 20>;
  const int K = sglab::sh_count(8), P = 32;
  std::vector<double> gram(std::size_t(K * K), 0.0), y(static_cast<std::size_t>(K));
  for (std::size_t k = 0; k < G::abscissa().size(); ++k)
    for (int sign : {1, -1}) {
      const double z = sign * G::abscissa()[k], r = std::sqrt(1 - z * z);
      for (int p = 0; p < P; ++p) {
        const double phi = 2 * M_PI * p / P, w = G::weights()[k] * 2 * M_PI / P;
        sglab::sh_eval(8, V(r * std::cos(phi), r * std::sin(phi), z), y.data());
        for (int i = 0; i < K; ++i)
          for (int j = 0; j <= i; ++j) gram[std::size_t(i * K + j)] += w * y[std::size_t(i)] * y[std::size_t(j)];
      }
    }
  for (int i = 0; i < K; ++i)
    for (int j = 0; j <= i; ++j) EXPECT_NEAR(gram[std::size_t(i * K + j)], i == j ? 1.0 : 0.0, 1e-12) << i << "," << j;
}

// A map that is an order-2 SH function (texel means) projects back onto its coefficients, and
// onto zero above order 2: the projection is exact but for the texel quadrature, whose error on
// a function of bandwidth l is O(l(l + 1) δ²/12) of its coefficients (δ = π/H; 64 rows: 1.4e-3),
// asserted at δ² max|c|.
TEST(Sh, ProjectionOfALowOrderShMapIsExactToQuadraturePrecision) {
  std::mt19937_64 rng(11);
  std::printf("seed 11\n");
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<std::array<double, 3>> c(9);
  double cmax = 0;
  for (auto& x : c)
    for (auto& v : x) v = u(rng), cmax = std::max(cmax, std::abs(v));
  c[0] = {3, 3, 3};  // keep it mostly positive, as radiance is (the projection does not need it)
  cmax = 3;
  const sglab::EnvMap map = sh_map(2, c, 128);
  const auto fits = fit::find_envmap_basis("sh")->fit(map, {4}, "", {});
  const double delta = M_PI / map.height, tol = delta * delta * cmax;
  double worst = 0;
  for (int k = 0; k < sglab::sh_count(4); ++k)
    for (int ch = 0; ch < 3; ++ch) {
      const double expect = k < 9 ? c[std::size_t(k)][std::size_t(ch)] : 0.0;
      worst = std::max(worst, std::abs(fits[0].sh[std::size_t(k)][std::size_t(ch)] - expect));
      EXPECT_NEAR(fits[0].sh[std::size_t(k)][std::size_t(ch)], expect, tol) << "coefficient " << k << " channel " << ch;
    }
  std::printf("worst coefficient error %.3g (bound %.3g)\n", worst, tol);
  EXPECT_EQ(fits[0].floats, 75);
}

// SH irradiance (order 8) of one SG light against sglab's exact clamped-cosine integral
// (clamped_cosine_reference): the light's band energy beyond l = 8 is ~e^{−l²/(2λ)} (λ = 4:
// < 1e-4), so what remains is the map's texel quadrature, O(δ²) with δ = π/64 (2.4e-3), asserted
// at 4e-3 of the peak. Order 2 (9 coefficients, Ramamoorthi & Hanrahan's choice) is within their
// few per cent for such a broad light; asserted at 3 %.
TEST(Sh, IrradianceOfOneSgLightMatchesTheClampedCosineReference) {
  sglab::SgLight l;
  l.axis = V(0.3, -0.5, 0.8).normalized();
  l.sharpness = 4;
  l.amplitude = {1, 1, 1};
  const sglab::EnvMap map = sglab::rasterize_mixture({l}, 128, 64, 8);
  const auto fits = fit::find_envmap_basis("sh")->fit(map, {2, 8}, "", {});
  const auto normals = fit::envmap_detail::fibonacci_axes(200);
  const double peak = sglab::clamped_cosine_reference(4.0, 1.0) / M_PI;
  double worst2 = 0, worst8 = 0;
  for (const auto& n : normals) {
    const double exact = sglab::clamped_cosine_reference(4.0, std::clamp(l.axis.dot(n), -1.0, 1.0)) / M_PI;
    worst2 = std::max(worst2, std::abs(fits[0].diffuse(n)[0] - exact) / peak);
    worst8 = std::max(worst8, std::abs(fits[1].diffuse(n)[0] - exact) / peak);
  }
  std::printf("worst irradiance error / peak: L=2 %.3g, L=8 %.3g\n", worst2, worst8);
  EXPECT_LT(worst8, 4e-3);
  EXPECT_LT(worst2, 3e-2);
  // The SG bases' diffuse is that same reference, lobe by lobe.
  fit::EnvBasisFit sg;
  sg.mixture = {l};
  EXPECT_NEAR(sg.diffuse(normals[3])[1], sglab::clamped_cosine_reference(4.0, l.axis.dot(normals[3])) / M_PI, 1e-12);
}

// Lawson–Hanson against the minimum over every active set of the unconstrained solutions that
// are feasible (the exact NNLS minimiser of a strictly convex quadratic is one of them).
TEST(Nnls, MatchesBruteForceOverActiveSets) {
  std::mt19937_64 rng(3);
  std::printf("seed 3\n");
  std::normal_distribution<double> n;
  for (int trial = 0; trial < 50; ++trial) {
    const int m = 6;
    Eigen::MatrixXd A(10, m);
    Eigen::VectorXd b(10);
    for (int i = 0; i < 10; ++i) {
      b(i) = n(rng);
      for (int j = 0; j < m; ++j) A(i, j) = n(rng);
    }
    const Eigen::MatrixXd H = A.transpose() * A;
    const Eigen::VectorXd g = A.transpose() * b;
    auto cost = [&](const Eigen::VectorXd& x) { return 0.5 * x.dot(H * x) - g.dot(x); };
    double best = 0;  // x = 0
    for (int mask = 1; mask < (1 << m); ++mask) {
      std::vector<int> idx;
      for (int j = 0; j < m; ++j)
        if (mask >> j & 1) idx.push_back(j);
      Eigen::MatrixXd Hs(idx.size(), idx.size());
      Eigen::VectorXd gs(idx.size());
      for (std::size_t a = 0; a < idx.size(); ++a) {
        gs(Eigen::Index(a)) = g(idx[a]);
        for (std::size_t c = 0; c < idx.size(); ++c) Hs(Eigen::Index(a), Eigen::Index(c)) = H(idx[a], idx[c]);
      }
      const Eigen::VectorXd s = Hs.ldlt().solve(gs);
      if (s.minCoeff() < 0) continue;
      Eigen::VectorXd x = Eigen::VectorXd::Zero(m);
      for (std::size_t a = 0; a < idx.size(); ++a) x(idx[a]) = s(Eigen::Index(a));
      best = std::min(best, cost(x));
    }
    const Eigen::VectorXd x = fit::nnls(H, g);
    EXPECT_GE(x.minCoeff(), 0.0);
    EXPECT_NEAR(cost(x), best, 1e-9 * (1 + std::abs(best))) << "trial " << trial;
  }
}

// NNLS and least squares recover the amplitudes of a map that is a fixed-lobe mixture (its own
// Fibonacci axes and sharpness, some lobes dark): texel means (8 × 8 points) of a 128 × 64 map; the
// right-hand side's 2 × 2 sub-texel quadrature is O(δ²) (δ = π/64) off the analytic Gram matrix's
// integrals, amplified by the Gram matrix's conditioning (neighbouring lobes overlap at
// λ = N ln2/2): asserted at 2 % of the largest amplitude.
TEST(SgFixed, SolversRecoverAFixedLobeMapsAmplitudes) {
  std::mt19937_64 rng(5);
  std::printf("seed 5\n");
  std::uniform_real_distribution<double> u(0, 2);
  // N = 16 (λ = 5.5: neighbours overlap, the product integral's 1 − e^{−2r} is ≈ 1) and N = 3
  // (λ = 1.04, broad lobes 120° apart: r = ‖λξ_j + λξ_k‖ ≈ λ, where 1 − e^{−2r} is 0.88, so the
  // Gram matrix's closed form is checked where each of its factors matters); both solvers.
  for (const int N : {16, 3}) {
    const auto axes = fit::envmap_detail::fibonacci_axes(N);
    const double lambda = 0.5 * N * std::log(2.0);
    sglab::SgMixture m;
    for (int j = 0; j < N; ++j) {
      sglab::SgLight l;
      l.axis = axes[std::size_t(j)];
      l.sharpness = lambda;
      l.amplitude = j % 4 == 1 ? std::array<double, 3>{0, 0, 0} : std::array<double, 3>{u(rng), u(rng), u(rng)};
      m.push_back(l);
    }
    const sglab::EnvMap map = sglab::rasterize_mixture(m, 128, 64, 8);
    for (const char* solver : {"nnls", "ls"}) {
      const auto fits = fit::find_envmap_basis("sg-fixed")->fit(map, {N}, solver, {});
      ASSERT_EQ(fits[0].mixture.size(), std::size_t(N));
      double worst = 0;
      for (int j = 0; j < N; ++j) {
        EXPECT_NEAR(fits[0].mixture[std::size_t(j)].sharpness, lambda, 1e-12);
        for (int c = 0; c < 3; ++c) {
          const double e = std::abs(fits[0].mixture[std::size_t(j)].amplitude[std::size_t(c)] -
                                    m[std::size_t(j)].amplitude[std::size_t(c)]);
          worst = std::max(worst, e);
          EXPECT_LT(e, 0.04) << "N " << N << " " << solver << " lobe " << j << " channel " << c;
        }
      }
      std::printf("N %d %s: worst amplitude error %.3g (amplitudes up to 2)\n", N, solver, worst);
      EXPECT_EQ(fits[0].floats, 3 * N);
    }
  }
}

// `--max-iterations` reaches the EM: a cap of 2 stops it after 2 iterations, unconverged.
TEST(VmfEm, HonoursItsIterationCap) {
  const sglab::EnvMap map = sglab::rasterize_mixture(sglab::render::synthetic_mixture(), 64, 32, 2);
  fit::EnvFitOptions o;
  o.lobes = 8;
  o.em_max_iterations = 2;
  const auto r = fit::fit_envmap_vmf_em(map, o);
  EXPECT_EQ(r.iterations, 2);
  EXPECT_FALSE(r.converged);
}

namespace eb = sglab::experiments::envmap_bases;

// `sglab envmap bases` as a library in a temporary directory: small_options(width) writes the
// synthetic mixture there as a width × width/2 map mix.exr and gives quick options that read it as
// environment `mix` and write their tables beside it.
class EnvmapBases : public sglab::test::TempDirTest {
 protected:
  eb::Options small_options(int width) const {
    sglab::runner::write_file_atomically(
        path("mix.exr"), sglab::render::encode_environment(
                             sglab::rasterize_mixture(sglab::render::synthetic_mixture(), width, width / 2, 2)));
    eb::Options o;
    o.envs = {"mix=" + path("mix.exr").string()};
    o.quick = true;
    o.sphere_res = 6;
    o.normals = 16;
    o.tables_dir = dir_.string();
    return o;
  }
};

// The rows measured beside the fits (a thread of the idle class, one row at a time) against the
// same rows measured each right after its fit on the calling thread: every value the same bits,
// whichever thread measured a row. The fixed-lobe fits (bit-for-bit the same fits in both runs; the
// SH projection's parallel sum and Ceres's per-thread sums are not), on a plain and a resolved map
// (its sparse quadrature). One roughness of the specular layer (its per-roughness values are
// compared as a vector all the same): with three the test took 1.4 times as long.
TEST_F(EnvmapBases, RowsMeasuredBesideTheFitsAreTheInlineRowsBitForBit) {
  eb::Options o = small_options(128);
  o.envs.push_back("res=" + path("mix.exr").string());
  o.resolve = {"res"};
  o.bases = {"sg-fixed"};
  o.width = 32;
  o.roughness = {0.3};
  o.measure_beside_fits = false;
  const eb::Result inline_rows = eb::compute(o);
  o.measure_beside_fits = true;
  const eb::Result beside = eb::compute(o);
  ASSERT_EQ(beside.environments.size(), inline_rows.environments.size());
  for (std::size_t e = 0; e < beside.environments.size(); ++e) {
    const auto &x = beside.environments[e].rows, &y = inline_rows.environments[e].rows;
    ASSERT_EQ(x.size(), y.size());
    ASSERT_GT(x.size(), 0u);
    for (std::size_t k = 0; k < x.size(); ++k) {
      SCOPED_TRACE(x[k].basis + " " + x[k].variant + " " + std::to_string(x[k].size));
      EXPECT_EQ(x[k].basis + x[k].variant, y[k].basis + y[k].variant);
      EXPECT_EQ(x[k].size, y[k].size);
      EXPECT_EQ(x[k].map_error, y[k].map_error);
      EXPECT_EQ(x[k].diffuse_error, y[k].diffuse_error);
      EXPECT_EQ(x[k].engine_diffuse_error, y[k].engine_diffuse_error);
      EXPECT_EQ(x[k].specular_error, y[k].specular_error);
    }
  }
}

// The comparison's rows on a small map: every basis and variant at every quick size, and bad
// options are input errors.
TEST_F(EnvmapBases, TablesHaveEveryBasisAndBadOptionsAreInputErrors) {
  eb::Options o = small_options(32);
  o.bases = {"sh", "sg-fixed"};
  const eb::Result r = eb::compute(o);
  ASSERT_EQ(r.environments.size(), 1u);
  // sh L ∈ {1, 2, 3, 4}, sg-fixed N ∈ {4, 8, 16} × 3 solvers (--quick: N ≤ 16).
  EXPECT_EQ(r.environments[0].rows.size(), 4u + 9u);
  for (const auto& row : r.environments[0].rows) {
    EXPECT_TRUE(std::isfinite(row.map_error));
    EXPECT_EQ(row.specular_error.size(), 3u);
  }
  const eb::Tables t = eb::tables(r);
  EXPECT_NE(t.markdown.find("| mix | sg-fixed nnls | N=16 | 48 |"), std::string::npos);
  o.bases = {"no-such-basis"};
  EXPECT_THROW(eb::compute(o), sglab::runner::InputError);
  o.bases = {"sh"};
  o.resolve = {"no-such-env"};  // --resolve names an --env
  try {
    eb::compute(o);
    ADD_FAILURE() << "--resolve no-such-env accepted";
  } catch (const sglab::runner::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-env"), std::string::npos) << e.what();
  }
  o.resolve = {"mix"};
  for (const double tau : {0.0, -1.0}) {  // τ ≤ 0
    o.resolve_tolerance = tau;
    try {
      eb::compute(o);
      ADD_FAILURE() << "--resolve-tolerance " << tau << " accepted";
    } catch (const sglab::runner::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fmt::format("--resolve-tolerance {}", tau)), std::string::npos) << e.what();
    }
  }
  o.resolve = {};
  o.resolve_tolerance = 0.01;
  o.bases = {};
  o.envs = {"noequals"};
  EXPECT_THROW(eb::compute(o), sglab::runner::InputError);
}

// The free-lobe fit on the generated sky (512 × 256, a 2° sun carrying ~87 % of the map's
// weighted L2²) at N = 16 is fitted on the 64 × 32 level, where the sun is one texel and so held
// by one lobe: one Gaussian on a uniform disk left it at relative L2 0.234 (0.231 at N = 32).
// Seeding the weakest lobes on the brightest full-map texels (seed_bright_lobes) measured 0.1715
// (kmeans, seed 1), as at N = 32 in nearly twice the time; asserted below 0.20, the margin for
// thread-count differences in the LM runs. (On a 256 × 128 sky the fit reaches 0.18 without the
// seeding, and the check would not see it gone.) At most 30 LM iterations a level here: 0.172 (the
// default 60 added 0.6 CPU s for 0.1715; 20 left 0.227).
TEST(SgFree, SunSizedFeatureImprovesOnTheOneLobeFloor) {
  sglab::render::SkyOptions so;
  const sglab::EnvMap sky = sglab::render::make_sky(so);
  fit::EnvFitOptions o;
  o.lobes = 16;
  o.init = "kmeans";
  o.max_iterations = 30;
  std::printf("seed %u\n", o.seed);
  const auto r = fit::fit_envmap_ceres(sky, o);
  std::printf("relative error %.4g (fitted on %d×%d)\n", r.error.relative, r.fit_width, r.fit_height);
  EXPECT_EQ(r.fit_width, 64);
  EXPECT_LT(r.error.relative, 0.20);
}

// vMF EM's working level is the finest whose texel count × N is at most 2^20 (envmap.hpp), the
// rule written out here: on a 256 × 128 map (32768 texels) N = 32 is fitted on the full map and
// N = 64 on 128 × 64 (1 EM iteration: only the level is checked). On the generated sky reduced
// to 128 × 64, N = 64 is fitted on the whole map; under the old dense-Jacobian level rule it was
// fitted on 64 × 32, where the 2° sun is below a texel, and its map error was 0.62 against 0.25 at
// N = 32 (paper_tables before this rule). Measured now 0.241 after the default cap of 200 EM
// iterations, 0.240 after 50 and 0.239 after the 10 run here (seed 1); asserted below 0.30.
TEST(VmfEm, FitsTheFinestLevelWithinItsCostGuard) {
  const sglab::EnvMap mix = sglab::rasterize_mixture(sglab::render::synthetic_mixture(), 256, 128, 2);
  fit::EnvFitOptions o;
  o.init = "kmeans";
  o.em_max_iterations = 1;
  std::printf("seed %u\n", o.seed);
  for (const int n : {32, 64}) {
    o.lobes = n;
    int width = mix.width, height = mix.height;
    while (double(width) * double(height) * n > 1048576.0) width /= 2, height /= 2;
    const auto r = fit::fit_envmap_vmf_em(mix, o);
    EXPECT_EQ(r.fit_width, width) << "N = " << n;
    EXPECT_EQ(r.fit_height, height) << "N = " << n;
  }
  sglab::EnvMap sky = sglab::render::make_sky(sglab::render::SkyOptions{});
  while (sky.width > 128) sky = sglab::downsample_envmap(sky);
  o.lobes = 64;
  o.em_max_iterations = 10;
  const auto r = fit::fit_envmap_vmf_em(sky, o);
  std::printf("sky 128×64, N = 64: relative error %.4g on %d×%d\n", r.error.relative, r.fit_width, r.fit_height);
  EXPECT_EQ(r.fit_width, 128);
  EXPECT_LT(r.error.relative, 0.30);
}

// The exact diffuse of an SG fit at many normals (diffuse_at, the factors cached across fits with
// the same lobes) against Σ_j μ_j clamped_cosine_reference(λ_j, ξ_j·n)/π written out here: equal
// to the last bit, on a first call, on a second call with other amplitudes (cached factors, one
// lobe now at zero amplitude, one newly non-zero), after the lobes change (a new entry) and for the
// first lobes again (their entry kept).
TEST(EnvBasisFit, DiffuseAtManyNormalsMatchesTheClampedCosineReferencePerLobe) {
  const auto normals = fit::envmap_detail::fibonacci_axes(40);
  const auto axes = fit::envmap_detail::fibonacci_axes(6);
  fit::EnvBasisFit f;
  for (int j = 0; j < 6; ++j) {
    sglab::SgLight l;
    l.axis = axes[std::size_t(j)];
    l.sharpness = 0.5 + 7.0 * j;
    l.amplitude = j == 2 ? std::array<double, 3>{0, 0, 0} : std::array<double, 3>{1.0 + j, 0.5, 0.25 * j};
    f.mixture.push_back(l);
  }
  auto expected = [&](const fit::EnvBasisFit& g, const V& n) {
    std::array<double, 3> out{0, 0, 0};
    for (const auto& l : g.mixture) {
      const double d = sglab::clamped_cosine_reference(l.sharpness, std::clamp(l.axis.dot(n), -1.0, 1.0)) / M_PI;
      for (int c = 0; c < 3; ++c) out[std::size_t(c)] += l.amplitude[std::size_t(c)] * d;
    }
    return out;
  };
  fit::LobeDiffuseCache cache;
  auto check = [&](const fit::EnvBasisFit& g, const char* what) {
    const auto got = fit::diffuse_at(g, normals, cache);
    ASSERT_EQ(got.size(), normals.size());
    for (std::size_t k = 0; k < normals.size(); ++k) {
      EXPECT_EQ(got[k], expected(g, normals[k])) << what << ", normal " << k;
      EXPECT_EQ(got[k], g.diffuse(normals[k])) << what << ", normal " << k;
    }
  };
  check(f, "first call");
  fit::EnvBasisFit other = f;
  other.mixture[1].amplitude = {0, 0, 0};
  other.mixture[2].amplitude = {3, 2, 1};
  check(other, "cached factors, other amplitudes");
  other.mixture[4].sharpness *= 2;
  check(other, "a lobe changed");
  check(f, "the first lobes again (an older entry)");
  EXPECT_EQ(cache.entries.size(), 2u);
  // Eviction is by last use: f's entry, among the oldest but used again once the cache is full,
  // outlives the two insertions that follow (by insertion order it would be the first to go).
  auto has = [&](const fit::EnvBasisFit& g) {
    return std::any_of(cache.entries.begin(), cache.entries.end(), [&](const fit::LobeDiffuseCache::Entry& e) {
      if (e.lobes.size() != g.mixture.size()) return false;
      for (std::size_t j = 0; j < e.lobes.size(); ++j)
        if (e.lobes[j].first != g.mixture[j].axis || e.lobes[j].second != g.mixture[j].sharpness) return false;
      return true;
    });
  };
  fit::EnvBasisFit filler = f;
  for (std::size_t i = 0; i + 2 < fit::LobeDiffuseCache::kEntries; ++i) {
    filler.mixture[0].sharpness = 100.0 + double(i);
    (void)fit::diffuse_at(filler, normals, cache);
  }
  ASSERT_EQ(cache.entries.size(), fit::LobeDiffuseCache::kEntries);
  check(f, "the first lobes, before the cache overflows");
  for (int i = 0; i < 2; ++i) {
    filler.mixture[0].sharpness = 200.0 + i;
    (void)fit::diffuse_at(filler, normals, cache);
  }
  EXPECT_EQ(cache.entries.size(), fit::LobeDiffuseCache::kEntries);
  EXPECT_TRUE(has(f)) << "the most recently used entry was evicted";
  EXPECT_FALSE(has(other)) << "the least recently used entry was kept";
}

// The `sg-free` basis (one ladder fit) on the synthetic 4-lobe mixture at 128×64: the map error
// of every N, recomputed here from the representation's 4 × 4-point texel means, is at most that
// at N/2, and a rung that kept its predecessor says so (zero-amplitude lobes counted). At most 10
// LM iterations a level (the default 60 took twice as long), where both branches of the guard
// occur: N = 8 keeps its own fit (0.003533 after 0.003561 at N = 4) and N = 16 keeps N = 8's
// lobes (its own fit: 0.004194, which without the guard fails the test).
TEST(SgFree, BasisErrorDoesNotGrowWithN) {
  const sglab::EnvMap map = sglab::rasterize_mixture(sglab::render::synthetic_mixture(), 128, 64, 8);
  fit::EnvBasisOptions o;
  o.max_iterations = 10;
  std::printf("seed %u\n", o.seed);
  const auto fits = fit::find_envmap_basis("sg-free")->fit(map, {4, 8, 16}, "", o);
  ASSERT_EQ(fits.size(), 3u);
  double previous = 1;
  for (const auto& f : fits) {
    const double e = sglab::envmap_error(map, sglab::rasterize_mixture(f.mixture, map.width, map.height, 4)).relative;
    std::printf("N = %d: map error %.6g, kept %d, zero lobes %d, %d LM iterations on %d×%d\n", f.size, e, f.kept_lobes,
                f.zero_lobes, f.iterations, f.fit_width, f.fit_height);
    EXPECT_LE(e, previous) << "N = " << f.size;
    EXPECT_GE(f.zero_lobes, f.kept_lobes > 0 ? f.size - f.kept_lobes : 0) << "N = " << f.size;
    EXPECT_GT(f.iterations, 0);
    previous = e;
  }
}

// The floor of one lobe per sun (kOneLobeDiskFloor): a uniform disk of angular radius R on the
// sphere against μe^{λ(cos θ − 1)} about its centre, μ optimal for each λ (the projection:
// residual² = ‖D‖² − ⟨D, G⟩²/‖G‖²), λ by golden-section search; the inner products by Gauss–Legendre
// quadrature in θ (axisymmetric). The planar closed form is √(1 − max_t 2(1 − e^{−t})²/t); on the
// sphere the floor differs by O(R²).
TEST(OneLobeDiskFloor, MatchesQuadratureOnTheSphere) {
  using G = boost::math::quadrature::gauss<double, 30>;
  for (const double diameter_deg : {0.53, 2.0}) {
    const double R = diameter_deg / 2 * M_PI / 180;
    const double disk2 = 2 * M_PI * (1 - std::cos(R));
    auto share = [&](double lambda) {  // ⟨D, G⟩²/(‖G‖² ‖D‖²) with unit μ
      const double dg = 2 * M_PI *
                        G::integrate([&](double t) { return std::exp(lambda * (std::cos(t) - 1)) * std::sin(t); }, 0.0,
                                     R);
      // ‖G‖² over [0, π], split where the lobe has fallen by e^{-50}
      const double cut = std::min(M_PI, std::sqrt(100 / lambda));
      double gg = 0;
      for (int k = 0; k < 8; ++k)
        gg += 2 * M_PI *
              G::integrate([&](double t) { return std::exp(2 * lambda * (std::cos(t) - 1)) * std::sin(t); },
                           cut * k / 8, cut * (k + 1) / 8);
      return dg * dg / (gg * disk2);
    };
    double a = std::log(0.1 / (R * R)), b = std::log(20 / (R * R));  // log λ; t = λR²/2 in [0.05, 10]
    const double phi = (std::sqrt(5.0) - 1) / 2;
    for (int i = 0; i < 200; ++i) {
      const double m1 = b - phi * (b - a), m2 = a + phi * (b - a);
      if (share(std::exp(m1)) < share(std::exp(m2))) a = m1;
      else b = m2;
    }
    const double lambda = std::exp((a + b) / 2);
    const double floor = std::sqrt(1 - share(lambda));
    std::printf("disk %.2f°: floor %.6f at t = λR²/2 = %.5f\n", diameter_deg, floor, lambda * R * R / 2);
    EXPECT_NEAR(floor, sglab::experiments::envmap_bases::kOneLobeDiskFloor, 1e-4) << diameter_deg << "°";
  }
}
