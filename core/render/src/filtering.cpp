// Upsampling indirect illumination with normal/depth-aware or lobe-aware weights (filtering.hpp).
#include "sglab/render/filtering.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sglab/brdf.hpp"
#include "sglab/enum_names.hpp"
#include "sglab/render/reference.hpp"
#include "sglab/render/rsm.hpp"
#include "sglab/render/vsgl_shading.hpp"

namespace sglab::render {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Runs body(k) for k in [0, rows·width) in parallel over rows, reporting progress in 5 % steps.
template <class Body>
void for_each_row(int width, int rows, std::string_view stage,
                  const std::function<void(std::string_view, double)>& progress, const Body& body) {
  std::atomic<int> done{0}, reported{0};
  if (progress) progress(stage, 0.0);
  tbb::parallel_for(tbb::blocked_range<int>(0, rows), [&](const tbb::blocked_range<int>& r) {
    for (int j = r.begin(); j < r.end(); ++j) {
      for (int i = 0; i < width; ++i) body(std::size_t(j) * std::size_t(width) + std::size_t(i), i, j);
      const int n = ++done;
      if (progress) {
        const int step = 20 * n / rows;
        int last = reported.load();
        while (step > last && !reported.compare_exchange_weak(last, step)) {
        }
        if (step > last && step < 20) progress(stage, step / 20.0);
      }
    }
  });
  if (progress) progress(stage, 1.0);
}

// The sample seen through image point (px, py) (full-resolution pixel units) with its lobes.
// pixel_angle: the angle one pixel of this sample's grid subtends (its footprint is depth × that).
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

// Per-channel a/b with 0 where b is 0 (a part whose reflectance is 0 in a channel carries no light
// there, and is remodulated by 0).
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

}  // namespace

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
  if (!positive(p.diffuse_sharpness)) return fmt::format("diffuse sharpness {} is not a positive number", p.diffuse_sharpness);
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
    return specular ? lobe_aware_weight(p.specular_axis, p.specular_sharpness, q.specular_axis, q.specular_sharpness, a.beta, a.kappa)
                    : lobe_aware_weight(p.point.normal, a.diffuse_sharpness, q.point.normal, a.diffuse_sharpness, a.beta, a.kappa);
  };
  switch (weights) {
    case FilterWeights::spatial:
      return 1.0;
    case FilterWeights::normal:
      return normal_weight(p.point.normal, q.point.normal, a.sigma_n2) * depth();
    case FilterWeights::lobe_depth:
      return lobes() * depth();
    case FilterWeights::lobe: {
      const double directional = lobes();
      if (directional == 0) return 0.0;
      const double nu2 = a.nu * a.nu;
      const double positional =
          gaussian_lobe_weight((p.point.position - q.point.position).squaredNorm(), smoothed_variance(p.footprint * p.footprint, nu2),
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
  const std::size_t n = std::size_t(in.width) * std::size_t(in.height);
  // One pixel's angle at the image centre: 2 tan(fov/2)/height.
  const double pixel_angle = 2 * std::tan(0.5 * cam.vertical_fov) / double(cam.height);
  in.full.resize(n);
  in.low.resize(std::size_t(in.low_width) * std::size_t(in.low_height));
  in.hit.assign(n, 0);
  in.glossy.assign(n, 0);
  for_each_row(in.width, in.height, "g-buffer", o.progress, [&](std::size_t k, int i, int j) {
    in.full[k] = sample_at(scene, i + 0.5, j + 0.5, pixel_angle);
    in.hit[k] = in.full[k].valid;
    in.glossy[k] = in.full[k].valid && in.full[k].point.glossy();
  });
  for_each_row(in.low_width, in.low_height, "g-buffer (low)", {}, [&](std::size_t k, int i, int j) {
    const double px = std::min(o.scale * (i + 0.5), double(in.width)), py = std::min(o.scale * (j + 0.5), double(in.height));
    in.low[k] = sample_at(scene, px, py, o.scale * pixel_angle);
  });
}

// The low-resolution indirect light, split into its diffuse and specular parts.
void fill_low_res_indirect(const ReflectiveShadowMap& rsm, const VplList& vpls, const FilterInputOptions& o, FilterInputs& in) {
  const std::size_t m = in.low.size();
  in.low_diffuse.assign(m, Rgb::Zero());
  in.low_specular.assign(m, Rgb::Zero());
  in.low_indirect.assign(m, Rgb::Zero());
  VsglSet vsgls;
  if (o.source == IndirectSource::vsgl) vsgls = build_vsgls(rsm, o.vsgl);
  const VsglShader shader(vsgls, o.shading);
  for_each_row(in.low_width, in.low_height, "low-res indirect", o.progress, [&](std::size_t k, int, int) {
    const FilterSample& s = in.low[k];
    if (!s.valid) return;
    Rgb diffuse, specular;
    if (o.source == IndirectSource::exact) {
      // The exact VPL sum of each part: the same point with the other layer switched off.
      ShadingPoint d = s.point, g = s.point;
      d.f0 = Rgb::Zero();
      g.diffuse_reflectance = Rgb::Zero();
      diffuse = reference_radiance(d, vpls);
      specular = s.point.glossy() ? reference_radiance(g, vpls) : Rgb::Zero();
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
  const std::size_t n = std::size_t(in.width) * std::size_t(in.height);

  auto t0 = Clock::now();
  fill_gbuffers(scene, o, in);
  in.seconds.gbuffer = seconds_since(t0);

  t0 = Clock::now();
  const ReflectiveShadowMap rsm = render_rsm(scene, o.rsm_resolution);
  const VplList vpls = prepare_vpls(rsm);
  in.vpl_count = vpls.vpls.size();
  in.seconds.rsm = seconds_since(t0);

  t0 = Clock::now();
  fill_low_res_indirect(rsm, vpls, o, in);
  in.seconds.low_res = seconds_since(t0);

  t0 = Clock::now();
  if (o.reference) {
    if (o.reference->size() != n)
      throw std::invalid_argument(fmt::format("the reference given has {} pixels, the image {}", o.reference->size(), n));
    in.reference = *o.reference;
    return in;  // seconds.reference stays 0: nothing was computed
  }
  in.reference.assign(n, Rgb::Zero());
  for_each_row(in.width, in.height, "reference (VPL sum)", o.progress, [&](std::size_t k, int, int) {
    if (in.full[k].valid) in.reference[k] = reference_radiance(in.full[k].point, vpls);
  });
  in.seconds.reference = seconds_since(t0);
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

  for_each_row(in.width, in.height, "upsampling", {}, [&](std::size_t k, int i, int j) {
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
  std::vector<char> diffuse_mask(n, 0);
  for (std::size_t k = 0; k < n; ++k) diffuse_mask[k] = in.hit[k] && !in.glossy[k];
  r.all = image_error(r.upsampled, in.reference, in.hit);
  r.glossy = image_error(r.upsampled, in.reference, in.glossy);
  r.diffuse = image_error(r.upsampled, in.reference, diffuse_mask);
  r.seconds = seconds_since(t0);
  return r;
}

}  // namespace sglab::render
