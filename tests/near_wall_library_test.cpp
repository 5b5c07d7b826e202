// near-wall as a library (experiments/near_wall.hpp): every lit pixel's reference against an
// independent quadrature of D(λ, c) at the pixel's incoming SG, each method's mean and max SMAPE
// recomputed from the pixels, the ranking, and the sweep's points.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "clamped_cosine_quadrature.hpp"
#include "input_error.hpp"
#include "near_wall.hpp"

namespace nw = sglab::experiments::near_wall;

namespace {

nw::Options small_scene() {
  nw::Options o;
  o.job.scene_path = SGLAB_SOURCE_DIR "/scenes/sg-light-near-wall-poster.json";
  o.job.width = 20;
  o.job.height = 15;
  return o;
}

}  // namespace

TEST(NearWallLibrary, ReferenceAgainstQuadratureAndSmapeFromThePixels) {
  const nw::Result r = nw::compute(small_scene());
  ASSERT_EQ(r.pixels.size(), 20u * 15u);
  std::size_t lit = 0;
  for (const nw::Pixel& p : r.pixels) {
    if (!p.lit) continue;
    ++lit;
    const double pole = sglab::test::clamped_cosine_quadrature(p.sharpness, 1.0);
    EXPECT_NEAR(p.reference / pole, sglab::test::clamped_cosine_quadrature(p.sharpness, p.cosine) / pole, 1e-9)
        << "λ=" << p.sharpness << " c=" << p.cosine;
  }
  ASSERT_GT(lit, 0u);
  ASSERT_EQ(r.errors.size(), r.methods.size());
  for (std::size_t i = 0; i < r.methods.size(); ++i) {
    double sum = 0, max = 0;
    std::size_t n = 0;
    for (const nw::Pixel& p : r.pixels) {
      if (!p.lit || std::isnan(p.value[i])) continue;
      const double v = p.value[i], ref = p.reference;
      const double s = std::fabs(v) + std::fabs(ref) > 0 ? 2 * std::fabs(v - ref) / (std::fabs(v) + std::fabs(ref))
                                                         : 0.0;
      sum += s;
      max = std::max(max, s);
      ++n;
    }
    const auto it = std::find_if(r.errors.begin(), r.errors.end(),
                                 [&](const nw::MethodError& e) { return e.method == r.methods[i]; });
    ASSERT_NE(it, r.errors.end()) << r.methods[i];
    EXPECT_EQ(it->pixels, n) << r.methods[i];
    EXPECT_NEAR(it->mean, sum / double(n), 1e-12) << r.methods[i];
    EXPECT_EQ(it->max, max) << r.methods[i];
  }
  for (std::size_t i = 1; i < r.errors.size(); ++i) EXPECT_LE(r.errors[i - 1].mean, r.errors[i].mean);
}

TEST(NearWallLibrary, SweepHasOnePointPerSharpnessAndDistance) {
  nw::Options o = small_scene();
  o.sweep_sharpness = {10, 100};
  o.sweep_distance = {0.1, 0.2, 0.4};
  o.sweep_width = 12;
  o.sweep_height = 9;
  const nw::Result r = nw::compute(o);
  ASSERT_TRUE(r.swept);
  ASSERT_EQ(r.sweep.size(), 6u);
  EXPECT_EQ(r.sweep[0].sharpness, 10);
  EXPECT_EQ(r.sweep[0].distance, 0.1);
  EXPECT_EQ(r.sweep[5].sharpness, 100);
  EXPECT_EQ(r.sweep[5].distance, 0.4);
  const nw::Tables t = nw::tables(r);
  EXPECT_EQ(std::count(t.sweep_csv.begin(), t.sweep_csv.end(), '\n'), std::ptrdiff_t(6 * r.methods.size() + 1));
}

TEST(NearWallLibrary, BadSweepValuesAreInputErrors) {
  nw::Options o = small_scene();
  o.sweep_distance = {0};
  EXPECT_THROW(nw::compute(o), sglab::runner::InputError);
}
