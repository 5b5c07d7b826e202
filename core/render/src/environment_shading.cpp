// Shading a sphere and a plane under an environment, V = 1 (environment.hpp).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <Eigen/Geometry>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sglab/brdf.hpp"
#include "sglab/error_metrics.hpp"
#include "sglab/glossy_reference.hpp"
#include "sglab/reference.hpp"
#include "sglab/registry.hpp"
#include "sglab/render/environment.hpp"
#include "sglab/render/pipeline.hpp"
#include "simd/render_table.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::render {

EnvImage sphere_image(int res) {
  EnvImage im{res, res, {}};
  for (int j = 0; j < res; ++j)
    for (int i = 0; i < res; ++i) {
      const double y = 2 * (i + 0.5) / res - 1, z = 1 - 2 * (j + 0.5) / res;
      const double r2 = y * y + z * z;
      if (r2 >= 1) continue;
      im.points.push_back({j * res + i, Vec3(std::sqrt(1 - r2), y, z), Vec3::UnitX()});
    }
  return im;
}

EnvImage plane_image(int res_azimuth, int res_elevation) {
  EnvImage im{res_azimuth, res_elevation, {}};
  for (int j = 0; j < res_elevation; ++j)
    for (int i = 0; i < res_azimuth; ++i) {
      const double phi = 2 * M_PI * (i + 0.5) / res_azimuth;
      const double e = 0.5 * M_PI * (j + 0.5) / res_elevation;
      im.points.push_back({j * res_azimuth + i, Vec3::UnitZ(),
                           Vec3(std::cos(e) * std::cos(phi), std::cos(e) * std::sin(phi), std::sin(e))});
    }
  return im;
}

namespace {

// The tangent frame of the registry's specular quantity: n = z, o in the xz-plane (t = the
// direction of o's projection; any tangent when o ∥ n).
struct ViewFrame {
  Vec3 t, b, n;
  Vec3 local(const Vec3& w) const { return Vec3(w.dot(t), w.dot(b), w.dot(n)); }
};

ViewFrame view_frame(const EnvShadingPoint& p) {
  ViewFrame f;
  f.n = p.normal;
  Vec3 t = p.view - p.view.dot(f.n) * f.n;
  if (t.norm() < 1e-12) {
    Vec3 e2;
    detail::orthonormal_frame(f.n, t, e2);
  }
  f.t = t.normalized();
  f.b = f.n.cross(f.t);
  return f;
}

// Sub-texel quadrature nodes of the map (environment.hpp): direction, solid angle, texel index.
struct Node {
  Vec3 dir;
  double omega;
  std::size_t texel;
};

std::vector<Node> nodes(const EnvMap& map, int supersample) {
  const int s = std::max(1, supersample);
  const int W = map.width * s, H = map.height * s;
  std::vector<Node> out;
  out.reserve(std::size_t(W) * std::size_t(H));
  for (int y = 0; y < H; ++y) {
    const double om = texel_solid_angle(W, H, y);
    for (int x = 0; x < W; ++x) {
      const std::size_t texel = std::size_t(y / s) * std::size_t(map.width) + std::size_t(x / s);
      const auto& v = map.texels[texel];
      if (v[0] == 0 && v[1] == 0 && v[2] == 0) continue;
      out.push_back({texel_direction(W, H, x, y), om, texel});
    }
  }
  return out;
}

// The GGX quadrature's shading point (integrate_specular's kernels).
simd_detail::EnvReceiver env_receiver(const EnvShadingPoint& p, double roughness, double f0) {
  return {p.normal(0), p.normal(1), p.normal(2), p.view(0), p.view(1), p.view(2), p.normal.dot(p.view), roughness, f0};
}

template <class Weight>
std::vector<Rgb> integrate(const EnvMap& map, const EnvImage& image, int supersample, const Weight& weight) {
  const auto n = nodes(map, supersample);
  std::vector<Rgb> out(std::size_t(image.width) * std::size_t(image.height), Rgb::Zero());
  tbb::parallel_for(std::size_t(0), image.points.size(), [&](std::size_t k) {
    const auto& p = image.points[k];
    const ViewFrame f = view_frame(p);
    const Vec3 wo = f.local(p.view);
    double sum[3] = {0, 0, 0};
    for (const auto& node : n) {
      const double w = weight(f, wo, node.dir) * node.omega;
      if (w == 0) continue;
      const auto& v = map.texels[node.texel];
      sum[0] += w * v[0];
      sum[1] += w * v[1];
      sum[2] += w * v[2];
    }
    out[std::size_t(p.pixel)] = Rgb(sum[0], sum[1], sum[2]);
  });
  return out;
}

const Method& registry_method(const std::string& quantity, const std::string& name) {
  const Quantity* q = find_quantity(quantity);
  const Method* m = q ? q->find(name) : nullptr;
  if (!m) {
    std::string names;
    if (q)
      for (const auto& x : q->methods) names += " " + x.name;
    throw std::invalid_argument("unknown " + quantity + " method " + quote(name) + " (methods:" + names + ")");
  }
  return *m;
}

}  // namespace

std::vector<Rgb> integrate_diffuse(const EnvMap& map, const EnvImage& image, int supersample) {
  return integrate(map, image, supersample, [](const ViewFrame& f, const Vec3&, const Vec3& w) {
    const double c = w.dot(f.n);
    return c > 0 ? c / M_PI : 0.0;
  });
}

// The same quadrature as integrate() with the GGX weight (ggx_brdf_cosine, brdf.hpp, in the world
// frame), through the renderer's vectorized loop on the nodes as arrays.
std::vector<Rgb> integrate_specular(const EnvMap& map, const EnvImage& image, double roughness, double f0,
                                    int supersample) {
  const auto n = nodes(map, supersample);
  std::vector<double> arrays(6 * n.size());
  double *x = arrays.data(), *y = x + n.size(), *z = y + n.size(), *wr = z + n.size(), *wg = wr + n.size(),
         *wb = wg + n.size();
  for (std::size_t k = 0; k < n.size(); ++k) {
    const auto& v = map.texels[n[k].texel];
    x[k] = n[k].dir(0);
    y[k] = n[k].dir(1);
    z[k] = n[k].dir(2);
    wr[k] = n[k].omega * v[0];
    wg[k] = n[k].omega * v[1];
    wb[k] = n[k].omega * v[2];
  }
  const simd_detail::EnvNodes view{n.size(), x, y, z, wr, wg, wb};
  const simd_detail::RenderKernelTable& t = simd_detail::render_kernels();
  auto receiver = [&](const EnvShadingPoint& p) { return env_receiver(p, roughness, f0); };
  std::vector<Rgb> out(std::size_t(image.width) * std::size_t(image.height), Rgb::Zero());
  // Points two at a time (one pass over the nodes for both: env_specular_sum2, each value
  // env_specular_sum's), the last one of an odd count alone.
  const std::size_t m = image.points.size();
  tbb::parallel_for(std::size_t(0), (m + 1) / 2, [&](std::size_t q) {
    const std::size_t k = 2 * q;
    double s[3] = {0, 0, 0}, s2[3] = {0, 0, 0};
    const auto& p = image.points[k];
    if (k + 1 < m) {
      const auto& p2 = image.points[k + 1];
      t.env_specular_sum2(view, receiver(p), receiver(p2), s, s2);
      out[std::size_t(p2.pixel)] = Rgb(s2[0], s2[1], s2[2]);
    } else {
      t.env_specular_sum(view, receiver(p), s);
    }
    out[std::size_t(p.pixel)] = Rgb(s[0], s[1], s[2]);
  });
  return out;
}

std::vector<std::vector<Rgb>> integrate_specular(const std::vector<const EnvMap*>& maps, const EnvImage& image,
                                                 double roughness, double f0, int supersample) {
  for (const EnvMap* m : maps)
    if (m->width != maps[0]->width || m->height != maps[0]->height)
      throw std::invalid_argument("integrate_specular: maps of different sizes (" + std::to_string(maps[0]->width) +
                                  "×" + std::to_string(maps[0]->height) + ", " + std::to_string(m->width) + "×" +
                                  std::to_string(m->height) + ")");
  const simd_detail::RenderKernelTable& t = simd_detail::render_kernels();
  constexpr std::size_t P = simd_detail::kEnvPointsPerPass, K = simd_detail::kEnvMapsPerPass;
  std::vector<std::vector<Rgb>> out(maps.size());
  std::vector<char> done(maps.size(), 0);
  for (std::size_t i = 0; i < maps.size(); ++i) {
    if (done[i]) continue;
    // Map i and the later maps with its nodes (the same all-zero texels left out), K at a time.
    const auto n = nodes(*maps[i], supersample);
    std::vector<std::size_t> group{i};
    for (std::size_t j = i + 1; j < maps.size(); ++j) {
      if (done[j]) continue;
      const auto other = nodes(*maps[j], supersample);
      if (std::equal(n.begin(), n.end(), other.begin(), other.end(),
                     [](const Node& a, const Node& b) { return a.texel == b.texel; }))
        group.push_back(j);
    }
    for (std::size_t first = 0; first < group.size(); first += K) {
      const std::size_t M = std::min(K, group.size() - first);
      // x, y, z, then each map's ω·L per channel, as the one-map integrate_specular forms them
      std::vector<double> arrays((3 + 3 * M) * n.size());
      simd_detail::EnvMapsNodes view{};
      view.n = n.size();
      view.maps = M;
      view.x = arrays.data();
      view.y = view.x + n.size();
      view.z = view.y + n.size();
      for (std::size_t c = 0; c < 3 * M; ++c) view.channel[c] = arrays.data() + (3 + c) * n.size();
      for (std::size_t k = 0; k < n.size(); ++k) {
        arrays[k] = n[k].dir(0);
        arrays[n.size() + k] = n[k].dir(1);
        arrays[2 * n.size() + k] = n[k].dir(2);
        for (std::size_t m = 0; m < M; ++m) {
          const auto& v = maps[group[first + m]]->texels[n[k].texel];
          for (std::size_t c = 0; c < 3; ++c) arrays[(3 + 3 * m + c) * n.size() + k] = n[k].omega * v[c];
        }
      }
      for (std::size_t m = 0; m < M; ++m) {
        out[group[first + m]].assign(std::size_t(image.width) * std::size_t(image.height), Rgb::Zero());
        done[group[first + m]] = 1;
      }
      const std::size_t points = image.points.size();
      tbb::parallel_for(std::size_t(0), (points + P - 1) / P, [&](std::size_t q) {
        const std::size_t count = std::min(P, points - q * P);
        simd_detail::EnvReceiver r[P] = {};
        for (std::size_t k = 0; k < count; ++k) r[k] = env_receiver(image.points[q * P + k], roughness, f0);
        double s[3 * P * K] = {};
        t.env_specular_maps(view, r, count, s);
        for (std::size_t k = 0; k < count; ++k)
          for (std::size_t m = 0; m < M; ++m) {
            const double* v = s + 3 * (k * M + m);
            out[group[first + m]][std::size_t(image.points[q * P + k].pixel)] = Rgb(v[0], v[1], v[2]);
          }
      });
    }
  }
  return out;
}

namespace {
template <class PerLobe>
std::vector<Rgb> mixture_shading(const SgMixture& m, const EnvImage& image, const PerLobe& per_lobe) {
  std::vector<Rgb> out(std::size_t(image.width) * std::size_t(image.height), Rgb::Zero());
  tbb::parallel_for(std::size_t(0), image.points.size(), [&](std::size_t k) {
    const auto& p = image.points[k];
    const ViewFrame f = view_frame(p);
    Rgb sum = Rgb::Zero();
    for (const auto& l : m) {
      const double x = per_lobe(f, p, l);
      sum += x * Rgb(l.amplitude[0], l.amplitude[1], l.amplitude[2]);
    }
    out[std::size_t(p.pixel)] = sum;
  });
  return out;
}
}  // namespace

// A lobe of zero amplitude (a ladder rung that kept its predecessor's fit carries its own lobes at
// zero, fit/envmap.hpp) adds +0 to the sum: its quadrature is skipped, the sums are unchanged.
std::vector<Rgb> mixture_diffuse_reference(const SgMixture& m, const EnvImage& image) {
  SgMixture lit;
  for (const auto& l : m)
    if (l.amplitude[0] != 0 || l.amplitude[1] != 0 || l.amplitude[2] != 0) lit.push_back(l);
  return mixture_shading(lit, image, [](const ViewFrame& f, const EnvShadingPoint&, const SgLight& l) {
    return clamped_cosine_reference(l.sharpness, std::clamp(l.axis.dot(f.n), -1.0, 1.0)) / M_PI;
  });
}

namespace {
// A registry method over every (point, lobe) pair, through its batch evaluator in blocks of
// points: `row` writes one pair's arguments (arity of them); the values are scaled and summed per
// point in lobe order, as mixture_shading does.
template <class Row>
std::vector<Rgb> mixture_method_shading(const SgMixture& m, const EnvImage& image, const Method& md, std::size_t arity,
                                        double scale, const Row& row) {
  std::vector<Rgb> out(std::size_t(image.width) * std::size_t(image.height), Rgb::Zero());
  const std::size_t lobes = m.size();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, image.points.size(), 32), [&](const auto& range) {
    std::vector<double> args(arity * lobes * range.size()), values(lobes * range.size());
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      const ViewFrame f = view_frame(image.points[k]);
      for (std::size_t j = 0; j < lobes; ++j)
        row(f, image.points[k], m[j], &args[arity * ((k - range.begin()) * lobes + j)]);
    }
    md.batch_double(args, arity, values);
    for (std::size_t k = range.begin(); k < range.end(); ++k) {
      Rgb sum = Rgb::Zero();
      for (std::size_t j = 0; j < lobes; ++j) {
        const auto& l = m[j];
        sum += values[(k - range.begin()) * lobes + j] * scale * Rgb(l.amplitude[0], l.amplitude[1], l.amplitude[2]);
      }
      out[std::size_t(image.points[k].pixel)] = sum;
    }
  });
  return out;
}
}  // namespace

std::vector<Rgb> mixture_diffuse_method(const SgMixture& m, const EnvImage& image, const std::string& method) {
  return mixture_method_shading(m, image, registry_method("clamped-cosine", method), 2, 1 / M_PI,
                                [](const ViewFrame& f, const EnvShadingPoint&, const SgLight& l, double* a) {
                                  a[0] = l.sharpness;
                                  a[1] = std::clamp(l.axis.dot(f.n), -1.0, 1.0);
                                });
}

std::vector<Rgb> mixture_specular_method(const SgMixture& m, const EnvImage& image, const std::string& method,
                                         double roughness, double f0) {
  return mixture_method_shading(
      m, image, registry_method("specular", method), 6, 1.0,
      [roughness, f0](const ViewFrame& f, const EnvShadingPoint& p, const SgLight& l, double* a) {
        const Vec3 xi = f.local(l.axis);
        a[0] = roughness;
        a[1] = l.sharpness;
        a[2] = std::clamp(xi(2), -1.0, 1.0);
        a[3] = std::clamp(p.view.dot(f.n), 0.0, 1.0);
        a[4] = std::atan2(xi(1), xi(0));
        a[5] = f0;
      });
}

ShadingError shading_error(const std::vector<Rgb>& value, const std::vector<Rgb>& reference, const EnvImage& image) {
  std::vector<char> mask(value.size(), 0);
  for (const auto& p : image.points) mask[std::size_t(p.pixel)] = 1;
  const ImageError e = image_error(value, reference, mask);
  metrics::BrightnessWeighted b;  // a pixel's channels summed first
  for (std::size_t k = 0; k < value.size(); ++k)
    if (mask[k]) b.add_terms((value[k] - reference[k]).abs().sum(), reference[k].abs().sum());
  return {e.relative_l2, e.smape, b.value()};
}

}  // namespace sglab::render
