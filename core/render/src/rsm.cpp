// The reflective shadow map (rsm.hpp).
#include "sglab/render/rsm.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <numbers>
#include <vector>

#include <boost/math/quadrature/gauss.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sglab/brdf.hpp"

namespace sglab::render {
namespace {

// Adaptive 15-point Gauss–Kronrod on [a, b], mapped onto [−1, 1] first: Boost 1.74 reports the
// error estimate of [−1, 1] without the (b − a)/2 factor (see glossy_reference.hpp), which on a
// texel-sized interval would make it refine ~100× too far.
template <class F>
double gauss_kronrod_piece(const F& f, double a, double b, double tolerance) {
  if (!(b > a)) return 0;
  const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
  const auto g = [&](double u) { return f(mid + half * u); };
  return half * boost::math::quadrature::gauss_kronrod<double, 15>::integrate(g, -1.0, 1.0, 15, tolerance);
}

// ∫_a^b f with panel ends at the given break points (those inside (a, b)).
template <class F>
double integrate_with_breaks(const F& f, double a, double b, std::vector<double> breaks, double tolerance) {
  breaks.erase(std::remove_if(breaks.begin(), breaks.end(), [&](double t) { return !(t > a && t < b); }), breaks.end());
  std::sort(breaks.begin(), breaks.end());
  double sum = 0, lo = a;
  for (const double t : breaks) {
    sum += gauss_kronrod_piece(f, lo, t, tolerance);
    lo = t;
  }
  return sum + gauss_kronrod_piece(f, lo, b, tolerance);
}

}  // namespace

namespace {

// Ŝ(r) = ∫_{c(r)}^1 s(c') dc', c(r) = 1/√(1 + r²): the emission (per radian of azimuth, over I0)
// inside radius r of the image plane, since r dr/(1 + r²)^{3/2} = −dc. Piecewise: 1 − c inside
// the inner cone; (1 − c_i) + w(½ − t³ + t⁴/2) in the smoothstep band (t = (c − c_o)/w,
// w = c_i − c_o, from ∫_t^1 (3τ² − 2τ³) dτ); (1 − c_i) + w/2 outside the cone.
struct EmissionProfile {
  double r_inner, r_outer;     // tan θi, tan θo
  double one_minus_ci, co, w;  // 1 − cos θi, cos θo, cos θi − cos θo

  explicit EmissionProfile(const Spotlight& l)
      : r_inner(std::tan(l.cone_angle - l.falloff)),
        r_outer(std::tan(l.cone_angle)),
        one_minus_ci(2 * std::pow(std::sin(0.5 * (l.cone_angle - l.falloff)), 2)),
        co(std::cos(l.cone_angle)),
        w(2 * std::sin(l.cone_angle - 0.5 * l.falloff) * std::sin(0.5 * l.falloff)) {}

  double operator()(double r) const {
    if (r <= r_inner) {
      const double q = std::sqrt(1 + r * r);
      return r * r / (q * (1 + q));  // 1 − 1/q without cancellation
    }
    if (r >= r_outer) return one_minus_ci + 0.5 * w;
    const double t = (1 / std::sqrt(1 + r * r) - co) / w;
    return one_minus_ci + w * (0.5 - t * t * t + 0.5 * t * t * t * t);
  }
};

// ∫ Ŝ(r(φ)) dφ over the image-plane triangle (origin, a, b), signed (positive when a → b turns
// counter-clockwise about the origin). Along the edge's line, r(φ) = h/cos(φ − φ_n) (h the
// line's distance from the origin, φ_n its normal's angle); the panel ends are where r crosses
// the inner and outer radii (kinks of Ŝ for a hard edge), so every panel is smooth.
double edge_emission(const EmissionProfile& S, double ax, double ay, double bx, double by) {
  const double delta = std::atan2(ax * by - ay * bx, ax * bx + ay * by);
  if (delta == 0) return 0;
  const double dx = bx - ax, dy = by - ay, len = std::hypot(dx, dy);
  double nx = dy / len, ny = -dx / len;
  double h = ax * nx + ay * ny;
  if (h < 0) {
    nx = -nx;
    ny = -ny;
    h = -h;
  }
  if (!(h > 0)) return 0;  // the edge's line passes through the origin: a degenerate triangle
  const double sign = delta > 0 ? 1 : -1, span = std::fabs(delta);
  const double phi_a = std::atan2(ay, ax), phi_n = std::atan2(ny, nx);
  const auto f = [&](double tau) { return S(h / std::cos(phi_a + sign * tau - phi_n)); };
  std::vector<double> breaks;
  for (const double radius : {S.r_inner, S.r_outer})
    if (h < radius)
      for (const double psi : {std::acos(h / radius), -std::acos(h / radius)})
        breaks.push_back(sign * std::remainder(phi_n + psi - phi_a, 2 * std::numbers::pi));
  return sign * integrate_with_breaks(f, 0.0, span, breaks, 1e-13);
}

}  // namespace

double texel_emission_fraction(const Spotlight& light, const LightView& view, int i, int j) {
  const double s = view.texel_size();
  const double x0 = view.x_lo(i), x1 = x0 + s, y0 = view.y_lo(j), y1 = y0 + s;
  const double peak = light.peak_intensity_per_power();
  const EmissionProfile S(light);
  // Nearest point of the texel to the axis, and its farthest corner.
  const double nx = std::clamp(0.0, x0, x1), ny = std::clamp(0.0, y0, y1);
  const double fx = std::max(std::fabs(x0), std::fabs(x1)), fy = std::max(std::fabs(y0), std::fabs(y1));
  const double r_min = std::hypot(nx, ny), r_max = std::hypot(fx, fy);
  if (r_max <= S.r_inner) return peak * image_rectangle_solid_angle(x0, x1, y0, y1);
  if (r_min >= S.r_outer) return 0;
  // The texel as the signed sum of the triangles (origin, edge), counter-clockwise.
  const double sum = edge_emission(S, x0, y0, x1, y0) + edge_emission(S, x1, y0, x1, y1) +
                     edge_emission(S, x1, y1, x0, y1) + edge_emission(S, x0, y1, x0, y0);
  return peak * std::max(sum, 0.0);
}

namespace {

// Gauss–Legendre nodes and weights on [a, b] (Boost.Math's 32-point rule, both halves).
struct GaussRule {
  double nodes[32], weights[32];
  GaussRule(double a, double b) {
    using rule = boost::math::quadrature::gauss<double, 32>;
    const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
    for (std::size_t k = 0; k < 16; ++k) {
      nodes[2 * k] = mid - half * rule::abscissa()[k];
      nodes[2 * k + 1] = mid + half * rule::abscissa()[k];
      weights[2 * k] = weights[2 * k + 1] = half * rule::weights()[k];
    }
  }
};

}  // namespace

GgxAlbedo ggx_directional_albedo(double alpha, double cos_incoming) {
  const double mu = std::clamp(cos_incoming, 0.0, 1.0);
  if (!(mu > 0)) return {};
  const double sin_in = std::sqrt((1 - mu) * (1 + mu));
  const Vec3 wo(sin_in, 0, mu);
  const double a2 = alpha * alpha;
  // For the half vector h at (θh, φ): ω·n = 2(ω'·h)cos θh − μ = s cos φ sin 2θh + μ cos 2θh
  // = ρ cos(2θh − δ), δ = atan2(s cos φ, μ), s = sin θ'; so ω is above the horizon exactly for
  // θh < θ* = δ/2 + π/4 (and then ω'·h > 0 too). In v = √(1 − u): v* = α/√(α² + tan²θ*).
  const auto v_min = [&](double cos_phi) {
    const double theta_max = 0.5 * std::atan2(sin_in * cos_phi, mu) + 0.25 * std::numbers::pi;
    return alpha / std::hypot(alpha, std::tan(theta_max));
  };
  // θ*(φ) swings from ≈ π/2 to ≈ 0 across φ = π/2 within |cos φ| ≲ μ/s: at grazing incidence the
  // outer integrand has a step of width ~μ there, resolved by panels π/2 ± μ·4^k.
  std::vector<double> phi_breaks{0.0, std::numbers::pi};
  if (mu < 0.25) {
    phi_breaks.push_back(0.5 * std::numbers::pi);
    for (double d = mu; d < 0.5 * std::numbers::pi; d *= 4) {
      phi_breaks.push_back(0.5 * std::numbers::pi - d);
      phi_breaks.push_back(0.5 * std::numbers::pi + d);
    }
  }
  std::sort(phi_breaks.begin(), phi_breaks.end());
  GgxAlbedo sum;
  for (std::size_t p = 0; p + 1 < phi_breaks.size(); ++p) {
    const GaussRule outer(phi_breaks[p], phi_breaks[p + 1]);
    for (int a = 0; a < 32; ++a) {
      const double cp = std::cos(outer.nodes[a]);
      const GaussRule inner(v_min(cp), 1.0);
      for (int b = 0; b < 32; ++b) {
        // In v = √(1 − u) (u = 1 − v², du = 2v dv), which removes the (1 − u)^{−1/2} of 1/cos θh
        // near u → 1 (close to the horizon's u* for small α). tan²θh = α²u/(1 − u): with
        // d = v² + α²(1 − v²), cos θh = v/√d, sin θh = α√(1 − v²)/√d.
        const double v = inner.nodes[b];
        const double d = v * v + a2 * (1 - v * v), root = std::sqrt(d);
        const double ch = v / root, sh = alpha * std::sqrt((1 - v) * (1 + v)) / root;
        const double oh = sin_in * sh * cp + mu * ch;  // ω'·h
        const double ci = 2 * oh * ch - mu;            // (2(ω'·h)h − ω')·n
        if (!(oh > 0) || !(ci > 0)) continue;
        // V·ci·4(ω'·h)/cos θh · 2v = V·ci·8(ω'·h)√d; 1/(2π) for du dφ/(2π), ×2 for φ ∈ [π, 2π].
        const double w = outer.weights[a] * inner.weights[b] * smith_visibility_ggx(alpha, mu, ci) * ci * 8 * oh *
                         root / std::numbers::pi;
        const double m = 1 - oh, m2 = m * m;
        sum.e1 += w;
        sum.e5 += w * m2 * m2 * m;
      }
    }
  }
  return sum;
}

GgxAlbedoTable::GgxAlbedoTable(double alpha) : nodes_(kNodes + 1) {
  tbb::parallel_for(0, kNodes + 1, [&](int k) {
    const double s = double(k) / kNodes;
    nodes_[std::size_t(k)] = ggx_directional_albedo(alpha, std::max(s * s, kMinCos));
  });
}

GgxAlbedo GgxAlbedoTable::operator()(double cos_incoming) const {
  const double s = std::sqrt(std::clamp(cos_incoming, 0.0, 1.0)) * kNodes;
  const int k = std::min(int(s), kNodes - 1);
  const double f = s - k;
  const GgxAlbedo& a = nodes_[std::size_t(k)];
  const GgxAlbedo& b = nodes_[std::size_t(k) + 1];
  return {a.e1 + f * (b.e1 - a.e1), a.e5 + f * (b.e5 - a.e5)};
}

std::shared_ptr<const GgxAlbedoTable> ggx_albedo_table(double alpha) {
  static std::mutex lock;
  static std::map<double, std::shared_ptr<const GgxAlbedoTable>> tables;
  {
    const std::lock_guard guard(lock);
    if (const auto it = tables.find(alpha); it != tables.end()) return it->second;
  }
  // Built outside the lock (its parallel_for could otherwise pick up a task that waits for it);
  // two threads that both build α's table build the same values.
  auto table = std::make_shared<const GgxAlbedoTable>(alpha);
  const std::lock_guard guard(lock);
  if (tables.size() >= 64) tables.clear();  // the tables handed out stay alive with their users
  return tables.emplace(alpha, std::move(table)).first->second;
}

ReflectiveShadowMap render_rsm(const Scene& scene, int resolution) {
  ReflectiveShadowMap rsm;
  rsm.resolution = resolution;
  rsm.texels.resize(std::size_t(resolution) * std::size_t(resolution));
  const LightView view(scene.light, resolution);
  const double s = view.texel_size();
  // One albedo table per distinct roughness of a glossy material.
  std::map<double, std::shared_ptr<const GgxAlbedoTable>> albedo;
  for (const Object& o : scene.objects)
    if (o.material.glossy() && !albedo.count(o.material.roughness))
      albedo.emplace(o.material.roughness, ggx_albedo_table(o.material.roughness));
  tbb::parallel_for(tbb::blocked_range<int>(0, resolution), [&](const tbb::blocked_range<int>& rows) {
    for (int j = rows.begin(); j < rows.end(); ++j)
      for (int i = 0; i < resolution; ++i) {
        Vpl& v = rsm.texels[std::size_t(j) * std::size_t(resolution) + std::size_t(i)];
        const Ray ray = view.ray(view.x_lo(i) + 0.5 * s, view.y_lo(j) + 0.5 * s);
        const auto hit = cast_ray(scene, ray);
        if (!hit) continue;
        const double fraction = texel_emission_fraction(scene.light, view, i, j);
        if (!(fraction > 0)) continue;  // outside the cone: no light, no VPL
        const Material& m = scene.objects[std::size_t(hit->object)].material;
        v.valid = true;
        v.position = hit->position;
        v.normal = hit->normal;
        v.incoming = -ray.direction;
        v.flux = scene.light.power * fraction;
        v.diffuse_reflectance = m.albedo;
        v.f0 = m.f0;
        v.roughness = m.roughness;
        if (m.glossy()) {
          const GgxAlbedo a = (*albedo.at(m.roughness))(v.normal.dot(v.incoming));
          for (int k = 0; k < 3; ++k) v.specular_reflectance(k) = a.reflectance(m.f0(k));
        }
        const double omega = image_rectangle_solid_angle(view.x_lo(i), view.x_lo(i) + s, view.y_lo(j),
                                                         view.y_lo(j) + s);
        v.footprint_radius = std::sqrt(omega / std::numbers::pi) * hit->distance;
      }
  });
  return rsm;
}

}  // namespace sglab::render
