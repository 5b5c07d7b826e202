// Environment maps: EXR input/output and the generated environments (environment.hpp).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <type_traits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "sglab/render/environment.hpp"
#include "sglab/render/exr.hpp"
#include "sglab/text_limits.hpp"

namespace sglab::render {

EnvMap load_environment(const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) throw EnvironmentError("environment " + quote(path) + ": no such file");
  // A FIFO would block the reader forever, a device never end: only a regular file is read.
  if (!std::filesystem::is_regular_file(status))
    throw EnvironmentError("environment " + quote(path) + " is not a regular file");
  ExrImage image;
  try {
    image = read_exr(path);
  } catch (const std::exception& e) {
    throw EnvironmentError("environment " + quote(path) + " is not a readable EXR (" + e.what() + ")");
  }
  // Plain R, G, B, or the first layer (in channel-name order) that has all three.
  std::string prefix;
  bool found = image.channels.count("R") && image.channels.count("G") && image.channels.count("B");
  if (!found) {
    for (const auto& [name, plane] : image.channels) {
      if (name.size() < 2 || name.substr(name.size() - 2) != ".R") continue;
      const std::string p = name.substr(0, name.size() - 1);
      if (image.channels.count(p + "G") && image.channels.count(p + "B")) {
        prefix = p;
        found = true;
        break;
      }
    }
  }
  if (!found) {
    std::string names;
    for (const auto& [name, plane] : image.channels) names += (names.empty() ? "" : ", ") + name;
    throw EnvironmentError("environment " + quote(path) +
                           " has no RGB channels (channels: " + (names.empty() ? "none" : clip_text(names, 300)) + ")");
  }
  if (image.width != 2 * image.height)
    throw EnvironmentError(
        fmt::format("environment {} is {}×{}: an equirectangular map must be 2:1 (width = 2 × height)", quote(path),
                    image.width, image.height));
  EnvMap map{image.width, image.height,
             std::vector<std::array<float, 3>>(std::size_t(image.width) * std::size_t(image.height))};
  for (int c = 0; c < 3; ++c) {
    const auto& plane = image.channels.at(prefix + "RGB"[c]);
    for (std::size_t k = 0; k < plane.size(); ++k) {
      const float x = plane[k];
      if (!std::isfinite(x) || x < 0)
        throw EnvironmentError(
            fmt::format("environment {}: texel (x {}, y {}) channel {} is {} (texels must be finite and ≥ 0)",
                        quote(path), k % std::size_t(image.width), k / std::size_t(image.width), prefix + "RGB"[c], x));
      map.texels[k][std::size_t(c)] = x;
    }
  }
  return map;
}

std::string encode_environment(const EnvMap& map, const std::vector<std::pair<std::string, std::string>>& attributes) {
  ImageLayer layer{"", std::vector<Rgb>(map.size())};
  for (std::size_t k = 0; k < map.size(); ++k)
    layer.pixels[k] = Rgb(map.texels[k][0], map.texels[k][1], map.texels[k][2]);
  return encode_exr(map.width, map.height, {layer}, attributes);
}

namespace {

void check_size(int width, int height) {
  if (width < 2 || height < 1 || width != 2 * height || double(width) * height > 1 << 26)
    throw EnvironmentError(fmt::format("environment size {}×{}: must be 2:1 and at most 2^26 texels", width, height));
}

// Coordinate (texel units) of sub-sample `sub` of texel `texel` at s × s samples per texel.
double sample_coordinate(int texel, int sub, int s) { return texel + (sub + 0.5) / s; }

// Rows [v0, v1) of `map` (already sized): each texel the average of f over supersample²
// sub-texel centres. The directions are envmap_direction's, with its sines and cosines taken once
// per sample column (φ) and sample row (θ): the same expressions, so the same values. f is called
// as f(w) or, when it takes one, f(w, j) with j = v·s + sy the global sample row (for a factor of
// a generated environment that depends on θ alone). Rows in parallel; each texel's sum in the
// same order as one loop, so the result does not depend on the threads.
template <class F>
void rasterize_rows(EnvMap& map, int supersample, int v0, int v1, const F& f) {
  const int width = map.width, height = map.height, s = std::max(1, supersample);
  std::vector<double> cos_phi(std::size_t(width) * std::size_t(s)), sin_phi(cos_phi.size());
  for (int u = 0; u < width; ++u)
    for (int sx = 0; sx < s; ++sx) {
      const double phi = 2 * M_PI * sample_coordinate(u, sx, s) / double(width) - M_PI;
      cos_phi[std::size_t(u * s + sx)] = std::cos(phi);
      sin_phi[std::size_t(u * s + sx)] = std::sin(phi);
    }
  tbb::parallel_for(tbb::blocked_range<int>(v0, v1), [&](const tbb::blocked_range<int>& rows) {
    std::vector<double> sin_theta(static_cast<std::size_t>(s)), cos_theta(static_cast<std::size_t>(s));
    for (int v = rows.begin(); v < rows.end(); ++v) {
      for (int sy = 0; sy < s; ++sy) {
        const double theta = M_PI * sample_coordinate(v, sy, s) / double(height);
        sin_theta[std::size_t(sy)] = std::sin(theta);
        cos_theta[std::size_t(sy)] = std::cos(theta);
      }
      for (int u = 0; u < width; ++u) {
        std::array<double, 3> sum{0, 0, 0};
        for (int sy = 0; sy < s; ++sy)
          for (int sx = 0; sx < s; ++sx) {
            const std::size_t k = std::size_t(u * s + sx);
            const double st = sin_theta[std::size_t(sy)];
            const Vec3 w(st * cos_phi[k], st * sin_phi[k], cos_theta[std::size_t(sy)]);
            std::array<double, 3> x;
            if constexpr (std::is_invocable_v<const F&, const Vec3&, int>) x = f(w, v * s + sy);
            else x = f(w);
            for (int c = 0; c < 3; ++c) sum[std::size_t(c)] += x[std::size_t(c)];
          }
        auto& t = map.texels[std::size_t(v) * std::size_t(width) + std::size_t(u)];
        for (int c = 0; c < 3; ++c) t[std::size_t(c)] = float(sum[std::size_t(c)] / (s * s));
      }
    }
  });
}

// rasterize_rows over the whole map.
template <class F>
EnvMap rasterize(int width, int height, int supersample, const F& f) {
  EnvMap map{width, height, std::vector<std::array<float, 3>>(std::size_t(width) * std::size_t(height))};
  rasterize_rows(map, supersample, 0, height, f);
  return map;
}

Vec3 direction_from_angles(double elevation_deg, double azimuth_deg) {
  const double e = elevation_deg * M_PI / 180, a = azimuth_deg * M_PI / 180;
  return Vec3(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
}

// xyY → linear sRGB: X = xY/y, Z = (1 − x − y)Y/y, then the IEC 61966-2-1 XYZ → sRGB (D65) matrix.
std::array<double, 3> xyY_to_linear_srgb(double x, double y, double Y) {
  const double X = x * Y / y, Z = (1 - x - y) * Y / y;
  return {std::max(0.0, 3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z),
          std::max(0.0, -0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z),
          std::max(0.0, 0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z)};
}

}  // namespace

EnvMap make_sky(const SkyOptions& o) {
  check_size(o.width, o.height);
  if (!(o.turbidity >= 2 && o.turbidity <= 10))
    throw EnvironmentError(fmt::format("--turbidity {} outside Preetham's [2, 10]", o.turbidity));
  if (!(o.sun_elevation_deg >= 0 && o.sun_elevation_deg <= 90))
    throw EnvironmentError(fmt::format("--sun-elevation {} outside [0, 90] degrees", o.sun_elevation_deg));
  if (!(o.sun_size_deg > 0 && o.sun_size_deg <= 45))
    throw EnvironmentError(fmt::format("--sun-size {} outside (0, 45] degrees", o.sun_size_deg));
  if (!(o.sun_luminance >= 0 && o.sun_luminance <= kMaxSunLuminance))
    throw EnvironmentError(fmt::format("--sun-luminance {} outside [0, {:g}]", o.sun_luminance, kMaxSunLuminance));
  if (!std::isfinite(o.sun_azimuth_deg))
    throw EnvironmentError(fmt::format("--sun-azimuth {} is not finite", o.sun_azimuth_deg));
  if (!(o.ground_albedo >= 0 && o.ground_albedo <= 1)) throw EnvironmentError("--ground-albedo must be in [0, 1]");
  const double T = o.turbidity;
  // Preetham et al. 1999, Appendix A.2: Perez coefficients (A..E) for Y, x, y.
  const double coef[3][5] = {
      {0.1787 * T - 1.4630, -0.3554 * T + 0.4275, -0.0227 * T + 5.3251, 0.1206 * T - 2.5771, -0.0670 * T + 0.3703},
      {-0.0193 * T - 0.2592, -0.0665 * T + 0.0008, -0.0004 * T + 0.2125, -0.0641 * T - 0.8989, -0.0033 * T + 0.0452},
      {-0.0167 * T - 0.2608, -0.0950 * T + 0.0092, -0.0079 * T + 0.2102, -0.0441 * T - 1.6537, -0.0109 * T + 0.0529}};
  const double ts = M_PI / 2 - o.sun_elevation_deg * M_PI / 180;  // θ_s
  const double chi = (4.0 / 9.0 - T / 120.0) * (M_PI - 2 * ts);
  const double Yz = (4.0453 * T - 4.9710) * std::tan(chi) - 0.2155 * T + 2.4192;
  const double t2 = T * T, s1 = ts, s2 = ts * ts, s3 = s2 * ts;
  const double xz = t2 * (0.00166 * s3 - 0.00375 * s2 + 0.00209 * s1) +
                    T * (-0.02903 * s3 + 0.06377 * s2 - 0.03202 * s1 + 0.00394) +
                    (0.11693 * s3 - 0.21196 * s2 + 0.06052 * s1 + 0.25886);
  const double yz = t2 * (0.00275 * s3 - 0.00610 * s2 + 0.00317 * s1) +
                    T * (-0.04214 * s3 + 0.08970 * s2 - 0.04153 * s1 + 0.00516) +
                    (0.15346 * s3 - 0.26756 * s2 + 0.06670 * s1 + 0.26688);
  const double zenith[3] = {Yz, xz, yz};
  // Perez's F(θ, γ) = (1 + A e^{B/cos θ})(1 + C e^{Dγ} + E cos²γ): the θ factor and the γ factor.
  auto perez_theta = [](const double* k, double cos_theta) {
    return 1 + k[0] * std::exp(k[1] / std::max(cos_theta, 1e-3));
  };
  auto perez_gamma = [](const double* k, double gamma, double cos_gamma) {
    return 1 + k[2] * std::exp(k[3] * gamma) + k[4] * cos_gamma * cos_gamma;
  };
  // F(zenith): the normalisation of every sample, computed once.
  std::array<double, 3> at_zenith{};
  for (std::size_t c = 0; c < 3; ++c) at_zenith[c] = perez_theta(coef[c], 1.0) * perez_gamma(coef[c], ts, std::cos(ts));
  // The θ factor per sample row j = v·s + sy (θ alone: once per row, not per sample).
  const int s = std::max(1, o.supersample);
  std::vector<std::array<double, 3>> theta_factor(std::size_t(o.height) * std::size_t(s));
  for (int v = 0; v < o.height; ++v)
    for (int sy = 0; sy < s; ++sy) {
      const double cos_theta = std::cos(M_PI * sample_coordinate(v, sy, s) / double(o.height));
      for (std::size_t c = 0; c < 3; ++c) theta_factor[std::size_t(v * s + sy)][c] = perez_theta(coef[c], cos_theta);
    }
  const Vec3 sun = direction_from_angles(o.sun_elevation_deg, o.sun_azimuth_deg);
  const double cos_sun_radius = std::cos(0.5 * o.sun_size_deg * M_PI / 180);
  const std::array<double, 3> sun_rgb{o.sun_luminance * Yz, o.sun_luminance * Yz, o.sun_luminance * Yz};
  auto sky = [&](const Vec3& w, int j) -> std::array<double, 3> {
    const double d = w.dot(sun);
    if (d >= cos_sun_radius) return sun_rgb;
    const double gamma = std::acos(std::clamp(d, -1.0, 1.0)), cos_gamma = std::cos(gamma);
    double v[3];
    for (std::size_t c = 0; c < 3; ++c)
      v[c] = zenith[c] * (theta_factor[std::size_t(j)][c] * perez_gamma(coef[c], gamma, cos_gamma)) / at_zenith[c];
    return xyY_to_linear_srgb(v[1], v[2], std::max(0.0, v[0]));
  };
  // Ground: E/π·albedo with E the horizontal irradiance of the sky and the sun (texel quadrature
  // of a first pass at the map's resolution, the ground black).
  EnvMap map = rasterize(o.width, o.height, o.supersample, [&](const Vec3& w, int j) -> std::array<double, 3> {
    if (w(2) <= 0) return {0, 0, 0};
    return sky(w, j);
  });
  std::array<double, 3> E{0, 0, 0};
  for (int v = 0; v < o.height; ++v) {
    const double om = texel_solid_angle(o.width, o.height, v);
    for (int u = 0; u < o.width; ++u) {
      const double c = texel_direction(o.width, o.height, u, v)(2);
      if (c <= 0) continue;
      for (int k = 0; k < 3; ++k) E[std::size_t(k)] += map.at(u, v)[std::size_t(k)] * om * c;
    }
  }
  // The rows whose every sample is above the horizon are the first pass's texels already; the
  // rest are rasterized again with the ground in place.
  int first_ground = 0;
  while (first_ground < o.height && std::cos(M_PI * sample_coordinate(first_ground, s - 1, s) / double(o.height)) > 0)
    ++first_ground;
  rasterize_rows(map, o.supersample, first_ground, o.height, [&](const Vec3& w, int j) -> std::array<double, 3> {
    if (w(2) > 0) return sky(w, j);
    return {o.ground_albedo * E[0] / M_PI, o.ground_albedo * E[1] / M_PI, o.ground_albedo * E[2] / M_PI};
  });
  return map;
}

EnvMap make_studio(const StudioOptions& o) {
  check_size(o.width, o.height);
  struct Rect {
    Vec3 c, e1, e2;
    double hw, hh;
    std::array<double, 3> radiance;
  };
  std::vector<Rect> rects;
  for (const auto& l : o.lights) {
    if (!(l.width_deg > 0 && l.width_deg < 180 && l.height_deg > 0 && l.height_deg < 180))
      throw EnvironmentError("studio light sizes must be in (0, 180) degrees");
    Rect r;
    r.c = direction_from_angles(l.elevation_deg, l.azimuth_deg);
    // e1 horizontal (towards increasing azimuth), e2 completes the frame (towards the zenith).
    r.e1 = Vec3::UnitZ().cross(r.c);
    if (r.e1.norm() < 1e-9) r.e1 = Vec3::UnitY();
    r.e1.normalize();
    r.e2 = r.c.cross(r.e1);
    r.hw = std::tan(0.5 * l.width_deg * M_PI / 180);
    r.hh = std::tan(0.5 * l.height_deg * M_PI / 180);
    r.radiance = l.radiance;
    rects.push_back(r);
  }
  return rasterize(o.width, o.height, o.supersample, [&](const Vec3& w) -> std::array<double, 3> {
    std::array<double, 3> out = o.background;
    for (const auto& r : rects) {
      const double d = w.dot(r.c);
      if (d <= 0) continue;
      // The ray hits the plane at distance 1 along r.c at (w·e1, w·e2)/d.
      if (std::abs(w.dot(r.e1) / d) <= r.hw && std::abs(w.dot(r.e2) / d) <= r.hh) out = r.radiance;
    }
    return out;
  });
}

EnvMap make_overcast(const OvercastOptions& o) {
  check_size(o.width, o.height);
  if (!(o.zenith >= 0) || !std::isfinite(o.zenith))
    throw EnvironmentError("overcast zenith radiance must be finite and ≥ 0");
  if (!(o.ground_albedo >= 0 && o.ground_albedo <= 1)) throw EnvironmentError("--ground-albedo must be in [0, 1]");
  // E = ∫_0^{π/2} L_z (1 + 2 cos θ)/3 cos θ sin θ dθ · 2π = 2π L_z (1/2 + 2/3)/3 = (7/9) π L_z.
  const double ground = o.ground_albedo * 7.0 / 9.0 * o.zenith;
  return rasterize(o.width, o.height, o.supersample, [&](const Vec3& w) -> std::array<double, 3> {
    const double v = w(2) > 0 ? o.zenith * (1 + 2 * w(2)) / 3 : ground;
    return {v, v, v};
  });
}

EnvMap make_indoor(const IndoorOptions& o) {
  check_size(o.width, o.height);
  // A room 6 m × 5 m × 3 m (x, y, z), the viewer at its centre 1.2 m above the floor.
  const double hx = 3.0, hy = 2.5, ceiling = 1.8, floor = -1.2;
  // Face radiances (linear RGB): painted walls, a white ceiling, a wooden floor.
  const std::array<double, 3> wall{0.09, 0.08, 0.07}, ceiling_rgb{0.12, 0.12, 0.12}, floor_rgb{0.06, 0.04, 0.025};
  // Emitters as axis-aligned rectangles on a face: [a0, a1] × [b0, b1] in the face's two free
  // coordinates (x, y on the ceiling; y, z on the x = +hx wall).
  struct Panel {
    double a0, a1, b0, b1;
    std::array<double, 3> radiance;
  };
  const Panel ceiling_panels[] = {{-1.8, -0.6, -0.3, 0.3, {9.0, 8.6, 8.0}}, {0.6, 1.8, -0.3, 0.3, {9.0, 8.6, 8.0}}};
  const Panel window{-1.0, 1.0, -0.2, 1.2, {2.2, 2.5, 3.0}};  // on the x = +hx wall: y ∈ [a0, a1], z ∈ [b0, b1]
  auto inside = [](const Panel& p, double a, double b) { return a >= p.a0 && a <= p.a1 && b >= p.b0 && b <= p.b1; };
  return rasterize(o.width, o.height, o.supersample, [&](const Vec3& w) -> std::array<double, 3> {
    // Distance to each slab's exit plane; the nearest one is the face hit.
    const double tx = std::abs(w(0)) > 0 ? hx / std::abs(w(0)) : INFINITY;
    const double ty = std::abs(w(1)) > 0 ? hy / std::abs(w(1)) : INFINITY;
    const double tz = w(2) > 0 ? ceiling / w(2) : (w(2) < 0 ? floor / w(2) : INFINITY);
    const double t = std::min({tx, ty, tz});
    const Vec3 p = t * w;
    if (t == tz) {
      if (w(2) < 0) return floor_rgb;
      for (const auto& c : ceiling_panels)
        if (inside(c, p(0), p(1))) return c.radiance;
      return ceiling_rgb;
    }
    if (t == tx && w(0) > 0 && inside(window, p(1), p(2))) return window.radiance;
    return wall;
  });
}

SgMixture synthetic_mixture() {
  auto lobe = [](double elevation, double azimuth, double sharpness, std::array<double, 3> amplitude) {
    SgLight l;
    l.axis = direction_from_angles(elevation, azimuth);
    l.sharpness = sharpness;
    l.amplitude = amplitude;
    return l;
  };
  return {lobe(60, 20, 2, {0.6, 0.7, 0.9}),     // broad sky-like lobe
          lobe(20, -100, 12, {1.5, 1.2, 0.8}),  // medium
          lobe(35, 130, 60, {4.0, 4.0, 3.5}),   // narrow
          lobe(-40, 60, 6, {0.3, 0.25, 0.2})};  // below the horizon
}

}  // namespace sglab::render
