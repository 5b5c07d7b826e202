// Exact glossy reflection of an SG light:
//
//   L = ∫ G(ω; ξ, λ) f(ωo, ω) ⟨ω·n⟩ dω,  f = GGX·height-correlated Smith·Schlick (brdf.hpp),
//
// by deterministic adaptive 2D quadrature, and a seeded importance-sampled Monte Carlo estimator
// that checks it (tests/glossy_reference_test.cpp).
//
// Quadrature. Spherical coordinates (θ, φ) about a pole p (the light axis): the SG is then a
// function of θ alone, peaked at θ = 0 with width 1/√λ. The BRDF lobe is a second peak at its
// own (θ_f, φ_f) (mirror direction; the dominant-visible-normal reflection) of width ~α. The
// outer integral runs over φ, the inner over θ. Kinks and peaks are made panel ends:
//  • inner θ: the visible interval [θ_lo(φ), θ_hi(φ)] where ω·n > 0 (solved in closed form: the
//    horizon is where cos θ (p·n) + sin θ (e(φ)·n) = 0), split geometrically about 0 (pole width),
//    about each focus' θ_f (focus width), and about both interval ends (the horizon, where G2
//    vanishes linearly on a scale ~α(ωo·n));
//  • outer φ: split at each focus azimuth φ_f and geometrically about it at the angular width
//    w_f/sin θ_f that the focus subtends.
// Two passes: one 15-point Gauss–Kronrod rule per panel gives the scale of the integral; then
// every panel is refined adaptively (Boost.Math's 7/15 nodes) to an absolute error of 1e-6 of
// that scale. Geometric splitting (ratio 2, starting a quarter of a width from the peak) resolves
// every scale between the narrowest lobe width and π at a cost logarithmic in the sharpness, so
// α = 0.01 with λ = 1e4 costs only a few more panels than α = 1 with λ = 1.
// Accuracy: ≤ 1e-6 relative is asserted in tests (comparison with a finer rule, and with Monte
// Carlo within 4 standard errors).
//
// Double only: the reference is evaluated in double and converted for float and mp50 (an mp50
// 2D quadrature would take minutes per point; the registry says so in the method's flaws).
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <span>
#include <type_traits>
#include <unordered_map>
#include <limits>
#include <vector>

#include <boost/container_hash/hash.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "sglab/brdf.hpp"
#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"

namespace sglab {

using Vec3d = Vec3<double>;

// A direction around which the integrand has a peak of angular width `width` (radians).
struct SphereFocus {
  Vec3d dir;
  double width;
};

// Quadrature controls (defaults give ≤ 1e-6 relative; tests compare against a finer setting).
struct SphereQuadrature {
  double tolerance = 1e-6;  // outer absolute error, relative to a first coarse estimate (inner: 1e-3 of it per radian)
  int max_depth = 10;       // adaptive bisections per panel
  double ratio = 2.0;       // geometric growth of panel lengths away from a peak
  double min_width = 1e-7;  // floor on focus widths (keeps the panel count bounded)
};

namespace detail {

// An orthonormal frame (e1, e2) completing the unit vector p (Duff et al. 2017, "Building an
// Orthonormal Basis, Revisited": branchless, no normalization, exact for p = ±z).
inline void orthonormal_frame(const Vec3d& p, Vec3d& e1, Vec3d& e2) {
  const double sign = std::copysign(1.0, p(2));
  const double a = -1.0 / (sign + p(2));
  const double b = p(0) * p(1) * a;
  e1 = Vec3d(1.0 + sign * p(0) * p(0) * a, sign * b, -sign * p(0));
  e2 = Vec3d(b, sign + p(1) * p(1) * a, -p(1));
}

// Breakpoints c ± w·ratio^k (k = 0, 1, …) inside (lo, hi), plus c itself if inside.
inline void add_geometric_breaks(std::vector<double>& out, double c, double w, double lo, double hi, double ratio) {
  if (c > lo && c < hi) out.push_back(c);
  for (double d = w; d < hi - lo; d *= ratio) {
    if (c + d > lo && c + d < hi) out.push_back(c + d);
    if (c - d > lo && c - d < hi) out.push_back(c - d);
  }
}

// The θ ∈ [0, π] interval where cos θ·A + sin θ·B > 0 (the half-space ω·q > 0 seen along the
// meridian of azimuth φ, A = p·q, B = e(φ)·q). With A cos θ + B sin θ = R cos(θ − β),
// β = atan2(B, A): the set is |θ − β| < π/2 (mod 2π). Returns false if it is empty.
inline bool visible_theta_interval(double A, double B, double& lo, double& hi) {
  const double pi = boost::math::constants::pi<double>();
  if (A == 0 && B == 0) return false;
  const double beta = std::atan2(B, A);
  if (beta >= -pi / 2) {
    lo = std::max(0.0, beta - pi / 2);
    hi = std::min(pi, beta + pi / 2);
  } else {
    lo = beta + 1.5 * pi;
    hi = pi;
  }
  return hi > lo;
}

// The points of the Boost.Math Gauss–Kronrod rule of this file's quadratures (7 Gauss points
// nested in 15 Kronrod points).
inline constexpr unsigned kSphereRulePoints = 15;

// Adaptive Gauss–Kronrod (7/15 points, Boost.Math's nodes) to an ABSOLUTE error abs_tol: split
// until the Kronrod–Gauss difference of a piece is below its share of the tolerance. Absolute,
// not relative, so that pieces where the integrand is negligible (far tails, next to a horizon)
// are not refined to the last digit of their own tiny value.
// `rule(a, b, &err)` is one such rule on [a, b].
template <class Rule>
double adaptive_absolute(const Rule& rule, double a, double b, double abs_tol, int depth) {
  double err = 0;
  const double k = rule(a, b, &err);
  // Boost 1.74 reports the error of the rule on [−1, 1] before its (b − a)/2 change of variable
  // (recursive_adaptive_integrate never scales error_local): scale it here. Below 4ε|k| the
  // estimate is rounding noise (Boost floors it at 2ε|k|), and bisecting cannot reduce it.
  err *= 0.5 * (b - a);
  if (depth <= 0 || !(err > abs_tol) || err <= 4 * std::numeric_limits<double>::epsilon() * std::abs(k)) return k;
  const double m = 0.5 * (a + b);
  return adaptive_absolute(rule, a, m, 0.5 * abs_tol, depth - 1) +
         adaptive_absolute(rule, m, b, 0.5 * abs_tol, depth - 1);
}
template <class G>
double gauss_kronrod_absolute(const G& g, double a, double b, double abs_tol, int depth) {
  using boost::math::quadrature::gauss_kronrod;
  const auto rule = [&](double lo, double hi, double* err) {
    return gauss_kronrod<double, kSphereRulePoints>::integrate(g, lo, hi, 0, 0.0, err);
  };
  return adaptive_absolute(rule, a, b, abs_tol, depth);
}

// A θ node of integrate_sphere's meridians: θ, sin θ, cos θ, sin(θ/2) and the factor of the
// integrand that depends on θ alone (integrate_sphere's pole_factor; 1 without one).
struct ThetaNode {
  double theta, sin, cos, sin_half, pole_factor;
};

// The bound of ThetaNodes' store, in panels (about 640 bytes each: 10 MiB). Typical references
// keep a few thousand; one at α = 10⁻³ and grazing view, whose horizon breaks move with every
// meridian, kept 355 MB of panels that seldom recurred before the bound (docs/testing.md). Past
// it new panels are computed as before and not kept.
inline constexpr std::size_t kMaxThetaPanels = 16384;

// The θ nodes of integrate_sphere, kept across its meridians. A meridian's θ panels are the same
// numbers on most meridians (the breaks about the pole and the foci do not depend on φ; only the
// horizon's do), and so are their adaptive halves, so most panels' nodes recur: 83 % of the nodes
// of 100 random specular references (docs/testing.md, "θ nodes kept across meridians"). Each panel
// [a, b] keeps the nodes Boost's rule asked for, in its order; a node is taken from there only
// if its θ has the same bits as the one asked for (else it is computed), so every value is the
// one computed without the store, to the bit: sin, cos and the pole factor are functions of θ.
template <class PoleFactor>
class ThetaNodes {
 public:
  explicit ThetaNodes(const PoleFactor& pole_factor) : pole_factor_(pole_factor) {}

  // One rule on [a, b] of g(ThetaNode).
  template <class G>
  double rule(const G& g, double a, double b, double* err) {
    using boost::math::quadrature::gauss_kronrod;
    const Key key{std::bit_cast<std::uint64_t>(a), std::bit_cast<std::uint64_t>(b)};
    Panel unkept;  // a panel past the store's bound: its nodes are computed and not kept
    auto found = panels_.find(key);
    if (found == panels_.end() && panels_.size() < kMaxThetaPanels) found = panels_.emplace(key, Panel{}).first;
    Panel& panel = found == panels_.end() ? unkept : found->second;
    std::size_t k = 0;
    const auto at = [&](double theta) -> double {
      if (k < panel.count && std::bit_cast<std::uint64_t>(panel.nodes[k].theta) == std::bit_cast<std::uint64_t>(theta))
        return g(panel.nodes[k++]);
      const ThetaNode t = node(theta);
      if (k == panel.count && k < panel.nodes.size()) panel.nodes[panel.count++] = t;
      ++k;
      return g(t);
    };
    return gauss_kronrod<double, kSphereRulePoints>::integrate(at, a, b, 0, 0.0, err);
  }
  // The nodes computed so far (not taken from the store).
  std::size_t computed() const { return computed_; }

 private:
  ThetaNode node(double theta) {
    ++computed_;
    ThetaNode t{theta, std::sin(theta), std::cos(theta), std::sin(0.5 * theta), 1.0};
    if constexpr (!std::is_same_v<PoleFactor, std::nullptr_t>)
      t.pole_factor = pole_factor_(2 * t.sin_half * t.sin_half);
    return t;
  }
  struct Key {
    std::uint64_t a, b;
    bool operator==(const Key&) const = default;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::size_t seed = 0;
      boost::hash_combine(seed, k.a);
      boost::hash_combine(seed, k.b);
      return seed;
    }
  };
  struct Panel {
    std::array<ThetaNode, kSphereRulePoints> nodes;
    std::size_t count = 0;
  };
  PoleFactor pole_factor_;
  std::unordered_map<Key, Panel, KeyHash> panels_;
  std::size_t computed_ = 0;
};

// A focus in the polar coordinates (θ, φ) about the pole (frame e1, e2), its width floored.
struct FocusPolar {
  double theta, phi, width;
};
inline std::vector<FocusPolar> foci_polar(std::span<const SphereFocus> foci, const Vec3d& pole, const Vec3d& e1,
                                          const Vec3d& e2, double min_width) {
  std::vector<FocusPolar> polar;
  for (const auto& fc : foci) {
    const double ct = std::clamp(fc.dir.dot(pole), -1.0, 1.0);
    const double st = std::hypot(fc.dir.dot(e1), fc.dir.dot(e2));
    polar.push_back({std::atan2(st, ct), std::atan2(fc.dir.dot(e2), fc.dir.dot(e1)), std::max(fc.width, min_width)});
  }
  return polar;
}

// Σ over the panels [br_i, br_{i+1}] of `panel(a, b)`, skipping empty ones, in order.
template <class Panel>
double sum_panels(const std::vector<double>& br, const Panel& panel) {
  double sum = 0;
  for (std::size_t i = 0; i + 1 < br.size(); ++i) {
    if (!(br[i + 1] > br[i])) continue;
    sum += panel(br[i], br[i + 1]);
  }
  return sum;
}

// The sorted θ panel ends of a meridian visible on [lo, hi]: geometric about the pole (width
// w_pole) and each focus, and about both ends (horizons or the poles: G2 vanishes there on the
// scale of the narrowest lobe).
inline std::vector<double> theta_breaks(double lo, double hi, double w_pole, const std::vector<FocusPolar>& polar,
                                        double ratio, double min_width) {
  const double pi = boost::math::constants::pi<double>();
  std::vector<double> br{lo, hi};
  add_geometric_breaks(br, 0.0, 0.25 * w_pole, lo, hi, ratio);
  for (const auto& fp : polar) add_geometric_breaks(br, fp.theta, 0.25 * fp.width, lo, hi, ratio);
  // The ends are split at the narrowest width but not below min_width (a pole narrower than that,
  // possible for a SpherePoint integrand, has its own breaks about θ = 0 above).
  double w_min = std::max(w_pole, min_width);
  for (const auto& fp : polar) w_min = std::min(w_min, fp.width);
  if (lo > 0) add_geometric_breaks(br, lo, 0.25 * w_min, lo, hi, ratio);
  if (hi < pi) add_geometric_breaks(br, hi, 0.25 * w_min, lo, hi, ratio);
  std::sort(br.begin(), br.end());
  return br;
}

// The sorted φ panel ends on [−π, π]: each focus azimuth (off the pole axis) and its geometric
// neighbours at the angular width w_f/sin θ_f it subtends, wrapped into [−π, π].
inline std::vector<double> azimuth_breaks(const std::vector<FocusPolar>& polar, double ratio) {
  const double pi = boost::math::constants::pi<double>();
  std::vector<double> br{-pi, pi};
  for (const auto& fp : polar) {
    if (fp.theta <= 0 || fp.theta >= pi) continue;  // on the pole axis: no azimuthal structure
    const double w = 0.25 * fp.width / std::sin(fp.theta);
    std::vector<double> local;
    add_geometric_breaks(local, 0.0, w, -pi, pi, ratio);
    for (double d : local) {
      double x = fp.phi + d;
      x = std::remainder(x, 2 * pi);
      if (x > -pi && x < pi) br.push_back(x);
    }
  }
  std::sort(br.begin(), br.end());
  return br;
}
}  // namespace detail

// A node of the polar grid about the pole, for an integrand that needs more than ω: θ and
// 1 − cos θ = 2 sin²(θ/2) exactly (ω·pole − 1 has lost every digit once θ < 1e-8, so an SG about
// the pole evaluated from ω is wrong past λ ≈ 1e14), and the azimuth's cosine and sine in the frame
// detail::orthonormal_frame(pole) (e1 = x, e2 = y for the pole z).
struct SpherePoint {
  Vec3d w;
  double theta, one_minus_cos, cos_phi, sin_phi;
  double sin_theta;    // std::sin(theta)
  double pole_factor;  // integrate_sphere's pole_factor at 1 − cos θ (1 without one)
};

// The polar angle past which an SG of sharpness λ about the pole is exactly 0 in double:
// λ(1 − cos θ) > 746 makes e^{−λ(1 − cos θ)} underflow (e^{−745.13} is the smallest subnormal),
// so nothing past it is lost by not integrating there. π when λ ≤ 373.
inline double sg_support_angle(double lambda) {
  const double pi = boost::math::constants::pi<double>();
  if (!(lambda > 373)) return pi;
  return 2 * std::asin(std::sqrt(373 / lambda));
}

// ∫_{S²} f(ω) dω for an f that is zero outside ∩_k {ω·clip_k > 0} and peaked at `pole` (width
// pole_width) and at the foci. See the file comment for the panel placement. f is called with ω,
// or with a SpherePoint if it takes one; only then is a pole width below q.min_width kept (an f of
// ω alone cannot resolve a narrower pole). f is taken to be 0 past θ = pole_support about the pole.
// pole_factor (optional): a factor of f that depends on θ alone, as a function of 1 − cos θ; it
// is evaluated once per θ node (detail::ThetaNodes) and handed to f in SpherePoint::pole_factor.
template <class F, class PoleFactor = std::nullptr_t>
double integrate_sphere(const F& f, const Vec3d& pole, double pole_width, std::span<const SphereFocus> foci,
                        std::span<const Vec3d> clips, const SphereQuadrature& q = {},
                        double pole_support = boost::math::constants::pi<double>(),
                        const PoleFactor& pole_factor = nullptr) {
  using boost::math::quadrature::gauss_kronrod;
  const double pi = boost::math::constants::pi<double>();
  constexpr bool polar_f = std::is_invocable_v<const F&, const SpherePoint&>;
  Vec3d e1, e2;
  detail::orthonormal_frame(pole, e1, e2);
  const double w_pole = std::max(pole_width, polar_f ? std::numeric_limits<double>::min() : q.min_width);
  const std::vector<detail::FocusPolar> polar = detail::foci_polar(foci, pole, e1, e2, q.min_width);

  detail::ThetaNodes<PoleFactor> nodes(pole_factor);
  // The θ integral along the meridian of azimuth φ, over where every clip is visible.
  // abs_tol < 0: one 15-point rule per panel (the coarse first pass that sets the scale).
  auto inner = [&](double phi, double abs_tol) -> double {
    const double cp = std::cos(phi), sp = std::sin(phi);
    const Vec3d e = cp * e1 + sp * e2;
    double lo = 0, hi = std::min(pi, pole_support);
    for (const auto& c : clips) {
      double l, h;
      if (!detail::visible_theta_interval(pole.dot(c), e.dot(c), l, h)) return 0.0;
      lo = std::max(lo, l);
      hi = std::min(hi, h);
      if (!(hi > lo)) return 0.0;
    }
    const std::vector<double> br = detail::theta_breaks(lo, hi, w_pole, polar, q.ratio, q.min_width);
    auto g = [&](const detail::ThetaNode& t) -> double {
      const Vec3d w = t.cos * pole + t.sin * e;
      if constexpr (polar_f) {
        return f(SpherePoint{w, t.theta, 2 * t.sin_half * t.sin_half, cp, sp, t.sin, t.pole_factor}) * t.sin;
      } else {
        return f(w) * t.sin;
      }
    };
    const auto rule = [&](double a, double b, double* err) { return nodes.rule(g, a, b, err); };
    const double share = abs_tol / double(br.size());
    return detail::sum_panels(br, [&](double a, double b) {
      return abs_tol < 0 ? rule(a, b, nullptr) : detail::adaptive_absolute(rule, a, b, share, q.max_depth);
    });
  };

  const std::vector<double> br = detail::azimuth_breaks(polar, q.ratio);
  // Pass 1: one rule per panel in θ and φ — the panels already follow the peaks, so this is
  // within a few percent, enough to turn the relative target into an absolute one.
  const double coarse = detail::sum_panels(br, [&](double a, double b) {
    return gauss_kronrod<double, detail::kSphereRulePoints>::integrate([&](double phi) { return inner(phi, -1.0); }, a,
                                                                       b, 0, 0.0);
  });
  if (!(coarse > 0)) return 0.0;  // the integrand is 0 (or underflows) everywhere the panels look
  // Pass 2: absolute tolerance τ = tolerance·coarse for the outer rule. The inner integrals are
  // made 1000× more accurate per radian of φ: the outer rule sees their error as noise in I(φ)
  // (their adaptive panel choices jump with φ), and a noise comparable to its own tolerance would
  // keep it bisecting to max_depth.
  const double tau = q.tolerance * coarse;
  const double inner_tol = 1e-3 * tau / (2 * pi);
  const double outer_share = tau / double(br.size());
  return detail::sum_panels(br, [&](double a, double b) {
    return detail::gauss_kronrod_absolute([&](double phi) { return inner(phi, inner_tol); }, a, b, outer_share,
                                          q.max_depth);
  });
}

// The smallest GGX α the specular reference accepts. Its panels follow the BRDF lobe, whose
// width ~2α(ωo·n) shrinks without bound: below this the cost grows past minutes a value (at
// α = 1e-8 and grazing view, hours), so smaller α are refused rather than left to hang. The
// same minimum as the renderer's scenes (scene.hpp kMinSceneRoughness).
inline constexpr double kMinReferenceRoughness = 1e-3;

// ---- the configuration of the `specular` quantity ---------------------------------------------
// n = (0, 0, 1), ωo = (√(1 − v²), 0, v), light axis ξ = (s cos φ, s sin φ, c), s = √(1 − c²).
struct SpecularConfig {
  double roughness;        // GGX α > 0
  double light_sharpness;  // λ ≥ 0
  double light_cos;        // ξ·n
  double view_cos;         // ωo·n ∈ [0, 1]
  double light_azimuth;    // φ, from the view's azimuth (π and light_cos = view_cos: mirror)
  double f0;               // Schlick reflectance at normal incidence
};

template <class T>
Vec3<T> specular_view(const T& view_cos) {
  const T v = clamp(view_cos, T(0), T(1));
  return Vec3<T>(safe_sqrt(sin2_from_cos(v)), T(0), v);
}

// The light axis ξ from its cosine and cos φ, sin φ of its azimuth (the renderer's columns and the
// SIMD pair kernels carry those, not φ); specular_light_axis from φ.
template <class T>
Vec3<T> specular_light_axis_cs(const T& light_cos, const T& cos_azimuth, const T& sin_azimuth) {
  const T c = clamp_cosine(light_cos);
  const T s = safe_sqrt(sin2_from_cos(c));
  return Vec3<T>(s * cos_azimuth, s * sin_azimuth, c);
}
template <class T>
Vec3<T> specular_light_axis(const T& light_cos, const T& light_azimuth) {
  using std::cos;
  using std::sin;
  return specular_light_axis_cs(light_cos, T(cos(light_azimuth)), T(sin(light_azimuth)));
}

// ∫ G(ω; pole, λ) h(ω) dω by integrate_sphere about the SG's axis, for any λ up to the largest
// double: the SG is evaluated from the exact 1 − cos θ (SpherePoint), only where it is nonzero in
// double (sg_support_angle), and the integrand is scaled by √λ and the result divided by it (for
// λ → DBL_MAX the value ≈ 2πh(ξ)/λ is near the smallest normal double, where the quadrature's
// absolute tolerances would underflow). So a sharp light tends to the point-light limit 2πh(ξ)/λ
// instead of the 0 (or 6.9e-24 at λ = 1e22) that a 1e-7 pole width and an SG from ω·ξ gave.
// Where the SG underflows to 0 h is not evaluated: h is finite, so the product is the same 0.
template <class H>
double integrate_sg_about_axis(const H& h, const Vec3d& xi, double lambda, std::span<const SphereFocus> foci,
                               std::span<const Vec3d> clips, const SphereQuadrature& q) {
  const double pole_width = lambda > 1 ? 1.0 / std::sqrt(lambda) : 1.0;
  const double scale = lambda > 1 ? std::sqrt(lambda) : 1.0;
  const auto light = [lambda](double one_minus_cos) { return std::exp(-lambda * one_minus_cos); };
  auto f = [&](const SpherePoint& p) -> double { return p.pole_factor == 0 ? 0.0 : scale * p.pole_factor * h(p.w); };
  return integrate_sphere(f, xi, pole_width, foci, clips, q, sg_support_angle(lambda), light) / scale;
}

// The exact L by the quadrature above: pole = light axis (width 1/√λ, capped at 1 rad for broad
// lights), foci = the mirror direction and the dominant-visible-normal reflection (width of the
// BRDF lobe in ω: ~2α(ωo·n) across the plane of incidence, the narrowest of its two widths),
// clip = the horizon. Right up to λ = DBL_MAX (integrate_sg_about_axis; tests/hardening_extremes_test.cpp
// checks it against the point-light limit 2π f(ωo, ξ)⟨ξ·n⟩/λ in 50 digits).
inline double specular_reference(const SpecularConfig& c, const SphereQuadrature& q = {}) {
  const double alpha = c.roughness;
  const Vec3d wo = specular_view(c.view_cos);
  const Vec3d xi = specular_light_axis(c.light_cos, c.light_azimuth);
  const double lambda = c.light_sharpness;
  const Vec3d n(0, 0, 1);
  auto h = [&](const Vec3d& w) { return ggx_brdf_cosine(alpha, c.f0, wo, w); };
  const double lobe_width = std::min(1.0, 2.0 * alpha * std::max(wo(2), 1e-3));
  const SphereFocus foci[2] = {{reflect_about(wo, n), lobe_width}, {dvn_reflection_lobe(alpha, wo).axis, lobe_width}};
  const Vec3d clips[1] = {n};
  return integrate_sg_about_axis(h, xi, lambda, foci, clips, q);
}

// ---- Monte Carlo check ------------------------------------------------------------------------

struct MonteCarloEstimate {
  double mean;
  double standard_error;
  std::uint64_t samples;
};

// Seeded estimator of the same L with multiple importance sampling (Veach 1997, balance
// heuristic, one-sample mixture): half the samples from the light's vMF (exact inversion,
// Jakob 2012 "Numerically stable sampling of the von Mises–Fisher distribution on S²"), half from
// the GGX NDF (Walter et al. 2007 Eq. 35–36, h reflected to ω with pdf D(h)(n·h)/(4|ωo·h|)).
// The mixture pdf covers both peaks, so the variance stays small at α = 0.01 and λ = 1e4.
inline MonteCarloEstimate specular_monte_carlo(const SpecularConfig& c, std::uint64_t samples, std::uint64_t seed) {
  const double pi = boost::math::constants::pi<double>();
  const double alpha = c.roughness, a2 = alpha * alpha;
  const double lambda = c.light_sharpness;
  const Vec3d wo = specular_view(c.view_cos);
  const Vec3d xi = specular_light_axis(c.light_cos, c.light_azimuth);
  Vec3d e1, e2;
  detail::orthonormal_frame(xi, e1, e2);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double vmf_norm = 1.0 / sg_integral(lambda);
  auto pdf_light = [&](const Vec3d& w) { return sg_eval(w, xi, lambda) * vmf_norm; };
  auto pdf_brdf = [&](const Vec3d& w) -> double {
    if (!(w(2) > 0)) return 0.0;  // the NDF sampler only produces ω with h in the upper hemisphere
    const Vec3d h = half_vector(wo, w);
    const double oh = wo.dot(h);
    if (!(oh > 0)) return 0.0;
    return ggx_ndf(alpha, h(2)) * h(2) / (4 * oh);
  };
  // Welford's running mean and sum of squared deviations (no E[x²] − E[x]² cancellation).
  double mean = 0, m2 = 0;
  for (std::uint64_t i = 0; i < samples; ++i) {
    const double u1 = uni(rng), u2 = uni(rng), u3 = uni(rng);
    Vec3d w;
    if (u1 < 0.5) {
      // vMF: cos θ = 1 + log(u + (1 − u)e^{−2λ})/λ (Jakob 2012), 1 − cos θ kept exact.
      // With u' = 1 − u also uniform: 1 − cos θ = −log1p(u'·expm1(−2λ))/λ, → 2u' as λ → 0.
      const double one_minus = lambda > 0 ? -std::log1p(u2 * std::expm1(-2 * lambda)) / lambda : 2 * u2;
      const double om = std::clamp(one_minus, 0.0, 2.0);
      const double ct = 1 - om;
      const double st = std::sqrt(om * (2 - om));
      const double ph = 2 * pi * u3;
      w = ct * xi + st * (std::cos(ph) * e1 + std::sin(ph) * e2);
    } else {
      // GGX NDF: cos²θh = (1 − u)/(1 + (α² − 1)u) (Walter et al. 2007 Eq. 35 in cosine form).
      const double c2 = (1 - u2) / (1 + (a2 - 1) * u2);
      const double ch = std::sqrt(c2), sh = std::sqrt(std::max(0.0, 1 - c2));
      const double ph = 2 * pi * u3;
      const Vec3d h(sh * std::cos(ph), sh * std::sin(ph), ch);
      w = reflect_about(wo, h);
    }
    const double value = sg_eval(w, xi, lambda) * ggx_brdf_cosine(alpha, c.f0, wo, w);
    double x = 0;
    if (value > 0) {
      const double pdf = 0.5 * pdf_light(w) + 0.5 * pdf_brdf(w);
      x = value / pdf;
    }
    const double delta = x - mean;
    mean += delta / double(i + 1);
    m2 += delta * (x - mean);
  }
  const double n = double(samples);
  return {mean, std::sqrt(m2 / (n - 1) / n), samples};
}

}  // namespace sglab
