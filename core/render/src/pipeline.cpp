// The renderer's stages, timed (pipeline.hpp).
#include "sglab/render/pipeline.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sglab/error_metrics.hpp"
#include "sglab/render/reference.hpp"
#include "sglab/render/rsm.hpp"
#include "sglab/render/shadow_map.hpp"
#include "sglab/render/visibility.hpp"
#include "row_loop.hpp"

namespace sglab::render {
namespace {

// Runs body(k) for every pixel k with hit[k], parallel over rows.
template <class Body>
void for_each_hit(const GBuffer& g, std::string_view stage, const RenderOptions& o, const Body& body) {
  for_each_pixel(g.width, g.height, stage, o.progress, [&](std::size_t k, int, int) {
    if (g.hit[k]) body(k);
  });
}

}  // namespace

ImageError image_error(const std::vector<Rgb>& value, const std::vector<Rgb>& reference,
                       const std::vector<char>& mask) {
  metrics::ErrorSums sums;
  for (std::size_t k = 0; k < value.size(); ++k) {
    if (!mask[k]) continue;
    for (int c = 0; c < 3; ++c) sums.add(value[k](c), reference[k](c));
  }
  return {sums.rmse(), sums.mean_smape(), sums.relative_l2(), sums.max_abs, sums.samples};
}

namespace {

void check_render_options(const RenderOptions& o, const std::vector<VsglOptions>& variants) {
  if (o.rsm_resolution < 1)
    throw std::invalid_argument("rsm resolution " + std::to_string(o.rsm_resolution) + " is below 1");
  if (o.visibility && (o.visibility_map_resolution < 1 || o.visibility_map_resolution > 4096))
    throw std::invalid_argument("visibility map resolution " + std::to_string(o.visibility_map_resolution) +
                                " is outside [1, 4096]");
  if (o.shadow_map_resolution < 1)
    throw std::invalid_argument("shadow map resolution " + std::to_string(o.shadow_map_resolution) + " is below 1");
  for (const auto& v : variants)
    if (const auto error = vsgl_options_error(v)) throw std::invalid_argument(*error);
}

// Every hit pixel shaded by the VSGLs into v.indirect.
void shade_vsgls(const Scene& scene, const RenderOptions& o, const GBuffer& g, const VsglShader& shader,
                 RenderResult& v) {
  std::vector<CubeShadowMap> maps;
  if (o.visibility) maps = vsgl_shadow_maps(scene, v.vsgls, o.visibility_map_resolution);
  // A row's hit pixels at once, so that the diffuse method runs on wide batches (per-thread
  // arrays, reused row after row); with visibility, the row's shadow-map lookups first, one
  // cluster's cube map at a time over the row's points (vectorized, cube_visibility), then the row
  // shaded in blocks with its (point, cluster) visibility as a mask.
  for_each_row(g.height, "vsgl shading", o.progress, [&](int j) {
    thread_local std::vector<ShadingPoint> points;
    thread_local std::vector<std::size_t> pixels;
    thread_local std::vector<VsglShading> shaded;
    thread_local std::vector<char> visible;
    points.clear();
    pixels.clear();
    for (int i = 0; i < g.width; ++i) {
      const std::size_t k = std::size_t(j) * std::size_t(g.width) + std::size_t(i);
      if (g.hit[k]) {
        points.push_back(g.points[k]);
        pixels.push_back(k);
      }
    }
    shaded.resize(points.size());
    if (o.visibility) {
      visible.resize(points.size() * maps.size());
      cube_visibility(maps, points, visible);
      shader.shade(points, visible, shaded);
    } else {
      shader.shade(points, shaded);
    }
    for (std::size_t i = 0; i < pixels.size(); ++i) v.indirect[pixels[i]] = shaded[i].total();
  });
}

// One variant: its VSGLs from the shared RSM, their shading and the error against the reference.
RenderResult render_variant(const Scene& scene, const RenderOptions& o, const CommonPass& c,
                            const VsglOptions& variant) {
  RenderResult v = c.result;
  const std::size_t n = std::size_t(v.width) * std::size_t(v.height);
  v.indirect.assign(n, Rgb::Zero());
  v.error.assign(n, Rgb::Zero());
  auto t0 = Clock::now();
  v.vsgls = build_vsgls(c.rsm, variant);
  v.seconds.vsgl = seconds_since(t0);
  // No glossy receiver in view, or no specular VSGL: no specular shading at all.
  ShadingOptions shading = o.shading;
  shading.specular = shading.specular && v.glossy_receivers > 0 && v.vsgls.stats.specular_vsgls > 0;
  v.specular_shading = shading.specular;
  v.asg_evaluations = shading.specular ? v.glossy_receivers * v.vsgls.stats.specular_vsgls : 0;
  t0 = Clock::now();
  const VsglShader shader(v.vsgls, shading);
  shade_vsgls(scene, o, c.g, shader, v);
  v.seconds.shading = seconds_since(t0);
  for (std::size_t k = 0; k < n; ++k) v.error[k] = v.indirect[k] - v.indirect_reference[k];
  v.error_metrics = image_error(v.indirect, v.indirect_reference, v.hit);
  return v;
}

}  // namespace

CommonPass render_common(const Scene& scene, const RenderOptions& o) {
  check_render_options(o, {});
  CommonPass c;
  RenderResult& r = c.result;
  r.width = scene.camera.width;
  r.height = scene.camera.height;
  const std::size_t n = std::size_t(r.width) * std::size_t(r.height);
  r.direct.assign(n, Rgb::Zero());
  r.indirect_reference.assign(n, Rgb::Zero());

  auto t0 = Clock::now();
  c.g = render_gbuffer(scene);
  const GBuffer& g = c.g;
  r.seconds.gbuffer = seconds_since(t0);
  r.hit = g.hit;
  for (std::size_t k = 0; k < n; ++k)
    if (g.hit[k]) {
      ++r.pixels_hit;
      if (g.points[k].glossy()) ++r.glossy_receivers;
    }

  if (o.direct) {
    t0 = Clock::now();
    const ShadowMap shadow = render_shadow_map(scene, o.shadow_map_resolution);
    r.seconds.shadow_map = seconds_since(t0);
    t0 = Clock::now();
    for_each_hit(g, "direct", o, [&](std::size_t k) { r.direct[k] = direct_radiance(scene, shadow, g.points[k]); });
    r.seconds.direct = seconds_since(t0);
  }

  t0 = Clock::now();
  c.rsm = render_rsm(scene, o.rsm_resolution);
  const VplList vpls = prepare_vpls(c.rsm);
  r.seconds.rsm = seconds_since(t0);
  r.vpl_count = vpls.vpls.size();
  for (const Vpl& v : vpls.vpls) {
    r.rsm_flux += v.flux;
    if (v.glossy()) ++r.glossy_vpls;
  }

  t0 = Clock::now();
  reference_rows(
      g.width, g.height, "reference (VPL sum)", o.progress, vpls, o.visibility ? &scene : nullptr,
      o.reference_precision.value_or(o.shading.precision),
      [&](std::size_t k) { return g.hit[k] ? &g.points[k] : nullptr; }, r.indirect_reference);
  r.seconds.reference = seconds_since(t0);
  return c;
}

std::vector<RenderResult> render_scene_variants(const Scene& scene, const RenderOptions& o,
                                                const std::vector<VsglOptions>& variants) {
  check_render_options(o, variants);
  return render_scene_variants(scene, o, render_common(scene, o), variants);
}

std::vector<RenderResult> render_scene_variants(const Scene& scene, const RenderOptions& o, const CommonPass& common,
                                                const std::vector<VsglOptions>& variants) {
  check_render_options(o, variants);
  std::vector<RenderResult> results;
  for (const VsglOptions& variant : variants) results.push_back(render_variant(scene, o, common, variant));
  return results;
}

RenderResult render_scene(const Scene& scene, const RenderOptions& o) {
  return std::move(render_scene_variants(scene, o, {o.vsgl}).front());
}

}  // namespace sglab::render
