// Specular VSGL shading by the registry's `specular` methods (core/render vsgl_specular_methods):
// for one specular VSGL and one glossy shading point, the shaded specular radiance must equal
// amplitude × e^{log_scale} × the registry method's scalar value for the same geometry, per RGB
// channel (f0 per channel). The expected value is computed here independently of the renderer's
// frame conversion: the incoming SG by vsgl.hpp's scalar forms, and the local frame by rotating n
// onto +z (Eigen quaternion) and the view to azimuth 0, the light azimuth then measured from the
// view's. Also: the default `vsgl-asg` (the renderer's own form, in its own tangent frame) equals
// the registry's `asg`, the same formula; and a bad name is refused, naming it.
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "sglab/render/vsgl_generation.hpp"
#include "sglab/render/vsgl_shading.hpp"
#include "sglab/render/vsgl_specular_methods.hpp"
#include "sglab/vsgl.hpp"

namespace {

using namespace sglab::render;
using sglab::Method;
using sglab::two_pi;
using sglab::vsgl_incoming_sg;
using sglab::vsgl_positional_sg;

VsglSet one_specular_vsgl() {
  VsglSet set;
  VsglCluster c;
  c.mean = Vec3(0.3, -0.2, 1.0);
  c.variance = 0.01;
  c.log_two_pi_variance = std::log(two_pi<double>() * c.variance);
  c.has_specular = true;
  c.specular.amplitude = Rgb(2.0, 1.0, 0.5);
  c.specular.axis = Vec3(0.1, 0.2, -1).normalized();
  c.specular.sharpness = 50;
  set.clusters.push_back(c);
  set.stats.specular_vsgls = 1;
  return set;
}

ShadingPoint glossy_point(double roughness) {
  ShadingPoint p;
  p.position = Vec3(0.05, 0.1, 0);
  p.normal = Vec3(0.2, -0.1, 1).normalized();
  p.view = Vec3(0.5, 0.3, 0.8).normalized();
  p.f0 = Rgb(0.9, 0.5, 0.04);
  p.roughness = roughness;
  return p;
}

// amplitude × e^{log_scale} × method(α, λ_in, light_cos, view_cos, φ, f0) per channel, for the
// specular lobe of cluster k.
Rgb expected(const Method& m, const VsglSet& set, const ShadingPoint& p, std::size_t k = 0) {
  const VsglCluster& c = set.clusters[k];
  const auto pos = vsgl_positional_sg<double>(c.mean, c.variance, p.position, c.log_two_pi_variance);
  const auto in = vsgl_incoming_sg<double>(pos, c.specular.axis, c.specular.sharpness);
  const Eigen::Quaterniond to_z = Eigen::Quaterniond::FromTwoVectors(p.normal, Vec3::UnitZ());
  const Vec3 v = to_z * p.view, xi = to_z * in.axis;
  const double view_azimuth = std::atan2(v.y(), v.x());
  const double light_azimuth = std::atan2(xi.y(), xi.x()) - view_azimuth;
  Rgb out;
  for (int ch = 0; ch < 3; ++ch) {
    const double row[6] = {p.roughness, in.sharpness, xi.z(), v.z(), light_azimuth, p.f0(ch)};
    out(ch) = c.specular.amplitude(ch) * sglab::scaled_by_exp(in.log_scale, m.eval_double(row));
  }
  return out;
}

double max_rel(const Rgb& a, const Rgb& b) { return ((a - b).abs() / b.abs()).maxCoeff(); }

TEST(VsglSpecularMethods, APixelsSpecularIsTheRegistryMethodsValue) {
  const VsglSet set = one_specular_vsgl();
  for (double roughness : {0.05, 0.3, 0.8}) {
    const ShadingPoint p = glossy_point(roughness);
    for (const auto& name : specular_method_names()) {
      const Method* m = find_specular_method(name);
      if (!m) continue;  // the default, vsgl-asg: below
      ShadingOptions o = shading_options("tokuyoshi2024");
      o.specular_method = m;
      const VsglShading s = shade_vsgls_parts(p, set, o);
      const Rgb want = expected(*m, set, p);
      ASSERT_TRUE((want > 0).all()) << name << " α = " << roughness;
      // The batch evaluator against the scalar template (≤ 8 ulps, tests/simd_specular_test.cpp)
      // and two computations of the same angles: 1e-12.
      EXPECT_LT(max_rel(s.specular, want), 1e-12)
          << name << " α = " << roughness << ": shaded " << s.specular.transpose() << ", method " << want.transpose();
      EXPECT_TRUE((s.diffuse == 0).all()) << name;  // no diffuse lobe in the set
    }
  }
}

// Many points shaded at once (the renderer's blocks: the rows as columns, the column pair
// evaluator, or the batch evaluator for a bound method), each with its own visibility, against the
// sum over its visible clusters of the single-lobe value above; clusters at varied distances and
// one of tiny variance (log_scale past the vectorized exponential's range: the scalar fallback).
// Each point's sum to 1e-12 of the sum of its terms' magnitudes (the same per-term allowance as
// above).
TEST(VsglSpecularMethods, ManyPointsWithVisibilityAreTheSumOfTheRegistryMethodsValues) {
  const unsigned seed = 20261203;
  std::printf("seed %u\n", seed);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  VsglSet set;
  for (int k = 0; k < 13; ++k) {
    VsglCluster c;
    c.mean = Vec3(u(rng), u(rng), 1 + 0.5 * u(rng));
    c.variance = k == 5 ? 1e-200 : 0.01 * (1.5 + u(rng));
    c.log_two_pi_variance = std::log(two_pi<double>() * c.variance);
    c.has_specular = true;
    c.specular.amplitude = Rgb(1.5 + u(rng), 1 + 0.5 * u(rng), 0.6);
    c.specular.axis = Vec3(0.3 * u(rng), 0.3 * u(rng), -1).normalized();
    c.specular.sharpness = std::pow(10.0, 1 + 2 * (1 + u(rng)));
    set.clusters.push_back(c);
  }
  set.stats.specular_vsgls = set.clusters.size();
  std::vector<ShadingPoint> points;
  for (int i = 0; i < 70; ++i) {
    ShadingPoint p;
    p.position = Vec3(0.5 * u(rng), 0.5 * u(rng), 0.1 * u(rng));
    p.normal = Vec3(0.3 * u(rng), 0.3 * u(rng), 1).normalized();
    p.view = Vec3(u(rng), u(rng), 1.2).normalized();
    p.f0 = i % 7 == 3 ? Rgb(0, 0, 0) : Rgb(0.9, 0.5, 0.04);  // every seventh: not glossy
    p.roughness = 0.05 + 0.5 * (1 + u(rng)) / 2;
    p.diffuse_reflectance = Rgb::Zero();
    points.push_back(p);
  }
  std::vector<char> visible(points.size() * set.clusters.size());
  for (auto& v : visible) v = u(rng) > -0.4 ? 1 : 0;
  const Method& asg = *find_specular_method("asg");
  std::vector<double> published;
  for (const auto& p : find_specular_method("sglab")->parameters) published.push_back(p.published);
  const Method bound = find_specular_method("sglab")->bind(published);  // no pair evaluator: the batch
  // Twice: with the non-glossy points (the kernels gather a block's glossy rows by index), then with
  // every point glossy (a block's rows read as they lie).
  std::vector<ShadingPoint> all_glossy = points;
  for (auto& p : all_glossy) p.f0 = Rgb(0.9, 0.5, 0.04);
  for (const auto* pts : {&points, &all_glossy})
    for (const Method* m : {&asg, find_specular_method("sg-warp"), find_specular_method("sglab"), &bound}) {
      ShadingOptions o = shading_options("tokuyoshi2024");
      o.specular_method = m;
      const VsglShader shader(set, o);
      std::vector<VsglShading> shaded(pts->size());
      shader.shade(*pts, visible, shaded);
      std::size_t glossy = 0;
      for (std::size_t i = 0; i < pts->size(); ++i) {
        const ShadingPoint& p = (*pts)[i];
        Rgb want = Rgb::Zero(), magnitude = Rgb::Zero();
        if (p.glossy())
          for (std::size_t k = 0; k < set.clusters.size(); ++k)
            if (visible[i * set.clusters.size() + k]) {
              const Rgb term = expected(*m, set, p, k);
              want += term;
              magnitude += term.abs();
            }
        glossy += p.glossy() ? 1 : 0;
        EXPECT_TRUE(((shaded[i].specular - want).abs() <= 1e-12 * magnitude).all())
            << m->name << (m == &bound ? " (bound)" : "") << (pts == &all_glossy ? ", every point glossy" : "")
            << ", point " << i << ": shaded " << shaded[i].specular.transpose() << ", method " << want.transpose()
            << ", seed " << seed;
      }
      EXPECT_GT(glossy, pts == &all_glossy ? 69u : 50u);
    }
}

TEST(VsglSpecularMethods, DefaultIsTheRenderersAsgFormAndEqualsTheRegistryAsg) {
  EXPECT_EQ(specular_method_names().front(), kDefaultSpecularMethod);
  EXPECT_EQ(find_specular_method(kDefaultSpecularMethod), nullptr);
  const VsglSet set = one_specular_vsgl();
  for (double roughness : {0.05, 0.3, 0.8}) {
    const ShadingPoint p = glossy_point(roughness);
    const VsglShading renderer = shade_vsgls_parts(p, set, shading_options("tokuyoshi2024"));
    ShadingOptions o = shading_options("tokuyoshi2024");
    o.specular_method = find_specular_method("asg");
    const VsglShading registry = shade_vsgls_parts(p, set, o);
    EXPECT_LT(max_rel(renderer.specular, registry.specular), 1e-10) << "α = " << roughness;
  }
}

TEST(VsglSpecularMethods, BadNamesAreRefusedByName) {
  for (const char* bad : {"ggx", "reference", ""}) {
    try {
      find_specular_method(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("'" + std::string(bad) + "'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("vsgl-asg"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
