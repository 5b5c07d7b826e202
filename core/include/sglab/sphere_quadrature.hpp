// Adaptive quadrature over the sphere of an integrand with a peak at a pole and further peaks
// (foci), clipped to half-spaces (integrate_sphere), and of an SG about its axis times a function
// of ω (integrate_sg_about_axis): the machinery of the exact specular references
// (glossy_reference.hpp, gaussian_ndf.hpp) and the ASG reference (registry_glossy.cpp).
//
// Spherical coordinates (θ, φ) about the pole p (for the references, the light axis): an SG about
// p is then a function of θ alone, peaked at θ = 0 with width 1/√λ. Each focus is a second peak at
// its own (θ_f, φ_f) (for the GGX reference the mirror direction and the dominant-visible-normal
// reflection, of width ~α). The outer integral runs over φ, the inner over θ. Kinks and peaks are
// made panel ends:
//  • inner θ: the visible interval [θ_lo(φ), θ_hi(φ)] where every clip is visible, ω·q > 0 (solved
//    in closed form: the horizon is where cos θ (p·q) + sin θ (e(φ)·q) = 0), split geometrically
//    about 0 (pole width), about each focus' θ_f (focus width), and about both interval ends (the
//    horizon, where the GGX G2 vanishes linearly on a scale ~α(ωo·n));
//  • outer φ: split at each focus azimuth φ_f and geometrically about it at the angular width
//    w_f/sin θ_f that the focus subtends.
// Two passes: one 15-point Gauss–Kronrod rule per panel gives the scale of the integral; then
// every panel is refined adaptively (Boost.Math's 7/15 nodes) to an absolute error of 1e-6 of
// that scale. Geometric splitting (ratio 2, starting a quarter of a width from the peak) resolves
// every scale between the narrowest lobe width and π at a cost logarithmic in the sharpness, so
// α = 0.01 with λ = 1e4 costs only a few more panels than α = 1 with λ = 1.
// Each θ rule's 15 nodes are handed to the integrand at once (gauss_kronrod_at_once, Boost's rule
// and sums), so that one with a `points` form evaluates them on vector registers (the GGX
// reference's GgxCosine).
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include <boost/container_hash/hash.hpp>
#include <boost/math/constants/constants.hpp>
#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "sglab/scalar.hpp"

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

// Boost.Math's 15-point Gauss–Kronrod rule on [a, b] without bisection, as
// gauss_kronrod<double, 15>::integrate(f, a, b, 0, 0.0, err) computes it (Boost 1.74:
// integrate, recursive_adaptive_integrate, integrate_non_adaptive_m1_1), but with its nodes handed
// to `values(x, fx)` all at once (fx[k] = f(x[k]), k < 15) so that an integrand can evaluate them on
// vector registers. The nodes (scale·x + mean), the order of the sums and the error estimate are
// Boost's, so the value and *err have its bits (tests/glossy_reference_test.cpp holds them to it).
template <class Values>
double gauss_kronrod_at_once(const Values& values, double a, double b, double* err) {
  using boost::math::quadrature::gauss;
  using boost::math::quadrature::gauss_kronrod;
  constexpr unsigned N = kSphereRulePoints;
  static_assert(((N - 1) / 2) % 2 == 1,
                "Boost's order below is that of an odd Gauss order (its centre is a Gauss node)");
  if (a == b) return 0.0;  // Boost returns 0 and leaves *err as it is
  if (b < a) return -gauss_kronrod_at_once(values, b, a, err);
  // Boost maps an infinite end onto a finite interval first; this rule's callers never pass one.
  if (!std::isfinite(a) || !std::isfinite(b))
    throw std::domain_error("gauss_kronrod_at_once: the interval's ends must be finite numbers");
  const auto& abscissa = gauss_kronrod<double, N>::abscissa();
  const auto& weight = gauss_kronrod<double, N>::weights();
  const auto& gauss_weight = gauss<double, (N - 1) / 2>::weights();
  const double mean = (b + a) / 2, scale = (b - a) / 2;
  // Boost's calls: the centre, then +x and −x of the Gauss abscissae (i = 2, 4, 6), then of the
  // Kronrod ones (i = 1, 3, 5, 7).
  std::array<double, N> x, fx;
  std::size_t k = 0;
  x[k++] = scale * 0.0 + mean;
  for (unsigned i = 2; i < abscissa.size(); i += 2) {
    x[k++] = scale * abscissa[i] + mean;
    x[k++] = scale * -abscissa[i] + mean;
  }
  for (unsigned i = 1; i < abscissa.size(); i += 2) {
    x[k++] = scale * abscissa[i] + mean;
    x[k++] = scale * -abscissa[i] + mean;
  }
  values(x.data(), fx.data());
  double kronrod = fx[0] * weight[0];
  double gauss_sum = 0;
  gauss_sum += fx[0] * gauss_weight[0];
  k = 1;
  for (unsigned i = 2; i < abscissa.size(); i += 2, k += 2) {
    kronrod += (fx[k] + fx[k + 1]) * weight[i];
    gauss_sum += (fx[k] + fx[k + 1]) * gauss_weight[i / 2];
  }
  for (unsigned i = 1; i < abscissa.size(); i += 2, k += 2) kronrod += (fx[k] + fx[k + 1]) * weight[i];
  if (err)
    *err = std::max(std::abs(kronrod - gauss_sum), std::abs(kronrod * std::numeric_limits<double>::epsilon() * 2.0));
  return scale * kronrod;
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

  // One rule on [a, b] (gauss_kronrod_at_once: Boost's) of an integrand of the θ nodes, given
  // as g_nodes(nodes, out, n): out[k] = g(nodes[k]) for the rule's n nodes, all at once.
  template <class GNodes>
  double rule(const GNodes& g_nodes, double a, double b, double* err) {
    const Key key{std::bit_cast<std::uint64_t>(a), std::bit_cast<std::uint64_t>(b)};
    Panel unkept;  // a panel past the store's bound: its nodes are computed and not kept
    auto found = panels_.find(key);
    if (found == panels_.end() && panels_.size() < kMaxThetaPanels) found = panels_.emplace(key, Panel{}).first;
    Panel& panel = found == panels_.end() ? unkept : found->second;
    const auto values = [&](const double* theta, double* out) {
      std::array<ThetaNode, kSphereRulePoints> t;
      for (std::size_t k = 0; k < kSphereRulePoints; ++k) {
        if (k < panel.count &&
            std::bit_cast<std::uint64_t>(panel.nodes[k].theta) == std::bit_cast<std::uint64_t>(theta[k])) {
          t[k] = panel.nodes[k];
          continue;
        }
        t[k] = node(theta[k]);
        if (k == panel.count) panel.nodes[panel.count++] = t[k];
      }
      g_nodes(t.data(), out, kSphereRulePoints);
    };
    return gauss_kronrod_at_once(values, a, b, err);
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

// An integrand of SpherePoints that also evaluates n ≤ detail::kSphereRulePoints of them at once
// (f.points(p, out, n): out[k] = f(p[k]), the same bits), which integrate_sphere then calls once per
// rule instead of f once per node.
template <class F>
concept SpherePointsIntegrand = requires(const F& f, const SpherePoint* p, double* out, std::size_t n) {
  f.points(p, out, n);
};

// A function of directions that also evaluates n ≤ detail::kSphereRulePoints of them at once
// (h.points(x, y, z, out, n): out[k] = h(Vec3d(x[k], y[k], z[k])), the same bits).
template <class H>
concept DirectionPointsFunction = requires(const H& h, const double* x, const double* y, const double* z, double* out,
                                           std::size_t n) {
  h.points(x, y, z, out, n);
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
  constexpr bool points_f = SpherePointsIntegrand<F>;
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
    auto direction = [&](const detail::ThetaNode& t) { return Vec3d(t.cos * pole + t.sin * e); };
    auto point = [&](const detail::ThetaNode& t) {
      return SpherePoint{direction(t), t.theta, 2 * t.sin_half * t.sin_half, cp, sp, t.sin, t.pole_factor};
    };
    // The rule's nodes at once: f.points on all of them where f has it (SpherePointsIntegrand),
    // else f node by node; either way f's value times sin θ.
    auto g_nodes = [&](const detail::ThetaNode* t, double* out, std::size_t n) {
      if constexpr (points_f) {
        std::array<SpherePoint, detail::kSphereRulePoints> p;
        for (std::size_t k = 0; k < n; ++k) p[k] = point(t[k]);
        f.points(p.data(), out, n);
        for (std::size_t k = 0; k < n; ++k) out[k] = out[k] * t[k].sin;
      } else if constexpr (polar_f) {
        for (std::size_t k = 0; k < n; ++k) out[k] = f(point(t[k])) * t[k].sin;
      } else {
        for (std::size_t k = 0; k < n; ++k) out[k] = f(direction(t[k])) * t[k].sin;
      }
    };
    const auto rule = [&](double a, double b, double* err) { return nodes.rule(g_nodes, a, b, err); };
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

namespace detail {
// integrate_sg_about_axis' integrand: scale·G·h at a SpherePoint (G its pole factor; h not
// evaluated where G is 0), and at n points at once where h evaluates directions so.
template <class H>
struct ScaledSg {
  const H& h;
  double scale;
  double operator()(const SpherePoint& p) const { return p.pole_factor == 0 ? 0.0 : scale * p.pole_factor * h(p.w); }
  void points(const SpherePoint* p, double* out, std::size_t n) const requires DirectionPointsFunction<H> {
    std::array<double, kSphereRulePoints> x, y, z;
    for (std::size_t k = 0; k < n; ++k) x[k] = p[k].w(0), y[k] = p[k].w(1), z[k] = p[k].w(2);
    h.points(x.data(), y.data(), z.data(), out, n);  // also where G is 0: those values are not used
    for (std::size_t k = 0; k < n; ++k) out[k] = p[k].pole_factor == 0 ? 0.0 : scale * p[k].pole_factor * out[k];
  }
};
}  // namespace detail

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
  const detail::ScaledSg<H> f{h, scale};
  return integrate_sphere(f, xi, pole_width, foci, clips, q, sg_support_angle(lambda), light) / scale;
}

}  // namespace sglab
