// Filtering noisy indirect illumination: the noisy VPL-subset input and the cross-bilateral filter
// (denoise.hpp).
#include "sglab/render/denoise.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <tuple>

#include <fmt/format.h>

#include "sglab/render/reference.hpp"
#include "sglab/render/rsm.hpp"
#include "filtering_detail.hpp"

namespace sglab::render {
namespace {

using namespace filtering_detail;

constexpr int kMaxSubsetSide = 64;         // M: at most 4096 subsets
constexpr int kMaxVplsPerPixel = 1 << 20;  // K
constexpr int kDefaultRandomRadius = 4;
// δ of the defensive mixture p_i = (1 − δ)P_i/ΣP + δ/N (Hesterberg 1995): every VPL keeps p_i ≥ δ/N,
// so that a VPL whose reflected power is 0 but whose term is not (none is expected: both are
// proportional to Φ_i) would still be sampled. A choice, not a published value.
constexpr double kUniformFraction = 0.1;

// SplitMix64 (Steele, Lea & Flood 2014): a well-mixed 64-bit value per (seed, stream).
std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// A uniform double in [0, 1) from the top 53 bits.
double unit_double(std::uint64_t x) { return double(x >> 11) * 0x1.0p-53; }

// The pdf of random:K and its cumulative sum.
struct VplSampler {
  std::vector<double> pdf, cdf;
  explicit VplSampler(const std::vector<Vpl>& vpls) {
    const std::size_t n = vpls.size();
    std::vector<double> power(n);
    double total = 0;
    for (std::size_t i = 0; i < n; ++i) {
      power[i] = (vpls[i].flux * (vpls[i].diffuse_reflectance + vpls[i].specular_reflectance)).sum();
      total += power[i];
    }
    pdf.resize(n);
    cdf.resize(n);
    double running = 0;
    for (std::size_t i = 0; i < n; ++i) {
      pdf[i] = (total > 0 ? (1 - kUniformFraction) * power[i] / total : 0.0) +
               (total > 0 ? kUniformFraction : 1.0) / double(n);
      running += pdf[i];
      cdf[i] = running;
    }
  }
  std::size_t draw(double u) const {  // u in [0, 1): the index whose cdf interval holds u·cdf.back()
    const auto at = std::upper_bound(cdf.begin(), cdf.end(), u * cdf.back());
    return std::min(std::size_t(at - cdf.begin()), cdf.size() - 1);
  }
};

// K VPLs drawn for pixel k, each with flux ×1/(K p_i).
void draw_pixel_vpls(const VplList& all, const VplSampler& sampler, int count, std::uint64_t seed, std::size_t pixel,
                     VplList& out) {
  out.vpls.clear();
  out.any_glossy = false;
  std::uint64_t state = splitmix64(seed ^ splitmix64(pixel + 1));
  for (int d = 0; d < count; ++d) {
    state = splitmix64(state);
    const std::size_t i = sampler.draw(unit_double(state));
    out.vpls.push_back(all.vpls[i]);
    out.vpls.back().flux *= 1 / (double(count) * sampler.pdf[i] / sampler.cdf.back());
    out.any_glossy = out.any_glossy || all.vpls[i].glossy();
  }
  prepare_vpl_arrays(out);
}

}  // namespace

std::vector<VplList> interleaved_vpl_subsets(const VplList& vpls, int m, std::uint64_t seed) {
  if (m < 1 || m > kMaxSubsetSide)
    throw std::invalid_argument(fmt::format("M = {} is outside [1, {}]", m, kMaxSubsetSide));
  const std::uint64_t subsets = std::uint64_t(m) * std::uint64_t(m);
  std::vector<VplList> out(subsets);
  const double weight = double(subsets);
  const std::uint64_t stream = splitmix64(seed);
  for (std::size_t i = 0; i < vpls.vpls.size(); ++i) {
    const Vpl& vpl = vpls.vpls[i];
    // Uniform over the M² subsets up to 2^-64·M² (a 64-bit value modulo M² ≤ 4096).
    VplList& s = out[splitmix64(stream ^ splitmix64(i + 1)) % subsets];
    s.vpls.push_back(vpl);
    s.vpls.back().flux *= weight;
    s.any_glossy = s.any_glossy || vpl.glossy();
  }
  for (VplList& s : out) prepare_vpl_arrays(s);
  return out;
}

std::optional<NoisySpec> parse_noisy_spec(std::string_view text) {
  const auto colon = text.find(':');
  if (colon == std::string_view::npos) return std::nullopt;
  const std::string_view mode = text.substr(0, colon), number = text.substr(colon + 1);
  int count = 0;
  const auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), count);
  if (ec != std::errc() || end != number.data() + number.size() || number.empty()) return std::nullopt;
  if (mode == "interleaved" && count >= 1 && count <= kMaxSubsetSide) return NoisySpec{NoisyMode::interleaved, count};
  if (mode == "random" && count >= 1 && count <= kMaxVplsPerPixel) return NoisySpec{NoisyMode::random, count};
  return std::nullopt;
}

std::string noisy_spec_name(const NoisySpec& spec) {
  return fmt::format("{}:{}", spec.mode == NoisyMode::interleaved ? "interleaved" : "random", spec.count);
}

int default_denoise_radius(const NoisySpec& spec) {
  return spec.mode == NoisyMode::interleaved ? spec.count : kDefaultRandomRadius;
}

std::optional<std::string> denoise_radius_error(const NoisySpec& spec, int radius) {
  if (radius < 1 || radius > 16) return fmt::format("radius {} is outside [1, 16]", radius);
  if (spec.mode == NoisyMode::interleaved && radius < spec.count)
    return fmt::format("radius {} is below M = {}: the window would not see every interleaved subset", radius,
                       spec.count);
  return std::nullopt;
}

DenoiseInputs prepare_denoise_inputs(const Scene& scene, const DenoiseInputOptions& o) {
  const int count_max = o.noisy.mode == NoisyMode::interleaved ? kMaxSubsetSide : kMaxVplsPerPixel;
  if (o.noisy.count < 1 || o.noisy.count > count_max)
    throw std::invalid_argument(fmt::format("noisy input {} is outside {}", noisy_spec_name(o.noisy), kNoisySpecForms));
  if (o.rsm_resolution < 1) throw std::invalid_argument(fmt::format("rsm resolution {} is below 1", o.rsm_resolution));
  DenoiseInputs in;
  in.width = scene.camera.width;
  in.height = scene.camera.height;
  in.noisy = o.noisy;
  in.seed = o.seed;
  const std::size_t n = std::size_t(in.width) * std::size_t(in.height);

  auto t0 = Clock::now();
  fill_full_gbuffer(scene, o.progress, in.full, in.hit, in.glossy);
  in.seconds.gbuffer = seconds_since(t0);

  const VplList vpls = render_rsm_vpls(scene, o.rsm_resolution, in.seconds.rsm).vpls;
  in.vpl_count = vpls.vpls.size();

  t0 = Clock::now();
  in.noisy_diffuse.assign(n, Rgb::Zero());
  in.noisy_specular.assign(n, Rgb::Zero());
  in.noisy_image.assign(n, Rgb::Zero());
  auto store = [&](std::size_t k, const std::pair<Rgb, Rgb>& parts) {
    const ShadingPoint& p = in.full[k].point;
    in.noisy_image[k] = parts.first + parts.second;
    in.noisy_diffuse[k] = demodulate(parts.first, p.diffuse_reflectance);
    in.noisy_specular[k] = demodulate(parts.second, p.f0);
  };
  if (o.noisy.mode == NoisyMode::interleaved) {
    const int m = o.noisy.count;
    const std::vector<VplList> subsets = interleaved_vpl_subsets(vpls, m, o.seed);
    for_each_pixel(in.width, in.height, "noisy (interleaved)", o.progress, [&](std::size_t k, int i, int j) {
      if (in.full[k].valid)
        store(k, split_vpl_sum(in.full[k].point, subsets[std::size_t(j % m) * std::size_t(m) + std::size_t(i % m)]));
    });
  } else if (!vpls.vpls.empty()) {
    const VplSampler sampler(vpls.vpls);
    for_each_pixel(in.width, in.height, "noisy (random)", o.progress, [&](std::size_t k, int, int) {
      if (!in.full[k].valid) return;
      thread_local VplList drawn;
      draw_pixel_vpls(vpls, sampler, o.noisy.count, o.seed, k, drawn);
      store(k, split_vpl_sum(in.full[k].point, drawn));
    });
  }
  in.seconds.noisy = seconds_since(t0);

  fill_reference(in.full, vpls, o.reference, in.width, o.progress, in.reference, in.seconds.reference);
  return in;
}

NoisyError noisy_error(const DenoiseInputs& in) {
  NoisyError r;
  set_receiver_errors(r, in.noisy_image, in);
  return r;
}

DenoiseResult denoise_indirect(const DenoiseInputs& in, FilterWeights weights, const FilterParameters& a) {
  if (const auto error = filter_parameters_error(a)) throw std::invalid_argument(*error);
  if (const auto error = denoise_radius_error(in.noisy, a.radius)) throw std::invalid_argument(*error);
  const auto t0 = Clock::now();
  DenoiseResult r;
  r.weights = weights;
  r.radius = a.radius;
  const std::size_t n = std::size_t(in.width) * std::size_t(in.height);
  r.filtered.assign(n, Rgb::Zero());
  r.error.assign(n, Rgb::Zero());
  const int radius = a.radius;
  const auto footprint = [radius](int d) { return std::abs(d) == radius ? 0.5 : 1.0; };

  for_each_pixel(in.width, in.height, "filtering", {}, [&](std::size_t k, int i, int j) {
    const FilterSample& p = in.full[k];
    if (!p.valid) return;
    Rgb total = Rgb::Zero();
    for (const bool specular : {false, true}) {
      if (!has_part(p, specular)) continue;
      const std::vector<Rgb>& values = specular ? in.noisy_specular : in.noisy_diffuse;
      Rgb sum = Rgb::Zero();
      double weight = 0;
      for (int y = std::max(j - radius, 0); y <= std::min(j + radius, in.height - 1); ++y) {
        const double hy = footprint(y - j);
        for (int x = std::max(i - radius, 0); x <= std::min(i + radius, in.width - 1); ++x) {
          const std::size_t q = std::size_t(y) * std::size_t(in.width) + std::size_t(x);
          if (!has_part(in.full[q], specular)) continue;
          const double w = hy * footprint(x - i) * filter_range_weight(p, in.full[q], specular, weights, a);
          sum += w * values[q];
          weight += w;
        }
      }
      // weight ≥ 1: p itself is in the window with w_r(p, p) = 1.
      total += (sum / weight) * (specular ? p.point.f0 : p.point.diffuse_reflectance);
    }
    r.filtered[k] = total;
    r.error[k] = total - in.reference[k];
  });

  set_receiver_errors(r, r.filtered, in);
  r.seconds = seconds_since(t0);
  return r;
}

}  // namespace sglab::render
