// ns per pixel·VPL of the exact VPL sum and ns per pixel·lobe of VSGL shading, each beside its
// peer in the same run: a straight port of the one-term-at-a-time loop the renderer used before
// it was vectorized (kept here only, not in the library). Scene: scenes/cornell-glossy.json, a 64²
// RSM (as `sglab render`'s default), shading points from its 128² G-buffer (every hit pixel).
// One thread (CPU time); `sglab render` runs the same per-pixel code on every core (TBB). The
// "max_rel_diff" counter is the largest relative difference between the two paths over the
// points timed (per channel, relative to the channel's value). Run:
//   build/benchmarks/sglab_render_bench [--benchmark_filter=Reference]
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "sglab/clamped_cosine.hpp"
#include "sglab/render/material_brdf.hpp"
#include "sglab/render/raycast.hpp"
#include "sglab/render/reference.hpp"
#include "sglab/render/rsm.hpp"
#include "sglab/render/scene.hpp"
#include "sglab/render/vsgl_generation.hpp"
#include "sglab/render/vsgl_shading.hpp"
#include "sglab/vsgl.hpp"

namespace {

using namespace sglab::render;

// ---- the peers: the loops as they were -------------------------------------------------------

Rgb old_reference(const ShadingPoint& p, const VplList& list) {
  Rgb sum = Rgb::Zero();
  for (const Vpl& v : list.vpls) {
    const Vec3 offset = p.position - v.position;
    const double d2 = offset.squaredNorm();
    if (!(d2 > 0)) continue;
    const Vec3 omega = offset / std::sqrt(d2);
    const double cos_vpl = omega.dot(v.normal), cos_point = -omega.dot(p.normal);
    if (!(cos_vpl > 0) || !(cos_point > 0)) continue;
    const Rgb emitted = brdf_cosine(v.diffuse_reflectance, v.f0, v.roughness, v.normal, v.incoming, omega);
    const Rgb reflected = brdf_cosine(p.diffuse_reflectance, p.f0, p.roughness, p.normal, p.view, -omega);
    sum += v.flux * emitted * reflected / (d2 + v.footprint_radius * v.footprint_radius);
  }
  return sum;
}

// The old shading loop, the diffuse method `method` (a callable (λ, c) → D) called directly.
template <class D>
Rgb old_shading(const ShadingPoint& p, const VsglSet& set, const D& method) {
  using sglab::VsglIncomingSg, sglab::VsglPositionalSg, sglab::VsglSpecularFactor, sglab::VsglSpecularReceiver;
  VsglShading out;
  const bool diffuse_receiver = (p.diffuse_reflectance > 0).any();
  const bool glossy_receiver = p.glossy();
  if (!diffuse_receiver && !glossy_receiver) return Rgb::Zero();
  std::optional<VsglSpecularReceiver<double>> receiver;
  if (glossy_receiver) receiver = sglab::vsgl_specular_receiver<double>(p.normal, p.view, p.roughness);
  Rgb diffuse = Rgb::Zero();
  auto add = [&](const VsglPositionalSg<double>& pos, const VsglLobe& lobe) {
    const VsglIncomingSg<double> in = sglab::vsgl_incoming_sg<double>(pos, lobe.axis, lobe.sharpness);
    if (diffuse_receiver)
      diffuse += lobe.amplitude *
                 sglab::vsgl_clamped_cosine(in, p.normal, method);
    if (receiver) {
      const VsglSpecularFactor<double> f = sglab::vsgl_specular(in, *receiver);
      out.specular += lobe.amplitude * (f.at_f0_zero + p.f0 * (f.at_f0_one - f.at_f0_zero));
    }
  };
  for (const VsglCluster& c : set.clusters) {
    const VsglPositionalSg<double> pos = sglab::vsgl_positional_sg<double>(c.mean, c.variance, p.position, c.log_two_pi_variance);
    if (pos.empty) continue;
    if (c.has_diffuse) add(pos, c.diffuse);
    if (c.has_specular) add(pos, c.specular);
  }
  out.diffuse = diffuse * p.diffuse_reflectance / sglab::pi<double>();
  return out.total();
}

// ---- the setting -------------------------------------------------------------------------------

struct Setting {
  std::vector<ShadingPoint> points;
  std::size_t glossy_points = 0;
  ReflectiveShadowMap rsm;
  VplList vpls;
};

const Setting& setting() {
  static const Setting s = [] {
    std::ifstream file(std::string(SGLAB_SOURCE_DIR) + "/scenes/cornell-glossy.json");
    std::stringstream text;
    text << file.rdbuf();
    const Scene scene = parse_scene(parse_scene_text(text.str(), "cornell-glossy.json"));
    Setting out;
    const GBuffer g = render_gbuffer(scene);
    for (std::size_t k = 0; k < g.points.size(); ++k)
      if (g.hit[k]) {
        out.points.push_back(g.points[k]);
        out.glossy_points += g.points[k].glossy() ? 1 : 0;
      }
    out.rsm = render_rsm(scene, 64);
    out.vpls = prepare_vpls(out.rsm);
    return out;
  }();
  return s;
}

constexpr std::size_t kPointStride = 16;  // every 16th hit pixel: ~1k points per iteration

double relative_difference(const Rgb& a, const Rgb& b) {
  double worst = 0;
  for (int c = 0; c < 3; ++c) {
    const double scale = std::max(std::fabs(a(c)), std::fabs(b(c)));
    if (scale > 0) worst = std::max(worst, std::fabs(a(c) - b(c)) / scale);
  }
  return worst;
}

// peer = 1: the old loop; 0: the library; range(1) = 1: the library's float path (--precision float).
void BM_Reference(benchmark::State& state) {
  const Setting& s = setting();
  const bool peer = state.range(0) == 1;
  const Precision precision = state.range(1) == 1 ? Precision::single : Precision::double_;
  std::size_t points = 0;
  double worst = 0;
  for (auto _ : state) {
    for (std::size_t k = 0; k < s.points.size(); k += kPointStride) {
      const Rgb v = peer ? old_reference(s.points[k], s.vpls) : reference_radiance(s.points[k], s.vpls, nullptr, precision);
      benchmark::DoNotOptimize(v);
      ++points;
    }
  }
  for (std::size_t k = 0; k < s.points.size(); k += kPointStride)
    worst = std::max(worst, relative_difference(old_reference(s.points[k], s.vpls),
                                                reference_radiance(s.points[k], s.vpls, nullptr, precision)));
  const double pairs = double(points) * double(s.vpls.vpls.size());
  state.counters["ns_per_pixel_vpl"] = benchmark::Counter(pairs, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["vpls"] = double(s.vpls.vpls.size());
  state.counters["max_rel_diff"] = worst;
  state.SetLabel(peer ? "peer: old one-VPL-at-a-time loop"
                      : (precision == Precision::single ? "sglab: vectorized arrays, float" : "sglab: vectorized arrays"));
}
BENCHMARK(BM_Reference)->Args({1, 0})->Args({0, 0})->Args({0, 1})->ArgNames({"peer", "float"})->Unit(benchmark::kMillisecond);

// range(0): VSGL mode (0 = two, 1 = fis with range(1) clusters); range(2): peer; range(3): diffuse
// method, 0 = tokuyoshi2024 (the default; its evaluation dominates), 1 = punctual (D nearly free:
// what is left is the renderer's own cost per lobe); range(4) = 1: the float path (--precision float).
void BM_Shading(benchmark::State& state) {
  const Setting& s = setting();
  VsglOptions vo;
  vo.mode = state.range(0) == 0 ? VsglMode::two : VsglMode::fis;
  vo.count = int(state.range(1));
  const VsglSet set = build_vsgls(s.rsm, vo);
  const bool peer = state.range(2) == 1;
  const bool punctual = state.range(3) == 1;
  ShadingOptions options = shading_options(punctual ? "punctual" : "tokuyoshi2024");
  const bool single = state.range(4) == 1;
  if (single) options.precision = Precision::single;
  const VsglShader shader(set, options);
  auto old = [&](const ShadingPoint& p) {
    return punctual ? old_shading(p, set, [](double l, double c) { return sglab::clamped_cosine_punctual(l, c); })
                    : old_shading(p, set, [](double l, double c) { return sglab::clamped_cosine_tokuyoshi2024(l, c); });
  };
  // The library shades the points as `sglab render` does: many at once (VsglShader::shade).
  std::vector<ShadingPoint> timed;
  for (std::size_t k = 0; k < s.points.size(); k += kPointStride) timed.push_back(s.points[k]);
  std::vector<VsglShading> shaded(timed.size());
  std::size_t points = 0;
  for (auto _ : state) {
    if (peer) {
      for (const ShadingPoint& p : timed) benchmark::DoNotOptimize(old(p));
    } else {
      shader.shade(timed, shaded);
      benchmark::DoNotOptimize(shaded.data());
    }
    points += timed.size();
  }
  double worst = 0;
  shader.shade(timed, shaded);
  for (std::size_t i = 0; i < timed.size(); ++i) {
    worst = std::max(worst, relative_difference(old(timed[i]), shaded[i].total()));
    worst = std::max(worst, relative_difference(shader.shade(timed[i]).total(), shaded[i].total()));
  }
  const double pairs = double(points) * double(shader.lobes());
  state.counters["ns_per_pixel_lobe"] = benchmark::Counter(pairs, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["lobes"] = double(shader.lobes());
  state.counters["max_rel_diff"] = worst;
  state.SetLabel(std::string(peer ? "peer: old one-lobe-at-a-time loop" : "sglab: arrays + registry batch") +
                 (punctual ? ", punctual" : ", tokuyoshi2024") + (single ? ", float" : ""));
}
BENCHMARK(BM_Shading)
    ->Args({0, 2, 1, 0, 0})
    ->Args({0, 2, 0, 0, 0})
    ->Args({0, 2, 0, 0, 1})
    ->Args({1, 64, 1, 0, 0})
    ->Args({1, 64, 0, 0, 0})
    ->Args({1, 64, 0, 0, 1})
    ->Args({1, 64, 1, 1, 0})
    ->Args({1, 64, 0, 1, 0})
    ->ArgNames({"fis", "count", "peer", "punctual", "float"})
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
