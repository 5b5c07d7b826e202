// The renderer's scene side (core/render; intersections are in raycast_test.cpp): the light
// view's solid angles and the RSM's flux against closed forms (a spotlight over a plane, over a
// square); each texel's emission fraction against the spot profile by Cartesian quadrature; the
// GGX directional albedo against core's adaptive sphere quadrature; the exact VPL sum against an
// independent brute-force evaluation in tangent frames with core's BRDF; direct light on a
// Lambert plane against E = I cos θ/d², with and without an occluder; the EXR round trip; and
// what the pipeline builds for diffuse-only and glossy scenes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include "render_scenes.hpp"
#include "sglab/brdf.hpp"
#include "sglab/glossy_reference.hpp"
#include "sglab/render/exr.hpp"
#include "sglab/render/pipeline.hpp"
#include "sglab/render/raycast.hpp"
#include "sglab/render/reference.hpp"
#include "sglab/render/rsm.hpp"
#include "sglab/render/scene.hpp"
#include "sglab/render/shadow_map.hpp"
#include "test_util.hpp"

namespace {

using namespace sglab::test;
using namespace sglab::render;

// ---- the light's view, solid angles, RSM flux ------------------------------------------------

// The square [−T, T]² at unit distance subtends 4 asin(T²/(1 + T²)) (a pyramid with apex half-
// angles a = b = atan T: Ω = 4 asin(sin a sin b)).
TEST(Rsm, ImageSolidAnglesAddUpToThePyramid) {
  for (const double cone : {5.0, 30.0, 60.0, 85.0}) {
    Spotlight l;
    l.cone_angle = cone * kDeg;
    const LightView v(l, 7);
    const double T = v.half_extent;
    const double pyramid = 4 * std::asin(T * T / (1 + T * T));
    EXPECT_NEAR(image_rectangle_solid_angle(-T, T, -T, T), pyramid, 1e-14 * pyramid) << cone;
    double sum = 0;
    for (int j = 0; j < 7; ++j)
      for (int i = 0; i < 7; ++i)
        sum += image_rectangle_solid_angle(v.x_lo(i), v.x_lo(i) + v.texel_size(), v.y_lo(j),
                                           v.y_lo(j) + v.texel_size());
    EXPECT_NEAR(sum, pyramid, 1e-13 * pyramid) << cone;
  }
}

// The image contains the whole cone, so the texels' emission fractions add up to 1 — whatever
// the resolution, with hard and smooth edges (the edge cuts many texels at every resolution).
TEST(Rsm, EmissionFractionsAddUpToOne) {
  for (const double cone : {10.0, 35.0, 70.0}) {
    for (const double falloff : {0.0, 0.25 * cone, cone}) {
      for (const int res : {1, 5, 32}) {
        Spotlight l;
        l.cone_angle = cone * kDeg;
        l.falloff = falloff * kDeg;
        const LightView v(l, res);
        double sum = 0;
        for (int j = 0; j < res; ++j)
          for (int i = 0; i < res; ++i) {
            const double f = texel_emission_fraction(l, v, i, j);
            EXPECT_GE(f, 0);
            sum += f;
          }
        EXPECT_NEAR(sum, 1.0, 1e-9) << "cone " << cone << ", falloff " << falloff << ", res " << res;
      }
    }
  }
}

// A texel's emission fraction ∫_texel I(ω) dω/Φ against the spot profile written out here:
// I/Φ = s(c)/(π((1 − cos θi) + (1 − cos θo))) (the power 2π∫ I0 s dc with ∫₀¹ smoothstep = ½),
// s = 1 for θ ≤ θi, 0 for θ ≥ θo and smoothstep 3t² − 2t³ of t = (cos θ − cos θo)/(cos θi − cos θo)
// in between (scene.hpp), integrated over the image-plane square as dx dy/(1 + x² + y²)^{3/2} in
// Cartesian coordinates, row by row, with panel ends where each row crosses the inner and outer
// circles (the code integrates the profile in closed form along r and over the azimuth instead). Every texel of the
// image, so the texels inside the inner cone, across its edge, inside the falloff band, across the outer edge and
// outside are all checked (the test counts each kind); a wrong polynomial in the band's radial integral changes the
// texels of the band while their sum stays 1.
TEST(Rsm, EmissionFractionsMatchTheSpotProfileOverEachTexel) {
  using boost::math::quadrature::gauss;
  using boost::math::quadrature::gauss_kronrod;
  // Rows: 20-point Gauss–Legendre on each panel between the circles (where the integrand is
  // smooth). Columns: adaptive Gauss–Kronrod over y mapped onto [−1, 1] (Boost 1.74's error
  // estimate leaves out the (b − a)/2 factor, which on short intervals would refine far too
  // long), with panel ends at ±r where a row becomes tangent to a circle.
  const auto pieces = [](const auto& integrate, double a, double b, std::vector<double> breaks) {
    std::sort(breaks.begin(), breaks.end());
    double sum = 0, lo = a;
    for (const double t : breaks)
      if (t > lo && t < b) {
        sum += integrate(lo, t);
        lo = t;
      }
    return sum + integrate(lo, b);
  };
  const auto mapped = [](const auto& f, double a, double b, const auto& rule) {
    const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
    return half * rule([&](double u) { return f(mid + half * u); });
  };
  struct Case {
    double cone, falloff;  // degrees
    int res;
  };
  int inside = 0, across_inner = 0, band = 0, across_outer = 0, outside = 0;
  double worst = 0;
  for (const Case k : {Case{30, 10, 16}, Case{30, 10, 15}, Case{70, 25, 12}, Case{20, 20, 9}, Case{45, 3, 24}}) {
    Spotlight l;
    l.cone_angle = k.cone * kDeg;
    l.falloff = k.falloff * kDeg;
    const LightView v(l, k.res);
    const double theta_i = (k.cone - k.falloff) * kDeg, theta_o = k.cone * kDeg;
    const double ci = std::cos(theta_i), co = std::cos(theta_o);
    const double peak = 1 / (kPi * ((1 - ci) + (1 - co)));
    const double r_i = std::tan(theta_i), r_o = std::tan(theta_o);
    const auto emitted = [&](double x, double y) {  // I/Φ · dω/(dx dy)
      const double q2 = 1 + x * x + y * y, c = 1 / std::sqrt(q2);
      double s = 0;
      if (c >= ci) {
        s = 1;
      } else if (c > co) {
        const double t = (c - co) / (ci - co);
        s = t * t * (3 - 2 * t);
      }
      return peak * s / (q2 * std::sqrt(q2));
    };
    for (int j = 0; j < k.res; ++j)
      for (int i = 0; i < k.res; ++i) {
        const double x0 = v.x_lo(i), x1 = x0 + v.texel_size(), y0 = v.y_lo(j), y1 = y0 + v.texel_size();
        const auto row = [&](double y) {
          std::vector<double> xb;
          for (const double r : {r_i, r_o})
            if (std::fabs(y) < r) xb.insert(xb.end(), {-std::sqrt(r * r - y * y), std::sqrt(r * r - y * y)});
          const auto f = [&](double x) { return emitted(x, y); };
          return pieces(
              [&](double a, double b) {
                return mapped(f, a, b, [](const auto& g) { return gauss<double, 20>::integrate(g, -1.0, 1.0); });
              },
              x0, x1, xb);
        };
        const double expected = pieces(
            [&](double a, double b) {
              return mapped(row, a, b, [](const auto& g) {
                return gauss_kronrod<double, 15>::integrate(g, -1.0, 1.0, 10, 1e-11);
              });
            },
            y0, y1, {-r_o, -r_i, r_i, r_o});
        const double got = texel_emission_fraction(l, v, i, j);
        // 1e-11 of the texel's emission at the peak intensity, I0/Φ·Ω_texel (the code states 1e-12
        // relative; measured 3e-14). A wrong band polynomial (t² for t³) moves band texels by
        // 2–20 % of it.
        const double scale = peak * image_rectangle_solid_angle(x0, x1, y0, y1);
        worst = std::max(worst, std::fabs(got - expected) / scale);
        EXPECT_NEAR(got, expected, 1e-11 * scale) << "cone " << k.cone << "°, falloff " << k.falloff << "°, res "
                                                  << k.res << ", texel (" << i << ", " << j << ")";
        const double r_min = std::hypot(std::clamp(0.0, x0, x1), std::clamp(0.0, y0, y1));
        const double r_max = std::hypot(std::max(std::fabs(x0), std::fabs(x1)), std::max(std::fabs(y0), std::fabs(y1)));
        if (r_max <= r_i) ++inside;
        else if (r_min < r_i) ++across_inner;
        else if (r_max <= r_o) ++band;
        else if (r_min < r_o) ++across_outer;
        else ++outside;
      }
  }
  std::printf(
      "[ measured ] worst |fraction − quadrature| / (I0/Φ·Ω_texel): %.3g; texels inside %d, across the inner edge %d, "
      "in the band %d, across the outer edge %d, outside %d\n",
      worst, inside, across_inner, band, across_outer, outside);
  EXPECT_GT(inside, 20);
  EXPECT_GT(across_inner, 20);
  EXPECT_GT(band, 20);
  EXPECT_GT(across_outer, 20);
  EXPECT_GT(outside, 20);
}

TEST(Rsm, FluxOverAPlaneIsThePower) {
  const Vec3 light(0.3, 1.5, -0.2);
  for (const double falloff : {0.0, 8.0}) {
    const Scene s = floor_scene(100, glossy(0.5, 0.8, 0.3), light, Vec3(0.2, -1, 0.1), 40, falloff);
    const ReflectiveShadowMap rsm = render_rsm(s, 24);
    Rgb sum = Rgb::Zero();
    int valid = 0;
    for (int j = 0; j < 24; ++j)
      for (int i = 0; i < 24; ++i) {
        const Vpl& v = rsm.at(i, j);
        if (!v.valid) continue;
        ++valid;
        sum += v.flux;
        EXPECT_NEAR(v.position.y(), 0, 1e-12);
        EXPECT_EQ(v.normal, Vec3(0, 1, 0));  // facing the light
        EXPECT_NEAR((v.incoming - (light - v.position).normalized()).norm(), 0, 1e-12);
        // r_i = √(Ω_i/π)·t_i with the texel's exact solid angle.
        const LightView view(s.light, 24);
        const double omega = image_rectangle_solid_angle(view.x_lo(i), view.x_lo(i) + view.texel_size(), view.y_lo(j),
                                                         view.y_lo(j) + view.texel_size());
        EXPECT_NEAR(v.footprint_radius, std::sqrt(omega / kPi) * (light - v.position).norm(), 1e-12);
        EXPECT_TRUE((v.diffuse_reflectance == Rgb(0.5, 0.5, 0.5)).all());
      }
    EXPECT_GT(valid, 300);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum(c) / s.light.power(c), 1.0, 1e-9) << "falloff " << falloff;
  }
}

// A square of half-size a centred under the light at distance d, its edges on texel boundaries
// (a/d = T/2 on a 32² map) and inside a hard cone: Σ Φ = I0·Ω_square with
// Ω_square = 4 atan(a²/(d√(2a² + d²))) and I0 = Φ/(2π(1 − cos θo)).
TEST(Rsm, FluxOnASquareIsItsSolidAngleTimesIntensity) {
  const double d = 1.7, cone = 40 * kDeg;
  const double a = 0.5 * d * std::tan(cone);
  Scene s = floor_scene(a, lambert(0.6), Vec3(0, d, 0), Vec3(0, -1, 0), 40, 0);
  const ReflectiveShadowMap rsm = render_rsm(s, 32);
  Rgb sum = Rgb::Zero();
  int valid = 0;
  for (const Vpl& v : rsm.texels)
    if (v.valid) {
      sum += v.flux;
      ++valid;
    }
  EXPECT_EQ(valid, 16 * 16);
  const double omega = 4 * std::atan(a * a / (d * std::sqrt(2 * a * a + d * d)));
  const double i0 = 1 / (2 * kPi * (1 - std::cos(cone)));
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum(c), s.light.power(c) * i0 * omega, 1e-12 * s.light.power(c));
}

// R_s against core's adaptive sphere quadrature of ∫ f_ggx(ω', ω)⟨ω·n⟩ dω (glossy_reference.hpp,
// ≤ 1e-6 relative), with f0 = 1 (F ≡ 1: e1) and f0 = 0 (F = (1 − ω'·h)⁵: e5).
TEST(Rsm, GgxDirectionalAlbedoMatchesSphereQuadrature) {
  double worst = 0;
  for (const double alpha : {0.02, 0.1, 0.3, 0.6, 1.0}) {
    for (const double mu : {0.005, 0.02, 0.2, 0.5, 0.8, 1.0}) {
      const sglab::Vec3d wo(std::sqrt(1 - mu * mu), 0, mu), n(0, 0, 1);
      const sglab::Vec3d mirror = sglab::reflect_about(wo, n);
      const sglab::Vec3d dvn = sglab::dvn_reflection_lobe(alpha, wo).axis;
      const std::vector<sglab::SphereFocus> foci{{dvn, alpha}};
      const std::vector<sglab::Vec3d> clips{n};
      double ref[2];
      for (int f0 = 0; f0 <= 1; ++f0)
        ref[f0] = sglab::integrate_sphere(
            [&](const sglab::Vec3d& w) { return sglab::ggx_brdf_cosine(alpha, double(f0), wo, w); }, mirror, alpha,
            foci, clips);
      const GgxAlbedo e = ggx_directional_albedo(alpha, mu);
      // Documented accuracy (rsm.hpp): 3e-4 at grazing incidence, 3e-5 from cos θ' = 0.2 up.
      const double tolerance = mu < 0.2 ? 3e-4 : 3e-5;
      EXPECT_NEAR(e.e1, ref[1], tolerance) << "α " << alpha << ", cos " << mu;
      EXPECT_NEAR(e.e5, ref[0], tolerance) << "α " << alpha << ", cos " << mu;
      EXPECT_NEAR(e.reflectance(0.3), 0.3 * ref[1] + 0.7 * ref[0], tolerance);
      worst = std::max({worst, std::fabs(e.e1 - ref[1]), std::fabs(e.e5 - ref[0])});
    }
  }
  std::printf("max |R_s − quadrature| = %.3g\n", worst);
}

// The table the RSM uses against the quadrature it tabulates, and the RSM's R_s against the table.
TEST(Rsm, AlbedoTableInterpolatesTheQuadrature) {
  for (const double alpha : {0.01, 0.05, 0.2, 1.0}) {
    const GgxAlbedoTable table(alpha);
    double worst = 0, worst_above = 0;
    for (double mu = 1e-4; mu <= 1; mu *= 1.07) {
      const GgxAlbedo t = table(mu), q = ggx_directional_albedo(alpha, mu);
      const double e = std::max(std::fabs(t.e1 - q.e1), std::fabs(t.e5 - q.e5));
      worst = std::max(worst, e);
      if (mu >= 0.01) worst_above = std::max(worst_above, e);
    }
    std::printf("α %g: max table error %.2e (cos ≥ 0.01: %.2e)\n", alpha, worst, worst_above);
    EXPECT_LT(worst, 1e-3) << alpha;  // the documented bounds (rsm.hpp)
    EXPECT_LT(worst_above, alpha < 0.05 ? 4e-4 : 1e-4) << alpha;
  }
  // Every glossy VPL's R_s is f0·(e1 − e5) + e5 of its incidence.
  const Scene s = floor_scene(5, glossy(0.5, 0.8, 0.3), Vec3(0, 1, 0), Vec3(0.6, -1, 0), 60, 0);
  const ReflectiveShadowMap rsm = render_rsm(s, 16);
  const GgxAlbedoTable table(0.3);
  int glossy_vpls = 0;
  for (const Vpl& v : rsm.texels) {
    if (!v.valid) continue;
    const GgxAlbedo a = table(v.normal.dot(v.incoming));
    for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(v.specular_reflectance(c), a.reflectance(v.f0(c)));
    ++glossy_vpls;
  }
  EXPECT_GT(glossy_vpls, 100);
}

// The tables kept per process (ggx_albedo_table, which render_rsm uses: the test above holds its
// VPLs to a table built afresh) are the tables built afresh, to the bit, also when many threads ask
// for the same roughness values at once; a roughness asked again gets the table kept, a different
// one its own.
TEST(Rsm, KeptAlbedoTablesAreTheTablesBuiltAfresh) {
  const std::vector<double> alphas = {0.013, 0.27, 0.61};
  std::vector<std::shared_ptr<const GgxAlbedoTable>> got(24);
  tbb::parallel_for(std::size_t(0), got.size(), [&](std::size_t k) { got[k] = ggx_albedo_table(alphas[k % 3]); });
  for (std::size_t k = 0; k < got.size(); ++k) {
    const double alpha = alphas[k % 3];
    const GgxAlbedoTable fresh(alpha);
    for (double mu = 0; mu <= 1; mu += 1.0 / 512) {
      const GgxAlbedo a = (*got[k])(mu), b = fresh(mu);
      ASSERT_EQ(a.e1, b.e1) << "α " << alpha << ", cos " << mu;
      ASSERT_EQ(a.e5, b.e5) << "α " << alpha << ", cos " << mu;
    }
  }
  EXPECT_EQ(ggx_albedo_table(0.27).get(), ggx_albedo_table(0.27).get());
  EXPECT_NE(ggx_albedo_table(0.27).get(), ggx_albedo_table(0.61).get());
}

// ---- the exact VPL sum --------------------------------------------------------------------------

// An orthonormal frame with z = n (Gram–Schmidt on whichever axis is least aligned with n).
void tangent_frame(const Vec3& n, Vec3& t, Vec3& b) {
  const Vec3 a = std::fabs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
  t = (a - a.dot(n) * n).normalized();
  b = n.cross(t);
}
sglab::Vec3d to_local(const Vec3& w, const Vec3& n) {
  Vec3 t, b;
  tangent_frame(n, t, b);
  return sglab::Vec3d(w.dot(t), w.dot(b), w.dot(n));
}
// f(ωo, ωi)⟨n·ωi⟩ of a material, per channel, with core's tangent-frame GGX.
double brute_brdf_cosine(const Rgb& albedo, const Rgb& f0, double alpha, const Vec3& n, const Vec3& wo, const Vec3& wi,
                         int c) {
  const sglab::Vec3d lo = to_local(wo, n), li = to_local(wi, n);
  if (!(li.z() > 0)) return 0;
  double f = albedo(c) / kPi * li.z();
  if ((f0 > 0).any()) f += sglab::ggx_brdf_cosine(alpha, f0(c), lo, li);
  return f;
}

TEST(Reference, VplSumMatchesBruteForce) {
  Scene s;
  s.camera = {
      .position = Vec3(0.3, 1.2, 2.5), .look_at = Vec3(0, 0.3, 0), .vertical_fov = 60 * kDeg, .width = 10, .height = 8};
  s.light = {.position = Vec3(-0.2, 1.4, 0.6),
             .direction = Vec3(0.1, -1, -0.5).normalized(),
             .cone_angle = 35 * kDeg,
             .falloff = 5 * kDeg,
             .power = Rgb(5, 4, 3)};
  s.objects.push_back(rectangle("floor", Vec3(-1, 0, -1), Vec3(0, 0, 2), Vec3(2, 0, 0), glossy(0.4, 0.7, 0.25)));
  s.objects.push_back(rectangle("back", Vec3(-1, 0, -1), Vec3(2, 0, 0), Vec3(0, 1.5, 0), lambert(0.7)));
  s.objects.push_back(Object{"ball", Sphere{Vec3(0.3, 0.25, 0), 0.25}, glossy(0.2, 0.9, 0.1)});
  const ReflectiveShadowMap rsm = render_rsm(s, 6);
  const VplList list = prepare_vpls(rsm);
  ASSERT_GT(list.vpls.size(), 20u);
  EXPECT_TRUE(list.any_glossy);
  const GBuffer g = render_gbuffer(s);
  int compared = 0;
  double worst = 0;
  for (std::size_t k = 0; k < g.points.size(); ++k) {
    if (!g.hit[k]) continue;
    const ShadingPoint& p = g.points[k];
    const Rgb value = reference_radiance(p, list);
    for (int c = 0; c < 3; ++c) {
      double brute = 0, scale = 0;
      for (const Vpl& v : rsm.texels) {
        if (!v.valid) continue;
        const Vec3 d = p.position - v.position;
        const Vec3 w = d.normalized();
        const double emitted = brute_brdf_cosine(v.diffuse_reflectance, v.f0, v.roughness, v.normal, v.incoming, w, c);
        const double reflected = brute_brdf_cosine(p.diffuse_reflectance, p.f0, p.roughness, p.normal, p.view, -w, c);
        const double term = v.flux(c) * emitted * reflected /
                            (d.squaredNorm() + v.footprint_radius * v.footprint_radius);
        brute += term;
        scale += std::fabs(term);
      }
      if (scale > 0) {
        worst = std::max(worst, std::fabs(value(c) - brute) / scale);
        ++compared;
      } else {
        EXPECT_EQ(value(c), 0);
      }
    }
  }
  std::printf("%d pixel channels, max relative difference %.3g\n", compared, worst);
  EXPECT_GT(compared, 60);
  EXPECT_LT(worst, 1e-12);
}

// Far from a VPL the bound changes 1/d² by the factor 1/(1 + r²/d²) only.
TEST(Reference, BoundIsTheDiscFactor) {
  Vpl v;
  v.valid = true;
  v.position = Vec3(0, 0, 0);
  v.normal = Vec3(0, 1, 0);
  v.incoming = Vec3(0, 1, 0);
  v.flux = Rgb(1, 1, 1);
  v.diffuse_reflectance = Rgb(1, 1, 1);
  v.footprint_radius = 0.01;
  VplList list;  // built by hand: reference_radiance converts it to arrays
  list.vpls = {v};
  ShadingPoint p;
  p.normal = Vec3(0, -1, 0);
  p.view = Vec3(0, -1, 0);
  p.diffuse_reflectance = Rgb(1, 1, 1);
  for (const double d : {0.0, 0.005, 0.01, 0.1, 1.0, 10.0}) {
    p.position = Vec3(0, d, 0);  // facing the VPL head-on: both cosines 1
    const double expected = d == 0 ? 0.0 : (1 / kPi) * (1 / kPi) / (d * d + 1e-4);
    EXPECT_NEAR(reference_radiance(p, list)(0), expected, 1e-14 * expected) << d;
  }
}

// ---- direct light ------------------------------------------------------------------------------

// A Lambert plane under the spotlight: L = R/π · I0 s(θ) cos θ_n/d², I0 = Φ/(2π(1 − cos θo)) for a
// hard cone; no pixel may be shadowed (no acne from the shadow map) — at the steep light angles
// this light makes at the far side of the floor too.
TEST(Direct, LambertPlaneMatchesTheClosedForm) {
  const Vec3 light(0.4, 1.1, -0.3);
  const double cone = 50 * kDeg;
  Scene s = floor_scene(3, lambert(0.6), light, Vec3(-0.3, -1, 0.4), 50, 0);
  s.camera.width = 48;
  s.camera.height = 40;
  const ShadowMap sm = render_shadow_map(s, 256);
  const GBuffer g = render_gbuffer(s);
  const double i0 = 1 / (2 * kPi * (1 - std::cos(cone)));
  int lit = 0, dark = 0;
  for (std::size_t k = 0; k < g.points.size(); ++k) {
    if (!g.hit[k]) continue;
    const ShadingPoint& p = g.points[k];
    const Vec3 to_light = light - p.position;
    const double d2 = to_light.squaredNorm();
    const Vec3 wi = to_light / std::sqrt(d2);
    const double theta = std::acos(std::clamp(-wi.dot(s.light.direction), -1.0, 1.0));
    const Rgb value = direct_radiance(s, sm, p);
    if (std::fabs(theta - cone) < 1e-9) continue;  // exactly on the edge
    const bool inside = theta < cone;
    for (int c = 0; c < 3; ++c) {
      const double expected = inside ? 0.6 / kPi * s.light.power(c) * i0 * wi.y() / d2 : 0.0;
      EXPECT_NEAR(value(c), expected, 1e-12 * (expected + 1e-300)) << "pixel " << k;
    }
    (inside ? lit : dark)++;
  }
  EXPECT_GT(lit, 400);
  EXPECT_GT(dark, 100);
}

// An occluding sphere: a point is in shadow iff its segment to the light hits the sphere. Points
// whose light ray passes within 2 shadow-map texels of the sphere's silhouette are not judged.
TEST(Direct, OccluderShadowsExactlyItsUmbra) {
  const Vec3 light(0, 2, 0);
  Scene s = floor_scene(3, lambert(0.5), light, Vec3(0, -1, 0), 45, 0);
  const Sphere ball{Vec3(0.3, 1.0, 0.1), 0.3};
  s.objects.push_back(Object{"ball", ball, lambert(0.5)});
  s.camera.position = Vec3(0.1, 4, 2.5);
  s.camera.look_at = Vec3(0.3, 0, 0.1);
  s.camera.width = 64;
  s.camera.height = 64;
  const int res = 512;
  const ShadowMap sm = render_shadow_map(s, res);
  const GBuffer g = render_gbuffer(s);
  const double texel_angle = 2 * std::tan(45 * kDeg) / res;
  const double silhouette = std::asin(ball.radius / (ball.center - light).norm());
  int shadowed = 0, lit = 0;
  for (std::size_t k = 0; k < g.points.size(); ++k) {
    if (!g.hit[k] || g.object[k] != 0) continue;
    const ShadingPoint& p = g.points[k];
    const Vec3 from_light = (p.position - light).normalized();
    if (std::acos(from_light.dot(s.light.direction)) > 44 * kDeg) continue;
    const double off_axis = std::acos(std::clamp(from_light.dot((ball.center - light).normalized()), -1.0, 1.0));
    if (std::fabs(off_axis - silhouette) < 2 * texel_angle) continue;
    const Vec3 to_light = light - p.position;
    const auto blocker = intersect(ball, Ray{p.position, to_light.normalized()}, 0, to_light.norm());
    const Rgb value = direct_radiance(s, sm, p);
    if (blocker) {
      EXPECT_EQ(value(0), 0) << "pixel " << k << " should be in shadow";
      ++shadowed;
    } else {
      EXPECT_GT(value(0), 0) << "pixel " << k << " should be lit";
      ++lit;
    }
  }
  std::printf("%d shadowed, %d lit pixels judged\n", shadowed, lit);
  EXPECT_GT(shadowed, 50);
  EXPECT_GT(lit, 500);
}

// ---- EXR ------------------------------------------------------------------------------------------

TEST(Exr, LayersRoundTrip) {
  const int w = 7, h = 5;
  auto rng = sglab::test::seeded_rng(1234);
  std::uniform_real_distribution<double> u(-10, 10);
  std::vector<ImageLayer> layers;
  for (const char* name : {"direct", "indirect", "indirect_reference", "error"}) {
    ImageLayer l{name, {}};
    for (int k = 0; k < w * h; ++k) l.pixels.push_back(Rgb(u(rng), u(rng), u(rng)));
    layers.push_back(l);
  }
  const std::string bytes = encode_exr(w, h, layers, {{"sglab_command", "sglab render x.json --out y.exr"}});
  const auto path = std::filesystem::temp_directory_path() / ("sglab-exr-test-" + std::to_string(::getpid()) + ".exr");
  std::ofstream(path, std::ios::binary) << bytes;
  const ExrImage image = read_exr(path.string());
  std::filesystem::remove(path);
  EXPECT_EQ(image.width, w);
  EXPECT_EQ(image.height, h);
  EXPECT_EQ(image.channels.size(), 12u);
  for (const auto& l : layers)
    for (int c = 0; c < 3; ++c) {
      const std::string name = l.name + "." + "RGB"[c];
      ASSERT_TRUE(image.channels.count(name)) << name;
      const auto& plane = image.channels.at(name);
      for (int k = 0; k < w * h; ++k)
        EXPECT_EQ(plane[std::size_t(k)], float(l.pixels[std::size_t(k)](c))) << name << " " << k;
    }
  EXPECT_EQ(image.attributes.at("sglab_command"), "sglab render x.json --out y.exr");
  EXPECT_THROW(read_exr("/nonexistent/sglab.exr"), std::runtime_error);
}

// ---- the pipeline ---------------------------------------------------------------------------------

TEST(Pipeline, ImageErrorDefinitions) {
  const std::vector<Rgb> v{Rgb(1, 2, 0), Rgb(5, 5, 5), Rgb(3, 0, 1)};
  const std::vector<Rgb> r{Rgb(1, 1, 0), Rgb(0, 0, 0), Rgb(1, 0, 2)};
  const std::vector<char> mask{1, 0, 1};  // the middle pixel is background: not compared
  const ImageError e = image_error(v, r, mask);
  EXPECT_EQ(e.samples, 6u);
  // differences 0, 1, 0, 2, 0, −1 against references 1, 1, 0, 1, 0, 2
  EXPECT_DOUBLE_EQ(e.rmse, std::sqrt(6.0 / 6));
  EXPECT_DOUBLE_EQ(e.relative_l2, std::sqrt(6.0 / 7));
  EXPECT_DOUBLE_EQ(e.smape, (2.0 * 1 / 3 + 2.0 * 2 / 4 + 2.0 * 1 / 3) / 6);
  EXPECT_DOUBLE_EQ(e.max_abs, 2);
}

// What a scene needs is built, and nothing else.
TEST(Pipeline, DiffuseOnlyBuildsNoSpecularVsgl) {
  RenderOptions o;
  o.rsm_resolution = 8;
  o.shadow_map_resolution = 64;
  Scene diffuse = floor_scene(2, lambert(0.6), Vec3(0, 1, 0), Vec3(0.2, -1, 0), 40, 5);
  diffuse.objects.push_back(rectangle("back", Vec3(-2, 0, -1), Vec3(4, 0, 0), Vec3(0, 2, 0), lambert(0.7)));
  diffuse.camera.width = 12;
  diffuse.camera.height = 10;
  RenderResult r = render_scene(diffuse, o);
  EXPECT_EQ(r.vsgls.stats.specular_vsgls, 0u);
  EXPECT_EQ(r.vsgls.stats.diffuse_vsgls, 1u);
  EXPECT_FALSE(r.specular_shading);
  EXPECT_EQ(r.asg_evaluations, 0u);
  EXPECT_EQ(r.glossy_vpls, 0u);
  EXPECT_GT(r.vpl_count, 30u);
  for (std::size_t k = 0; k < r.error.size(); ++k)
    EXPECT_TRUE((r.error[k] == r.indirect[k] - r.indirect_reference[k]).all());
  EXPECT_GT(r.error_metrics.samples, 0u);

  Scene glossy_floor = diffuse;
  glossy_floor.objects[0].material = glossy(0.3, 0.6, 0.2);
  r = render_scene(glossy_floor, o);
  EXPECT_EQ(r.vsgls.stats.specular_vsgls, 1u);
  EXPECT_EQ(r.vsgls.stats.diffuse_vsgls, 1u);
  EXPECT_TRUE(r.specular_shading);
  EXPECT_EQ(r.asg_evaluations, r.glossy_receivers);
  EXPECT_GT(r.glossy_receivers, 0u);

  // Glossy VPLs but only Lambert receivers in view: a specular VSGL, but no specular shading.
  Scene wall_only = glossy_floor;
  wall_only.camera.position = Vec3(0, 1, 1.5);
  wall_only.camera.look_at = Vec3(0, 1.2, -1);
  wall_only.camera.vertical_fov = 20 * kDeg;
  r = render_scene(wall_only, o);
  EXPECT_EQ(r.glossy_receivers, 0u);
  EXPECT_EQ(r.vsgls.stats.specular_vsgls, 1u);
  EXPECT_FALSE(r.specular_shading);
  EXPECT_EQ(r.asg_evaluations, 0u);
}

}  // namespace
