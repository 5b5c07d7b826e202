// Upsampling indirect illumination with normal/depth-aware or lobe-aware weights (filtering.hpp).
#include "sglab/render/filtering.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sglab/brdf.hpp"
#include "sglab/enum_names.hpp"
#include "sglab/render/reference.hpp"
#include "sglab/render/rsm.hpp"
#include "sglab/render/vsgl_shading.hpp"
#include "filtering_detail.hpp"

namespace sglab::render {
namespace filtering_detail {

FilterSample sample_at(const Scene& scene, double px, double py, double pixel_angle) {
  FilterSample s;
  const Ray ray = camera_ray(scene.camera, px, py);
  const auto hit = cast_ray(scene, ray);
  if (!hit) return s;
  s.valid = true;
  s.point = shading_point(scene, *hit, -ray.direction);
  s.depth = hit->distance;
  s.footprint = hit->distance * pixel_angle;
  if (s.point.glossy()) {
    // The GGX lobe as an SG by the spherical warp (App. B): brdf.hpp's spherical_warp in the
    // world frame — axis = reflection of ω_o about n, λ_s = λ_h/(4|ω_o·n|), λ_h = 2/α².
    const double lambda_h = ndf_sharpness_wang(std::max(s.point.roughness, kMinRoughness));
    s.specular_axis = reflect_about(s.point.view, s.point.normal);
    s.specular_sharpness = lambda_h / (4 * std::max(std::fabs(s.point.view.dot(s.point.normal)), kMinWarpCosine));
  }
  return s;
}

// A part whose reflectance is 0 in a channel carries no light there, and is remodulated by 0.
Rgb demodulate(const Rgb& value, const Rgb& reflectance) {
  Rgb out = Rgb::Zero();
  for (int c = 0; c < 3; ++c)
    if (reflectance(c) > 0) out(c) = value(c) / reflectance(c);
  return out;
}

bool has_part(const FilterSample& s, bool specular) {
  if (!s.valid) return false;
  return specular ? s.point.glossy() : (s.point.diffuse_reflectance > 0).any();
}

void fill_full_gbuffer(const Scene& scene, const std::function<void(std::string_view, double)>& progress,
                       std::vector<FilterSample>& full, std::vector<char>& hit, std::vector<char>& glossy) {
  const Camera& cam = scene.camera;
  const std::size_t n = std::size_t(cam.width) * std::size_t(cam.height);
  full.assign(n, FilterSample{});
  hit.assign(n, 0);
  glossy.assign(n, 0);
  // One pixel's angle at the image centre: 2 tan(fov/2)/height.
  const double pixel_angle = 2 * std::tan(0.5 * cam.vertical_fov) / double(cam.height);
  for_each_pixel(cam.width, cam.height, "g-buffer", progress, [&](std::size_t k, int i, int j) {
    full[k] = sample_at(scene, i + 0.5, j + 0.5, pixel_angle);
    hit[k] = full[k].valid;
    glossy[k] = full[k].valid && full[k].point.glossy();
  });
}

std::pair<Rgb, Rgb> split_vpl_sum(const ShadingPoint& point, const VplList& vpls) {
  ShadingPoint d = point, g = point;
  d.f0 = Rgb::Zero();
  g.diffuse_reflectance = Rgb::Zero();
  return {reference_radiance(d, vpls), point.glossy() ? reference_radiance(g, vpls) : Rgb::Zero()};
}

void fill_reference(const std::vector<FilterSample>& full, const VplList& vpls, const std::vector<Rgb>* given,
                    int width, const std::function<void(std::string_view, double)>& progress,
                    std::vector<Rgb>& reference, double& seconds) {
  const std::size_t n = full.size();
  if (given) {
    if (given->size() != n)
      throw std::invalid_argument(fmt::format("the reference given has {} pixels, the image {}", given->size(), n));
    reference = *given;
    return;
  }
  const auto t0 = Clock::now();
  reference.assign(n, Rgb::Zero());
  reference_rows(
      width, int(n / std::size_t(width)), "reference (VPL sum)", progress, vpls, nullptr, Precision::double_,
      [&](std::size_t k) { return full[k].valid ? &full[k].point : nullptr; }, reference);
  seconds = seconds_since(t0);
}

RsmVpls render_rsm_vpls(const Scene& scene, int resolution, double& seconds) {
  const auto t0 = Clock::now();
  RsmVpls r{render_rsm(scene, resolution), {}};
  r.vpls = prepare_vpls(r.rsm);
  seconds = seconds_since(t0);
  return r;
}

ReceiverErrors receiver_errors(const std::vector<Rgb>& value, const std::vector<Rgb>& reference,
                               const std::vector<char>& hit, const std::vector<char>& glossy) {
  std::vector<char> diffuse_mask(hit.size(), 0);
  for (std::size_t k = 0; k < hit.size(); ++k) diffuse_mask[k] = hit[k] && !glossy[k];
  return {image_error(value, reference, hit), image_error(value, reference, glossy),
          image_error(value, reference, diffuse_mask)};
}

}  // namespace filtering_detail

using namespace filtering_detail;

namespace {
constexpr EnumName<FilterWeights> kFilterWeightsNames[] = {{FilterWeights::spatial, "spatial"},
                                                           {FilterWeights::normal, "normal"},
                                                           {FilterWeights::lobe, "lobe"},
                                                           {FilterWeights::lobe_depth, "lobe-depth"}};
constexpr EnumName<IndirectSource> kIndirectSourceNames[] = {{IndirectSource::exact, "exact"},
                                                             {IndirectSource::vsgl, "vsgl"}};
}  // namespace

std::optional<FilterWeights> parse_filter_weights(std::string_view name) {
  return parse_enum(kFilterWeightsNames, name);
}

std::string_view filter_weights_name(FilterWeights weights) { return enum_name(kFilterWeightsNames, weights); }

std::vector<std::string> filter_weights_names() { return enum_names(kFilterWeightsNames); }

std::vector<std::string> indirect_source_names() { return enum_names(kIndirectSourceNames); }

std::optional<IndirectSource> parse_indirect_source(std::string_view name) {
  return parse_enum(kIndirectSourceNames, name);
}

std::string_view indirect_source_name(IndirectSource source) { return enum_name(kIndirectSourceNames, source); }

std::optional<std::string> filter_parameters_error(const FilterParameters& p) {
  auto positive = [](double x) { return std::isfinite(x) && x > 0; };
  if (p.radius < 1 || p.radius > 16) return fmt::format("radius {} is outside [1, 16]", p.radius);
  if (!positive(p.spatial_sigma)) return fmt::format("spatial sigma {} is not a positive number", p.spatial_sigma);
  if (!positive(p.sigma_n2)) return fmt::format("sigma_n^2 {} is not a positive number", p.sigma_n2);
  if (!positive(p.depth_sigma)) return fmt::format("depth sigma {} is not a positive number", p.depth_sigma);
  if (!positive(p.beta)) return fmt::format("beta {} is not a positive number", p.beta);
  // κ = +∞ is allowed: no smoothing.
  if (!(p.kappa > 0)) return fmt::format("kappa {} is not positive", p.kappa);
  if (!(std::isfinite(p.nu) && p.nu >= 0)) return fmt::format("nu {} is not a non-negative number", p.nu);
  if (!positive(p.diffuse_sharpness))
    return fmt::format("diffuse sharpness {} is not a positive number", p.diffuse_sharpness);
  return std::nullopt;
}

double filter_range_weight(const FilterSample& p, const FilterSample& q, bool specular, FilterWeights weights,
                           const FilterParameters& a) {
  const auto depth = [&] {
    const double dz = p.depth - q.depth;
    const double sz = a.depth_sigma * p.depth;
    return gaussian_weight(dz * dz, sz * sz);
  };
  const auto lobes = [&] {
    return specular ? lobe_aware_weight(p.specular_axis, p.specular_sharpness, q.specular_axis, q.specular_sharpness,
                                        a.beta, a.kappa)
                    : lobe_aware_weight(p.point.normal, a.diffuse_sharpness, q.point.normal, a.diffuse_sharpness,
                                        a.beta, a.kappa);
  };
  switch (weights) {
    case FilterWeights::spatial: return 1.0;
    case FilterWeights::normal: return normal_weight(p.point.normal, q.point.normal, a.sigma_n2) * depth();
    case FilterWeights::lobe_depth: return lobes() * depth();
    case FilterWeights::lobe: {
      const double directional = lobes();
      if (directional == 0) return 0.0;
      const double nu2 = a.nu * a.nu;
      const double positional = gaussian_lobe_weight((p.point.position - q.point.position).squaredNorm(),
                                                     smoothed_variance(p.footprint * p.footprint, nu2),
                                                     smoothed_variance(q.footprint * q.footprint, nu2), a.beta, 3);
      return directional * positional;
    }
  }
  return 0.0;
}

namespace {

// The full- and low-resolution G-buffers (the low one at the centres of the scale × scale blocks,
// clamped into the image for a last, partial block).
void fill_gbuffers(const Scene& scene, const FilterInputOptions& o, FilterInputs& in) {
  const Camera& cam = scene.camera;
  const double pixel_angle = 2 * std::tan(0.5 * cam.vertical_fov) / double(cam.height);
  fill_full_gbuffer(scene, o.progress, in.full, in.hit, in.glossy);
  in.low.resize(std::size_t(in.low_width) * std::size_t(in.low_height));
  for_each_pixel(in.low_width, in.low_height, "g-buffer (low)", {}, [&](std::size_t k, int i, int j) {
    const double px = std::min(o.scale * (i + 0.5), double(in.width)),
                 py = std::min(o.scale * (j + 0.5), double(in.height));
    in.low[k] = sample_at(scene, px, py, o.scale * pixel_angle);
  });
}

// The low-resolution indirect light, split into its diffuse and specular parts.
void fill_low_res_indirect(const ReflectiveShadowMap& rsm, const VplList& vpls, const FilterInputOptions& o,
                           FilterInputs& in) {
  const std::size_t m = in.low.size();
  in.low_diffuse.assign(m, Rgb::Zero());
  in.low_specular.assign(m, Rgb::Zero());
  in.low_indirect.assign(m, Rgb::Zero());
  VsglSet vsgls;
  if (o.source == IndirectSource::vsgl) vsgls = build_vsgls(rsm, o.vsgl);
  const VsglShader shader(vsgls, o.shading);
  for_each_pixel(in.low_width, in.low_height, "low-res indirect", o.progress, [&](std::size_t k, int, int) {
    const FilterSample& s = in.low[k];
    if (!s.valid) return;
    Rgb diffuse, specular;
    if (o.source == IndirectSource::exact) {
      std::tie(diffuse, specular) = split_vpl_sum(s.point, vpls);
    } else {
      const VsglShading parts = shader.shade(s.point);
      diffuse = parts.diffuse;
      specular = parts.specular;
    }
    in.low_indirect[k] = diffuse + specular;
    in.low_diffuse[k] = demodulate(diffuse, s.point.diffuse_reflectance);
    in.low_specular[k] = demodulate(specular, s.point.f0);
  });
}

}  // namespace

FilterInputs prepare_filter_inputs(const Scene& scene, const FilterInputOptions& o) {
  if (o.scale < 1 || o.scale > 64) throw std::invalid_argument(fmt::format("scale {} is outside [1, 64]", o.scale));
  if (o.rsm_resolution < 1) throw std::invalid_argument(fmt::format("rsm resolution {} is below 1", o.rsm_resolution));
  if (o.source == IndirectSource::vsgl)
    if (const auto error = vsgl_options_error(o.vsgl)) throw std::invalid_argument(*error);

  FilterInputs in;
  const Camera& cam = scene.camera;
  in.width = cam.width;
  in.height = cam.height;
  in.scale = o.scale;
  in.source = o.source;
  in.low_width = (cam.width + o.scale - 1) / o.scale;
  in.low_height = (cam.height + o.scale - 1) / o.scale;
  auto t0 = Clock::now();
  fill_gbuffers(scene, o, in);
  in.seconds.gbuffer = seconds_since(t0);

  const auto [rsm, vpls] = render_rsm_vpls(scene, o.rsm_resolution, in.seconds.rsm);
  in.vpl_count = vpls.vpls.size();

  t0 = Clock::now();
  fill_low_res_indirect(rsm, vpls, o, in);
  in.seconds.low_res = seconds_since(t0);

  // seconds.reference stays 0 when the reference was given: nothing was computed.
  fill_reference(in.full, vpls, o.reference, in.width, o.progress, in.reference, in.seconds.reference);
  return in;
}

FilterResult upsample_indirect(const FilterInputs& in, FilterWeights weights, const FilterParameters& a) {
  if (const auto error = filter_parameters_error(a)) throw std::invalid_argument(*error);
  const auto t0 = Clock::now();
  FilterResult r;
  r.weights = weights;
  const std::size_t n = std::size_t(in.width) * std::size_t(in.height);
  r.upsampled.assign(n, Rgb::Zero());
  r.error.assign(n, Rgb::Zero());
  std::atomic<std::size_t> fallbacks{0};
  const double inv_two_sigma2 = 1 / (2 * a.spatial_sigma * a.spatial_sigma);

  for_each_pixel(in.width, in.height, "upsampling", {}, [&](std::size_t k, int i, int j) {
    const FilterSample& p = in.full[k];
    if (!p.valid) return;
    // p's position on the low-resolution grid, where sample (I, J) sits at (I, J).
    const double u = (i + 0.5) / in.scale - 0.5, v = (j + 0.5) / in.scale - 0.5;
    const int i0 = int(std::floor(u)) - a.radius + 1, j0 = int(std::floor(v)) - a.radius + 1;
    bool fell_back = false;
    Rgb total = Rgb::Zero();
    for (const bool specular : {false, true}) {
      if (!has_part(p, specular)) continue;
      const std::vector<Rgb>& values = specular ? in.low_specular : in.low_diffuse;
      Rgb sum = Rgb::Zero(), sum_spatial = Rgb::Zero();
      double weight = 0, weight_spatial = 0;
      for (int jj = j0; jj < j0 + 2 * a.radius; ++jj) {
        if (jj < 0 || jj >= in.low_height) continue;
        for (int ii = i0; ii < i0 + 2 * a.radius; ++ii) {
          if (ii < 0 || ii >= in.low_width) continue;
          const std::size_t q = std::size_t(jj) * std::size_t(in.low_width) + std::size_t(ii);
          if (!has_part(in.low[q], specular)) continue;
          const double ws = std::exp(-((ii - u) * (ii - u) + (jj - v) * (jj - v)) * inv_two_sigma2);
          const double w = ws * filter_range_weight(p, in.low[q], specular, weights, a);
          sum += w * values[q];
          weight += w;
          sum_spatial += ws * values[q];
          weight_spatial += ws;
        }
      }
      Rgb filtered = Rgb::Zero();
      if (weight > 0) {
        filtered = sum / weight;
      } else if (weight_spatial > 0) {
        filtered = sum_spatial / weight_spatial;
        fell_back = true;
      }
      total += filtered * (specular ? p.point.f0 : p.point.diffuse_reflectance);
    }
    if (fell_back) ++fallbacks;
    r.upsampled[k] = total;
    r.error[k] = total - in.reference[k];
  });

  r.fallback_pixels = fallbacks.load();
  set_receiver_errors(r, r.upsampled, in);
  r.seconds = seconds_since(t0);
  return r;
}

}  // namespace sglab::render
