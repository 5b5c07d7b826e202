// VSGL generation: two / two-shared / fis / kmeans (see vsgl_generation.hpp for the method and its choices).
#include "sglab/render/vsgl_generation.hpp"

#include "sglab/enum_names.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <map>
#include <random>
#include <tuple>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace sglab::render {

namespace {
constexpr EnumName<VsglMode> kVsglModeNames[] = {
    {VsglMode::two, "two"}, {VsglMode::two_shared, "two-shared"}, {VsglMode::fis, "fis"}, {VsglMode::kmeans, "kmeans"}};
}  // namespace

std::string_view vsgl_mode_name(VsglMode m) { return enum_name(kVsglModeNames, m); }

std::optional<VsglMode> parse_vsgl_mode(std::string_view name) { return parse_enum(kVsglModeNames, name); }

std::vector<std::string> vsgl_mode_names() { return enum_names(kVsglModeNames); }

std::optional<std::string> vsgl_options_error(const VsglOptions& o) {
  auto bad = [](const char* field, double value, const char* why) {
    return std::string("VSGL option ") + field + " = " + std::to_string(value) + ": " + why;
  };
  if (!vsgl_mode_is_whole_rsm(o.mode) && o.count < 1) return bad("count", o.count, "must be at least 1");
  if (!(std::isfinite(o.lambda_d) && o.lambda_d > 0))
    return bad("lambda_d", o.lambda_d, "must be a finite positive sharpness");
  if (!(std::isfinite(o.fis_k) && o.fis_k > 0)) return bad("fis_k", o.fis_k, "must be finite and positive");
  if (o.fis_bisection_iterations < 0 || o.fis_bisection_iterations > 60)
    return bad("fis_bisection_iterations", o.fis_bisection_iterations, "must be in [0, 60]");
  if (o.kmeans_iterations < 0) return bad("kmeans_iterations", o.kmeans_iterations, "must be non-negative");
  if (!(std::isfinite(o.kmeans_normal_weight) && o.kmeans_normal_weight >= 0))
    return bad("kmeans_normal_weight", o.kmeans_normal_weight, "must be finite and non-negative");
  return std::nullopt;
}

VsglSums<double> vpl_sums(const Vpl& vpl, const Vec3& origin, double diffuse_mean_length, SharpnessEstimator estimator,
                          PositionWeight position) {
  VsglSums<double> s;
  if (!vpl.valid) return s;
  const Rgb pd = position == PositionWeight::specular ? Rgb(Rgb::Zero()) : Rgb(vpl.flux * vpl.diffuse_reflectance);
  const Rgb ps = vpl.glossy() && position != PositionWeight::diffuse ? Rgb(vpl.flux * vpl.specular_reflectance)
                                                                     : Rgb(Rgb::Zero());
  // Position weight u_i = Y(Φ_i(R_d + R_s)) (Tokuyoshi 2016 §3.2), also the importance; with
  // one component only, Y(Φ_i R_d) or Y(Φ_i R_s) (Tokuyoshi 2015 (two-VSGL poster) §2.2).
  const double u = luminance<double>(Rgb(pd + ps));
  if (!(u > 0)) return s;
  add_position(s.position, u, vpl.position, origin);
  if ((pd > 0).any()) add_lobe<double>(s.diffuse, pd, vpl.normal, diffuse_mean_length);
  if ((ps > 0).any()) {
    const SgLobe<double> lobe = vpl_specular_lobe<double>(vpl.normal, vpl.incoming, vpl.roughness);
    add_lobe<double>(s.specular, ps, lobe.axis, vsgl_mean_length(lobe.sharpness, estimator));
  }
  return s;
}

namespace {

VsglLobe make_lobe(const VsglLobeSums<double>& sums, SharpnessEstimator e) {
  const VsglIntensity<double> i = vsgl_intensity(sums, e);
  return {i.amplitude, i.axis, i.sharpness};
}

}  // namespace

VsglCluster vsgl_cluster(const VsglSums<double>& sums, const Vec3& origin, const VsglOptions& options) {
  VsglCluster c;
  const VsglPosition<double> p = vsgl_position(sums.position, origin, options.variance);
  c.mean = p.mean;
  c.variance = p.variance;
  c.position_weight = sums.position.weight;
  c.log_two_pi_variance = p.variance > 0 ? std::log(two_pi<double>() * p.variance)
                                         : -std::numeric_limits<double>::infinity();
  c.diffuse_power = sums.diffuse.power;
  c.specular_power = sums.specular.power;
  if (!sums.diffuse.empty()) {
    c.diffuse = make_lobe(sums.diffuse, options.estimator);
    c.has_diffuse = (c.diffuse.amplitude > 0).any();
  }
  if (!sums.specular.empty()) {
    c.specular = make_lobe(sums.specular, options.estimator);
    c.has_specular = (c.specular.amplitude > 0).any();
  }
  return c;
}

namespace {

using Sums = VsglSums<double>;

struct Prepared {
  std::vector<double> importance;  // u_i per texel (0: contributes nothing)
  double total = 0;                // W = Σ u_i
  Vec3 origin = Vec3::Zero();      // importance-weighted mean position
  std::size_t valid = 0, glossy = 0;
  double diffuse_mean_length = 0;
};

// Importance of every texel, the total, and the reference point. Deterministic (sequential sums;
// the per-texel work is parallel).
Prepared prepare(const ReflectiveShadowMap& rsm, const VsglOptions& o) {
  Prepared p;
  p.diffuse_mean_length = vsgl_mean_length(o.lambda_d, o.estimator);
  const std::size_t n = rsm.texels.size();
  p.importance.assign(n, 0.0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i)
      p.importance[i] = vpl_sums(rsm.texels[i], Vec3::Zero(), p.diffuse_mean_length, o.estimator).position.weight;
  });
  Vec3 weighted = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const double u = p.importance[i];
    if (!(u > 0)) continue;
    p.total += u;
    weighted += u * rsm.texels[i].position;
    ++p.valid;
    if (rsm.texels[i].glossy() && (rsm.texels[i].flux * rsm.texels[i].specular_reflectance > 0).any()) ++p.glossy;
  }
  if (p.total > 0) p.origin = weighted / p.total;
  return p;
}

// Σ of vpl_sums relative to `origin` over texels 0 … count−1, or over (*indices)[0 … count−1]:
// a deterministic parallel sum (the same bits on every run and thread count).
Sums sum_texels(const ReflectiveShadowMap& rsm, const std::vector<std::size_t>* indices, std::size_t count,
                const Vec3& origin, const Prepared& p, SharpnessEstimator e, PositionWeight w = PositionWeight::total) {
  auto texel = [&](std::size_t k) -> const Vpl& { return rsm.texels[indices ? (*indices)[k] : k]; };
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<std::size_t>(0, count, 1024), Sums{},
      [&](const tbb::blocked_range<std::size_t>& r, Sums acc) {
        for (std::size_t k = r.begin(); k != r.end(); ++k)
          acc += vpl_sums(texel(k), origin, p.diffuse_mean_length, e, w);
        return acc;
      },
      [](Sums a, const Sums& b) { return a += b; });
}

// ---- the mip pyramid of sums (fis) ------------------------------------------------------------
struct Pyramid {
  std::vector<int> size;                          // side length per level
  std::vector<std::vector<Sums>> sums;            // level → row-major blocks
  std::vector<std::vector<std::uint32_t>> count;  // contributing texels per block
  int top() const { return int(size.size()) - 1; }
  const Sums& at(int level, int x, int y) const { return sums[level][std::size_t(y) * size[level] + x]; }
  double weight(int level, int x, int y) const { return at(level, x, y).position.weight; }
};

Pyramid build_pyramid(const ReflectiveShadowMap& rsm, const Prepared& p, const VsglOptions& o) {
  Pyramid py;
  const int res = rsm.resolution;
  py.size.push_back(res);
  py.sums.emplace_back(std::size_t(res) * res);
  py.count.emplace_back(std::size_t(res) * res, 0u);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, py.sums[0].size()), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      py.sums[0][i] = vpl_sums(rsm.texels[i], p.origin, p.diffuse_mean_length, o.estimator);
      py.count[0][i] = p.importance[i] > 0 ? 1u : 0u;
    }
  });
  while (py.size.back() > 1) {
    const int lv = int(py.size.size()) - 1;
    const int s = py.size[lv];
    const int ns = (s + 1) / 2;
    std::vector<Sums> next(std::size_t(ns) * ns);
    std::vector<std::uint32_t> next_count(std::size_t(ns) * ns, 0u);
    tbb::parallel_for(0, ns, [&](int y) {
      for (int x = 0; x < ns; ++x) {
        Sums acc;
        std::uint32_t c = 0;
        // Children in Z order (the order the sampler descends in).
        for (int k = 0; k < 4; ++k) {
          const int cx = 2 * x + (k & 1), cy = 2 * y + (k >> 1);
          if (cx >= s || cy >= s) continue;
          acc += py.sums[lv][std::size_t(cy) * s + cx];
          c += py.count[lv][std::size_t(cy) * s + cx];
        }
        next[std::size_t(y) * ns + x] = acc;
        next_count[std::size_t(y) * ns + x] = c;
      }
    });
    py.size.push_back(ns);
    py.sums.push_back(std::move(next));
    py.count.push_back(std::move(next_count));
  }
  return py;
}

// u in [0, 1) → a texel, drawn with probability ∝ importance by descending the pyramid (children
// in Z order; the same additions as the pyramid's, so the node weight is the children's sum to
// the last bit). Requires a positive total.
std::pair<int, int> sample_texel(const Pyramid& py, double u) {
  int x = 0, y = 0;
  for (int lv = py.top(); lv > 0; --lv) {
    const int cs = py.size[lv - 1];
    const double target = u * py.weight(lv, x, y);
    double acc = 0;
    int chosen = -1, last_positive = -1;
    double chosen_lo = 0, chosen_w = 0, last_lo = 0;
    for (int k = 0; k < 4; ++k) {
      const int cx = 2 * x + (k & 1), cy = 2 * y + (k >> 1);
      if (cx >= cs || cy >= cs) continue;
      const double w = py.weight(lv - 1, cx, cy);
      if (!(w > 0)) continue;
      const double lo = acc;
      acc += w;
      last_positive = k;
      last_lo = lo;
      if (target < acc) {
        chosen = k;
        chosen_lo = lo;
        chosen_w = w;
        break;
      }
    }
    if (chosen < 0) {  // u·w rounded up to w: the last child with weight
      chosen = last_positive;
      chosen_lo = last_lo;
      chosen_w = py.weight(lv - 1, 2 * x + (chosen & 1), 2 * y + (chosen >> 1));
    }
    u = std::clamp((target - chosen_lo) / chosen_w, 0.0, std::nextafter(1.0, 0.0));
    x = 2 * x + (chosen & 1);
    y = 2 * y + (chosen >> 1);
  }
  return {x, y};
}

// Stratified u_i = (i + ξ_i)/N, ξ_i uniform in [0, 1) from the seeded generator (53 random bits,
// so the stream is the same on every platform, unlike std::uniform_real_distribution).
std::vector<std::pair<int, int>> sample_texels(const Pyramid& py, int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<std::pair<int, int>> out;
  out.reserve(std::size_t(n));
  for (int i = 0; i < n; ++i) {
    const double xi = double(rng() >> 11) * 0x1.0p-53;
    out.push_back(sample_texel(py, std::min((i + xi) / n, std::nextafter(1.0, 0.0))));
  }
  return out;
}

// 4^l/M p̄(x, l): the probability mass of the mip texel around (x, y) at (fractional) level l,
// trilinear between levels as the GPU filters (see the header).
double fis_mass(const Pyramid& py, double total, int x, int y, double l) {
  const int top = py.top();
  if (l >= top) return py.weight(top, 0, 0) / total;
  const int l0 = int(std::floor(l));
  const double t = l - l0;
  const double p0 = py.weight(l0, x >> l0, y >> l0) / total;
  if (t == 0) return p0;
  const double p1 = py.weight(l0 + 1, x >> (l0 + 1), y >> (l0 + 1)) / total;
  return std::pow(4.0, t) * ((1 - t) * p0 + t * p1 / 4);
}

// Algorithm 1 of Tokuyoshi 2016 §5.
double fis_level(const Pyramid& py, double total, int x, int y, double target, int iterations) {
  double lmin = 0, lmax = py.top();
  for (int k = 0; k < iterations; ++k) {
    const double l = (lmin + lmax) / 2;
    if (fis_mass(py, total, x, y, l) < target) lmin = l;
    else lmax = l;
  }
  return (lmin + lmax) / 2;
}

std::vector<VsglCluster> build_fis(const ReflectiveShadowMap& rsm, const Prepared& p, const VsglOptions& o,
                                   std::size_t& merged) {
  const Pyramid py = build_pyramid(rsm, p, o);
  const int n = o.count;
  const double target = o.fis_k / n;
  const auto texels = sample_texels(py, n, o.seed);
  // Identical clusters (same level-⌊l⌋ block, same l) are merged: key → index.
  struct Sample {
    int x, y;
    double level;
    int copies;
  };
  std::vector<Sample> samples;
  std::map<std::tuple<int, int, double>, std::size_t> index;  // (block x, block y, l) → sample
  for (const auto& [x, y] : texels) {
    const double l = fis_level(py, p.total, x, y, target, o.fis_bisection_iterations);
    const int l0 = std::min(int(std::floor(l)), py.top());
    const auto [it, inserted] = index.emplace(std::make_tuple(x >> l0, y >> l0, l), samples.size());
    if (inserted) samples.push_back({x, y, l, 1});
    else {
      ++samples[it->second].copies;
      ++merged;
    }
  }
  std::vector<VsglCluster> out(samples.size());
  tbb::parallel_for(std::size_t(0), samples.size(), [&](std::size_t i) {
    const Sample& s = samples[i];
    const int top = py.top();
    const int l0 = std::min(int(std::floor(s.level)), top);
    const double t = l0 >= top ? 0.0 : s.level - l0;
    Sums sums = py.at(l0, s.x >> l0, s.y >> l0);
    if (t > 0) sums = sums * (1 - t) + py.at(l0 + 1, s.x >> (l0 + 1), s.y >> (l0 + 1)) * (t / 4);
    // FIS weight f̄/(N p̄): the interpolated sums over N times their interpolated importance
    // fraction, i.e. × W/(N ŵ); merged copies add.
    const double weight = s.copies * p.total / (double(n) * sums.position.weight);
    sums *= weight;
    VsglCluster c = vsgl_cluster(sums, p.origin, o);
    c.weight = weight;
    c.mip_level = s.level;
    c.texel_x = s.x;
    c.texel_y = s.y;
    c.texels = py.count[l0][std::size_t(s.y >> l0) * py.size[l0] + (s.x >> l0)];
    out[i] = c;
  });
  return out;
}

// ---- k-means ------------------------------------------------------------------------------------
// Texel i's image-space coordinates (texel units; the map is row-major).
Eigen::Vector2d texel_coordinates(const ReflectiveShadowMap& rsm, std::size_t i) {
  return Eigen::Vector2d(double(i % std::size_t(rsm.resolution)), double(i / std::size_t(rsm.resolution)));
}

// The k-means centres: the texel each was seeded at, its position, normal and image-space position.
struct KmeansCentres {
  std::vector<std::pair<int, int>> texels;
  std::vector<Vec3> position, normal;
  std::vector<Eigen::Vector2d> image;  // texel coordinates
  std::size_t size() const { return texels.size(); }
};

// N texels drawn by importance (the fis sampler), duplicates dropped (counted in `merged`).
KmeansCentres kmeans_seed(const ReflectiveShadowMap& rsm, const Prepared& p, const VsglOptions& o,
                          std::size_t& merged) {
  KmeansCentres c;
  {
    const Pyramid py = build_pyramid(rsm, p, o);
    for (const auto& t : sample_texels(py, o.count, o.seed)) {
      if (std::find(c.texels.begin(), c.texels.end(), t) != c.texels.end()) {
        ++merged;
        continue;
      }
      c.texels.push_back(t);
    }
  }
  for (const auto& [x, y] : c.texels) {
    const Vpl& v = rsm.at(x, y);
    c.position.push_back(v.position);
    c.normal.push_back(v.normal);
    c.image.push_back(Eigen::Vector2d(x, y));
  }
  return c;
}

// Each VPL with importance > 0 to its nearest centre (label −1 for the others): in image space, or
// by ‖y − ȳ‖² + normal_coef·‖n − n̄‖² in world space.
void kmeans_assign(const ReflectiveShadowMap& rsm, const Prepared& p, const KmeansCentres& c, bool image,
                   double normal_coef, std::vector<int>& label) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, label.size()), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      if (!(p.importance[i] > 0)) {
        label[i] = -1;
        continue;
      }
      const Vpl& v = rsm.texels[i];
      const Eigen::Vector2d t = texel_coordinates(rsm, i);
      double best = std::numeric_limits<double>::infinity();
      int arg = 0;
      for (std::size_t j = 0; j < c.size(); ++j) {
        const double d = image ? (t - c.image[j]).squaredNorm()
                               : (v.position - c.position[j]).squaredNorm() +
                                     normal_coef * (v.normal - c.normal[j]).squaredNorm();
        if (d < best) {
          best = d;
          arg = int(j);
        }
      }
      label[i] = arg;
    }
  });
}

// Lloyd update: importance-weighted mean position (relative to the old centre), image position and
// normal of each cluster; an empty cluster keeps its centre.
void kmeans_update(const ReflectiveShadowMap& rsm, const Prepared& p, const std::vector<int>& label, KmeansCentres& c) {
  const std::size_t k = c.size();
  std::vector<double> w(k, 0.0);
  std::vector<Vec3> dy(k, Vec3::Zero()), sn(k, Vec3::Zero());
  std::vector<Eigen::Vector2d> st(k, Eigen::Vector2d::Zero());
  for (std::size_t i = 0; i < label.size(); ++i) {
    if (label[i] < 0) continue;
    const std::size_t j = std::size_t(label[i]);
    const double u = p.importance[i];
    w[j] += u;
    dy[j] += u * (rsm.texels[i].position - c.position[j]);
    sn[j] += u * rsm.texels[i].normal;
    st[j] += u * texel_coordinates(rsm, i);
  }
  for (std::size_t j = 0; j < k; ++j) {
    if (!(w[j] > 0)) continue;
    c.position[j] += dy[j] / w[j];
    c.image[j] = st[j] / w[j];
    if (sn[j].norm() > 0) c.normal[j] = sn[j].normalized();
  }
}

// One VSGL per non-empty cluster: its texels in texel order (counting sort), summed relative to the
// centre.
std::vector<VsglCluster> kmeans_clusters(const ReflectiveShadowMap& rsm, const Prepared& p, const VsglOptions& o,
                                         const KmeansCentres& c, const std::vector<int>& label) {
  const std::size_t k = c.size();
  std::vector<std::vector<std::size_t>> members(k);
  for (std::size_t i = 0; i < label.size(); ++i)
    if (label[i] >= 0) members[std::size_t(label[i])].push_back(i);
  std::vector<VsglCluster> out(k);
  std::vector<char> keep(k, 0);
  tbb::parallel_for(std::size_t(0), k, [&](std::size_t j) {
    if (members[j].empty()) return;
    const Sums s = sum_texels(rsm, &members[j], members[j].size(), c.position[j], p, o.estimator);
    out[j] = vsgl_cluster(s, c.position[j], o);
    out[j].texel_x = c.texels[j].first;
    out[j].texel_y = c.texels[j].second;
    out[j].texels = members[j].size();
    keep[j] = 1;
  });
  std::vector<VsglCluster> kept;
  for (std::size_t j = 0; j < k; ++j)
    if (keep[j]) kept.push_back(out[j]);
  return kept;
}

std::vector<VsglCluster> build_kmeans(const ReflectiveShadowMap& rsm, const Prepared& p, const VsglOptions& o,
                                      std::size_t& merged) {
  KmeansCentres centres = kmeans_seed(rsm, p, o, merged);
  // ℓ² = E‖y − ȳ‖² of all VPLs (relative to the weighted mean, so no cancellation).
  const Sums all = sum_texels(rsm, nullptr, rsm.texels.size(), p.origin, p, o.estimator);
  const double ell2 = vsgl_position(all.position, p.origin).variance;
  const double normal_coef = o.kmeans_normal_weight * o.kmeans_normal_weight * ell2 / 4;
  const bool image = o.kmeans_space == VsglOptions::KmeansSpace::image;
  std::vector<int> label(rsm.texels.size(), -1);
  kmeans_assign(rsm, p, centres, image, normal_coef, label);
  for (int it = 0; it < o.kmeans_iterations; ++it) {
    kmeans_update(rsm, p, label, centres);
    kmeans_assign(rsm, p, centres, image, normal_coef, label);
  }
  return kmeans_clusters(rsm, p, o, centres, label);
}

}  // namespace

VsglSet build_vsgls(const ReflectiveShadowMap& rsm, const VsglOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (auto e = vsgl_options_error(options)) throw std::invalid_argument(*e);
  if (rsm.resolution < 0 || rsm.texels.size() != std::size_t(rsm.resolution) * std::size_t(rsm.resolution))
    throw std::invalid_argument("reflective shadow map: resolution " + std::to_string(rsm.resolution) + " but " +
                                std::to_string(rsm.texels.size()) + " texels");
  VsglSet set;
  set.lambda_d = options.lambda_d;
  VsglStats& st = set.stats;
  st.mode = std::string(vsgl_mode_name(options.mode));
  st.requested = vsgl_mode_is_whole_rsm(options.mode) ? 1 : options.count;
  st.seed = options.seed;
  st.lambda_d = options.lambda_d;

  const Prepared p = prepare(rsm, options);
  st.valid_vpls = p.valid;
  st.glossy_vpls = p.glossy;
  if (p.total > 0) {
    switch (options.mode) {
      case VsglMode::two: {
        // One cluster per component, each with its own positional Gaussian.
        for (const PositionWeight w : {PositionWeight::diffuse, PositionWeight::specular}) {
          const Sums s = sum_texels(rsm, nullptr, rsm.texels.size(), p.origin, p, options.estimator, w);
          if (!(s.position.weight > 0)) continue;  // no diffuse (or no glossy) power at all
          VsglCluster c = vsgl_cluster(s, p.origin, options);
          c.texels = p.valid;
          set.clusters.push_back(c);
        }
        break;
      }
      case VsglMode::two_shared: {
        const Sums s = sum_texels(rsm, nullptr, rsm.texels.size(), p.origin, p, options.estimator);
        VsglCluster c = vsgl_cluster(s, p.origin, options);
        c.texels = p.valid;
        set.clusters.push_back(c);
        break;
      }
      case VsglMode::fis: set.clusters = build_fis(rsm, p, options, st.merged_duplicates); break;
      case VsglMode::kmeans: set.clusters = build_kmeans(rsm, p, options, st.merged_duplicates); break;
    }
  }
  st.clusters = set.clusters.size();
  for (const auto& c : set.clusters) {
    st.diffuse_vsgls += c.has_diffuse ? 1 : 0;
    st.specular_vsgls += c.has_specular ? 1 : 0;
  }
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return set;
}

}  // namespace sglab::render
