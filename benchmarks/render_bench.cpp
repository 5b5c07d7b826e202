// ns per pixel·VPL of the exact VPL sum and ns per pixel·lobe of VSGL shading, each beside its
// peer in the same run: a straight port of the one-term-at-a-time loop the renderer used before
// it was vectorized (kept here only, not in the library). Scene: scenes/cornell-glossy.json, a 64²
// RSM (as `sglab render`'s default), shading points from its 128² G-buffer (every hit pixel).
// One thread (CPU time); `sglab render` runs the same per-pixel code on every core (TBB). The
// "max_rel_diff" counter is the largest relative difference between the two paths over the
// points timed (per channel, relative to the channel's value). Run:
//   build/benchmarks/sglab_render_bench [--benchmark_filter=Reference]
// SGLAB_RENDER_BENCH_RSM=N takes an N² RSM instead (8 to 1024): 128 gives the render sweeps'
// 13 104 VPLs, whose arrays no longer fit in a core's second-level cache (docs/testing.md, "Tried,
// not kept: the VPL arrays in chunks").
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "bench_args.hpp"
#include "peak.hpp"

#include "sglab/clamped_cosine.hpp"
#include "sglab/render/material_brdf.hpp"
#include "sglab/render/raycast.hpp"
#include "sglab/render/reference.hpp"
#include "sglab/render/rsm.hpp"
#include "sglab/render/scene.hpp"
#include "sglab/render/shadow_map.hpp"
#include "sglab/render/vsgl_generation.hpp"
#include "sglab/render/vpl.hpp"
#include "sglab/render/visibility.hpp"
#include "sglab/render/vsgl_shading.hpp"
#include "sglab/render/vsgl_specular_methods.hpp"
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
    if (diffuse_receiver) diffuse += lobe.amplitude * sglab::vsgl_clamped_cosine(in, p.normal, method);
    if (receiver) {
      const VsglSpecularFactor<double> f = sglab::vsgl_specular(in, *receiver);
      out.specular += lobe.amplitude * (f.at_f0_zero + p.f0 * (f.at_f0_one - f.at_f0_zero));
    }
  };
  for (const VsglCluster& c : set.clusters) {
    const VsglPositionalSg<double> pos = sglab::vsgl_positional_sg<double>(c.mean, c.variance, p.position,
                                                                           c.log_two_pi_variance);
    if (pos.empty) continue;
    if (c.has_diffuse) add(pos, c.diffuse);
    if (c.has_specular) add(pos, c.specular);
  }
  out.diffuse = diffuse * p.diffuse_reflectance / sglab::pi<double>();
  return out.total();
}

// ---- the setting -------------------------------------------------------------------------------

struct Setting {
  Scene scene;
  std::vector<ShadingPoint> points;
  std::size_t glossy_points = 0;
  ReflectiveShadowMap rsm;
  VplList vpls;
};

// The RSM's texels per side: SGLAB_RENDER_BENCH_RSM, or 64. A bad value ends the run with status 2.
int rsm_texels() {
  const char* text = std::getenv("SGLAB_RENDER_BENCH_RSM");
  if (!text) return 64;
  const auto n = sglab::bench::integer_in(text, 8, 1024);
  if (!n) {
    std::fprintf(stderr, "SGLAB_RENDER_BENCH_RSM: '%s' is not an integer in [8, 1024]\n", text);
    std::exit(2);
  }
  return int(*n);
}

const Setting& setting() {
  static const Setting s = [] {
    std::ifstream file(std::string(SGLAB_SOURCE_DIR) + "/scenes/cornell-glossy.json");
    std::stringstream text;
    text << file.rdbuf();
    Setting out;
    out.scene = parse_scene(parse_scene_text(text.str(), "cornell-glossy.json"));
    const Scene& scene = out.scene;
    const GBuffer g = render_gbuffer(scene);
    for (std::size_t k = 0; k < g.points.size(); ++k)
      if (g.hit[k]) {
        out.points.push_back(g.points[k]);
        out.glossy_points += g.points[k].glossy() ? 1 : 0;
      }
    out.rsm = render_rsm(scene, rsm_texels());
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

// ---- the VPL sum's arithmetic bound ---------------------------------------------------------------
// Operations per (pixel, VPL) term of render_kernels_vpl.hpp vpl_sum_blocks, counted from its formula
// with every receiver-only quantity hoisted out of the loop (the fewest the formula allows), as
// multiplies + adds (a subtraction is an add):
//   the term itself: ω = (y − x)/|y − x| (3 sub, |·|² 3 + 2, 1 sqrt, 1 div, 3 mul), the two cosines
//     (3 + 2 each), the Lambert factors (3 + 3 mul), 1/(d² + r²) (1 add, 1 div), the three channel
//     sums e·q·k (6 mul, 3 add): 24 + 13 = 37 arithmetic, 2 div, 1 sqrt;
//   a GGX layer (ggx_layer + Schlick): h = ω_o + ω_i (3 add), |h|² (3 + 2), 1 sqrt, 1 div, h·(1/|h|)
//     (3 mul), α² (1 mul), n·h (3 + 2), the NDF's denominator (1 + 2 for (1 − c)(1 + c), 2 + 1 for
//     dn), π·dn² (2 mul) and 1 div, the two Smith roots (3 + 3 each, 2 sqrt), their sum (2 + 1),
//     1/(2·den) (1 mul, 1 div), D·V·cos (2 mul), ω_o·h (3 + 2): 29 + 19 = 48; Schlick's (1 − c)⁵
//     (3 + 1) and per channel f0 + (1 − f0)·m⁵ (1 + 2). With the VPL's layer (its incoming side's
//     Smith root one per VPL, in its arrays: ggx_smith_root) 29 − 3 + 3 + 3·1 + 3·2 (its flux
//     products) = 38 multiplies and 19 − 3 + 1 + 3·2 + 3·1 = 26 adds, 3 div, 2 sqrt; the receiver's
//     (α², its own Smith root and 1 − f0 hoisted) 29 − 4 + 3 + 3 + 3·1 (its products with F) = 34
//     multiplies and 19 − 3 + 1 + 3 + 3 = 23 adds, 3 div, 2 sqrt.
// In float a GGX layer forms the NDF's sin²θ_h as |n × h|² (6 + 3 for n × h, 3 + 2 for its squared
// length) instead of (1 − c)(1 + c) (1 + 2): 8 multiplies and 3 adds more per layer (kFloatLayer).
// Every term is counted, though the sum skips blocks of terms that are all off (vpl_sum_blocks).
// Multiplies and adds run on the vector pipes (no fused multiply-add: -ffp-contract=off), divisions
// and square roots on the one divider. The bound per term is the largest of the times the
// multiplies and adds take together at the mixed rate, the multiplies alone at the multiply rate,
// the adds alone at the add rate (on a core whose multiplies and adds have pipes of their own, the
// larger of the two counts at half the mixed rate: peak.hpp), and the divider's time, at the rates
// peak.hpp measures for the instruction set the renderer's loops run on (peak_rates). Until
// 2026-12-06 it counted 32 instead of the 37 its own list adds up to for the term itself, and took
// multiplies and adds as one pool.
struct TermOps {
  double mul, add, div, sqrt;
};
constexpr TermOps kTermBase = {24, 13, 2, 1}, kVplLayer = {38, 26, 3, 2}, kReceiverLayer = {34, 23, 3, 2},
                  kFloatLayer = {8, 3, 0, 0};

// The bound in ns for one term of kind k (2·glossy VPL + glossy receiver), in double or float.
double term_bound_ns(int k, bool single, const sglab::bench::Rates& r) {
  TermOps o = kTermBase;
  const auto add_layer = [&o, single](const TermOps& l) {
    o = {o.mul + l.mul, o.add + l.add, o.div + l.div, o.sqrt + l.sqrt};
    if (single) o = {o.mul + kFloatLayer.mul, o.add + kFloatLayer.add, o.div, o.sqrt};
  };
  if (k & 2) add_layer(kVplLayer);
  if (k & 1) add_layer(kReceiverLayer);
  const double mixed = (o.mul + o.add) / (single ? r.mul_add_f : r.mul_add);
  const double muls = o.mul / (single ? r.mul_f : r.mul), adds = o.add / (single ? r.add_f : r.add);
  const double divider = o.div / (single ? r.div_f : r.div) + o.sqrt / (single ? r.sqrt_f : r.sqrt);
  return 1e9 * std::max({mixed, muls, adds, divider});
}

// The rates of the instruction set the renderer's loops run on (sglab::render::kernel_isa(): the
// widest the CPU supports, or SGLAB_SIMD's): AVX-512's for the AVX-512 kernels, else AVX2's (the
// SSE2 kernels too, whose bound is then one they cannot reach by their vectors' width).
const sglab::bench::Rates& peak_rates() {
  static const sglab::bench::Rates r = [] {
    return sglab::render::kernel_isa() == "avx512" ? sglab::bench::rates_avx512() : sglab::bench::rates_avx2();
  }();
  return r;
}

// peer = 1: the old loop; 0: the library; range(1) = 1: the library's float path (--precision float).
// "bound_ns_per_pixel_vpl": the arithmetic bound above over the timed points' mix of terms (the
// achieved/bound ratio is ns_per_pixel_vpl over it).
void BM_Reference(benchmark::State& state) {
  const Setting& s = setting();
  const bool peer = state.range(0) == 1;
  const Precision precision = state.range(1) == 1 ? Precision::single : Precision::double_;
  std::size_t points = 0;
  double worst = 0;
  std::vector<const ShadingPoint*> timed;
  for (std::size_t k = 0; k < s.points.size(); k += kPointStride) timed.push_back(&s.points[k]);
  std::vector<Rgb> values(timed.size());
  for (auto _ : state) {
    if (peer) {
      for (const ShadingPoint* p : timed) benchmark::DoNotOptimize(old_reference(*p, s.vpls));
    } else {
      reference_radiances(timed, s.vpls, values, nullptr, precision);
      benchmark::DoNotOptimize(values.data());
    }
    points += timed.size();
  }
  for (std::size_t k = 0; k < s.points.size(); k += kPointStride)
    worst = std::max(worst, relative_difference(old_reference(s.points[k], s.vpls),
                                                reference_radiance(s.points[k], s.vpls, nullptr, precision)));
  const double pairs = double(points) * double(s.vpls.vpls.size());
  state.counters["ns_per_pixel_vpl"] = benchmark::Counter(pairs,
                                                          benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["vpls"] = double(s.vpls.vpls.size());
  {
    std::size_t glossy_vpls = 0, n = 0;
    for (const Vpl& v : s.vpls.vpls) glossy_vpls += v.glossy() ? 1 : 0;
    const double plain_vpls = double(s.vpls.vpls.size() - glossy_vpls);
    double bound = 0;
    for (std::size_t k = 0; k < s.points.size(); k += kPointStride, ++n) {
      const int receiver = s.points[k].glossy() ? 1 : 0;
      bound += plain_vpls * term_bound_ns(receiver, precision == Precision::single, peak_rates()) +
               double(glossy_vpls) * term_bound_ns(2 + receiver, precision == Precision::single, peak_rates());
    }
    bound /= double(n) * double(s.vpls.vpls.size());
    state.counters["bound_ns_per_pixel_vpl"] = bound;
  }
  state.counters["max_rel_diff"] = worst;
  state.SetLabel(
      peer ? "peer: old one-VPL-at-a-time loop"
           : (precision == Precision::single ? "sglab: vectorized arrays, float" : "sglab: vectorized arrays"));
}
BENCHMARK(BM_Reference)
    ->Args({1, 0})
    ->Args({0, 0})
    ->Args({0, 1})
    ->ArgNames({"peer", "float"})
    ->Unit(benchmark::kMillisecond);

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
  state.counters["ns_per_pixel_lobe"] = benchmark::Counter(pairs,
                                                           benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
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

// The setting's VSGLs by modified FIS with `count` clusters.
VsglSet fis_vsgls(const Setting& s, int count) {
  VsglOptions vo;
  vo.mode = VsglMode::fis;
  vo.count = count;
  return build_vsgls(s.rsm, vo);
}

// VSGL shading with visibility (`sglab render --visibility`), fis 64, cube maps of 64² per face:
// range(0) = 1, the peer: the loop the renderer ran before (each point alone: its clusters' cube
// map lookups, then VsglShader::shade of that one point); 0: the renderer's loop now (a row's
// points at once: the lookups vectorized over the points one cluster's map at a time
// (cube_visibility), then the points shaded in blocks with the (point, cluster) visibility as a
// mask). Both include the lookups; ns per pixel·lobe. The maps are built once, outside the loop
// (BM_CubeShadowMaps times them).
void BM_ShadingVisibility(benchmark::State& state) {
  const Setting& s = setting();
  const VsglSet set = fis_vsgls(s, 64);
  const std::vector<CubeShadowMap> maps = vsgl_shadow_maps(s.scene, set, 64);
  const VsglShader shader(set, shading_options("tokuyoshi2024"));
  const bool peer = state.range(0) == 1;
  std::vector<ShadingPoint> timed;
  for (std::size_t k = 0; k < s.points.size(); k += kPointStride) timed.push_back(s.points[k]);
  const std::size_t clusters = maps.size();
  std::vector<VsglShading> shaded(timed.size());
  std::vector<char> visible(timed.size() * clusters);
  auto run = [&] {
    if (peer) {
      for (std::size_t i = 0; i < timed.size(); ++i) {
        std::vector<char> v(clusters);
        for (std::size_t c = 0; c < clusters; ++c) v[c] = maps[c].lit(timed[i].position, timed[i].normal) ? 1 : 0;
        shaded[i] = shader.shade(timed[i], v);
      }
    } else {
      cube_visibility(maps, timed, visible);
      shader.shade(timed, visible, shaded);
    }
  };
  std::size_t points = 0;
  for (auto _ : state) {
    run();
    benchmark::DoNotOptimize(shaded.data());
    points += timed.size();
  }
  // The two paths against each other on the points timed.
  run();
  const std::vector<VsglShading> mine = shaded;
  double worst = 0;
  for (std::size_t i = 0; i < timed.size(); ++i) {
    std::vector<char> v(clusters);
    for (std::size_t c = 0; c < clusters; ++c) v[c] = maps[c].lit(timed[i].position, timed[i].normal) ? 1 : 0;
    worst = std::max(worst, relative_difference(shader.shade(timed[i], v).total(), mine[i].total()));
  }
  const double pairs = double(points) * double(shader.lobes());
  state.counters["ns_per_pixel_lobe"] = benchmark::Counter(pairs,
                                                           benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["lobes"] = double(shader.lobes());
  state.counters["max_rel_diff"] = worst;
  state.SetLabel(peer ? "peer: one point at a time (lookups, then shade)"
                      : "sglab: a row's lookups, then blocks with a mask");
}
BENCHMARK(BM_ShadingVisibility)->Arg(1)->Arg(0)->ArgNames({"peer"})->Unit(benchmark::kMillisecond);

// The cube shadow maps of `sglab render --visibility` (one per cluster, six faces each): range(0) = 1,
// the peer: the loop render_shadow_map ran before (cast_ray texel by texel, kept here only);
// 0: the library's (a row's rays at once, vectorized over them). One map of 64² per face at the
// first cluster's μ_v, on one thread; ns per ray. "max_abs_diff": the largest depth difference
// between the two (the same arithmetic: 0).
void BM_CubeShadowMaps(benchmark::State& state) {
  const Setting& s = setting();
  const Vec3 origin = fis_vsgls(s, 64).clusters.front().mean;
  const bool peer = state.range(0) == 1;
  constexpr int kResolution = 64;
  auto old_map = [&](const LightView& view) {
    ShadowMap m;
    m.view = view;
    m.depth.assign(std::size_t(kResolution) * kResolution, std::numeric_limits<double>::infinity());
    const double t = view.texel_size();
    for (int j = 0; j < kResolution; ++j)
      for (int i = 0; i < kResolution; ++i)
        if (const auto hit = cast_ray(s.scene, view.ray(view.x_lo(i) + 0.5 * t, view.y_lo(j) + 0.5 * t)))
          m.depth[std::size_t(j) * kResolution + std::size_t(i)] = hit->distance;
    return m;
  };
  const CubeShadowMap library = render_cube_shadow_map(s.scene, origin, kResolution);
  const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  std::size_t rays = 0;
  for (auto _ : state) {
    if (peer) {
      for (const ShadowMap& face : library.faces) benchmark::DoNotOptimize(old_map(face.view).depth.data());
    } else {
      // One face at a time on this thread, as the peer (TBB held to one thread above).
      for (const ShadowMap& face : library.faces)
        benchmark::DoNotOptimize(render_shadow_map(s.scene, face.view).depth.data());
    }
    rays += 6 * std::size_t(kResolution) * kResolution;
  }
  double worst = 0;
  for (const ShadowMap& face : library.faces) {
    const ShadowMap old = old_map(face.view);
    for (std::size_t k = 0; k < old.depth.size(); ++k)
      if (old.depth[k] != face.depth[k]) worst = std::max(worst, std::fabs(old.depth[k] - face.depth[k]));
  }
  state.counters["ns_per_ray"] = benchmark::Counter(double(rays),
                                                    benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["max_abs_diff"] = worst;
  state.SetLabel(peer ? "peer: cast_ray texel by texel" : "sglab: a row's rays at once");
}
BENCHMARK(BM_CubeShadowMaps)->Arg(1)->Arg(0)->ArgNames({"peer"})->Unit(benchmark::kMillisecond);

// The specular term by a registry method (`sglab render --specular METHOD`) against the built-in
// vsgl-asg (the same ASG × SG formula as the registry's `asg`), fis 64, the diffuse part with
// `punctual` (nearly free) so that the specular shading dominates; only the glossy points are
// timed. range(0): 0 = vsgl-asg (built in), 1 = asg, 2 = sg-warp, 3 = sglab (registry methods).
void BM_SpecularMethod(benchmark::State& state) {
  const Setting& s = setting();
  const VsglSet set = fis_vsgls(s, 64);
  static const char* const kNames[] = {"vsgl-asg", "asg", "sg-warp", "sglab"};
  const char* name = kNames[state.range(0)];
  ShadingOptions options = shading_options("punctual");
  options.specular_method = find_specular_method(name);
  const VsglShader shader(set, options);
  std::vector<ShadingPoint> timed;
  for (std::size_t k = 0; k < s.points.size(); k += kPointStride / 4)
    if (s.points[k].glossy()) timed.push_back(s.points[k]);
  std::vector<VsglShading> shaded(timed.size());
  std::size_t points = 0;
  for (auto _ : state) {
    shader.shade(timed, shaded);
    benchmark::DoNotOptimize(shaded.data());
    points += timed.size();
  }
  const double pairs = double(points) * double(shader.lobes());
  state.counters["ns_per_pixel_lobe"] = benchmark::Counter(pairs,
                                                           benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["points"] = double(timed.size());
  state.SetLabel(std::string("specular ") + name + (state.range(0) == 0 ? " (built in)" : " (registry batch)"));
}
BENCHMARK(BM_SpecularMethod)->DenseRange(0, 3)->ArgNames({"method"})->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  rsm_texels();  // a bad SGLAB_RENDER_BENCH_RSM ends the run here, before any output (status 2)
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
