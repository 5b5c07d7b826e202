// Exact references for the lobe-aware filtering weights: the similarity
//   q_ij = ∫ c_i c_j / √(∫ c_i² ∫ c_j²),   c_i = a_i ⊛ b,
// of two lobes a_i, a_j smoothed by a kernel b (Tokuyoshi 2015 (lobe-aware filtering), App. A and D; see
// filtering_weights.hpp), by direct numerical integration of that definition. Nothing here uses
// the closed forms or approximations under test (no Tsai–Shih product, no Iwasaki form, no
// λ̄ = λκ/(λ + κ), no τ̄² = τ² + ν²): the convolutions are integrated too.
// (Bessel's I0 of the SG's ring integral is the one special function used: asg.hpp, tested
// against Boost and its asymptotic series in asg_test.)
//
// ℝ^m, Gaussian lobes a_i = g(x − x_i, τ_i²), kernel b = g(·, ν²) (App. A). Both functions are
// products over the coordinates, so by Fubini q is the product of 1D similarities, one per
// coordinate offset. In 1D: c_i(x) = ∫ a_i(x') b(x − x') dx' and ∫ c_i c_j dx, nested quadrature
// on panels split at the peaks (x_i, x_j, x) and geometrically about them.
//
// Sphere, zonal lobes: a lobe is f(ω·ξ) for an axis ξ; here an SG f(t) = e^{λ(t−1)} or a clamped
// cosine f(t) = ⟨t⟩. The kernel is the vMF of sharpness κ, K(s) = e^{κ(s−1)}/A(κ) (the paper's
// Eq. (9) "the smoothing kernel is an SG with lobe sharpness κ"; κ = ∞: no smoothing). Symmetry
// reduces every integral to nested 1D integrals in polar angles about ξ_i, with the angle φ
// between the axes as a parameter:
//  • ring integral of the lobe f about ξ_j over the circle at polar angle θ from ξ_i,
//      R_f(θ, φ) = ∫_0^{2π} f(cos θ cos φ + sin θ sin φ cos ϕ) dϕ,
//    closed form for both shapes (the azimuthal integral):
//      SG:       2π e^{λ(cos(θ−φ) − 1)} I0e(λ sin θ sin φ)           (I0e(x) = e^{−x}I0(x))
//      cosine:   u = cos θ cos φ, v = sin θ sin φ: 2πu if u ≥ v; 0 if u ≤ −v (kinks where
//                cos(θ ± φ) = 0);
//                else 2(uψ + √m), m = v² − u² = −cos(θ+φ)cos(θ−φ), ψ = atan2(√m, −u);
//  • ring integral of the smoothed lobe f ⊛ K (exchange the order, integrate the kernel's ring):
//      R_{f⊛K}(θ, φ) = ∫_0^π sin θ' R_f(θ', φ) k_κ(θ, θ') dθ',
//      k_κ(θ, θ') = 2π e^{κ(cos(θ−θ') − 1)} I0e(κ sin θ sin θ')/A(κ);
//  • the smoothed lobe's own profile at angle θ from its axis: c(θ) = R_c(θ, 0)/(2π);
//  • ∫ c_i c_j dω = ∫_0^π sin θ c_i(θ) R_{c_j}(θ, φ) dθ.
// All exponents are ≤ 0 (nothing overflows for sharpnesses up to 1e6 and beyond); e^{...} is
// written with cos(θ − φ) − 1 = −2 sin²((θ − φ)/2) (no cancellation at the peak).
//
// Quadrature (integrate_panels): panel ends at the kinks of the clamped cosine's ring integral
// (θ + φ = π/2 or 3π/2, |θ − φ| = π/2, where R_f has (distance)^{3/2} behaviour) and at the peaks
// (0, φ, the kernel's θ, the SG product's axis), with further ends placed geometrically (ratio 2)
// about every peak from half its width 1/√λ outwards; the kernel's integral stops where it is
// below ε³ of its peak. Each panel gets a 31-point Gauss–Kronrod rule; those whose error estimate
// misses the target are redone by tanh-sinh (Boost.Math), which converges doubly exponentially
// on the kink panels too. Each nesting level has its own tanh-sinh integrator (Boost refines its
// tables lazily, so one instance must not be re-entered). Double only for the smoothed (nested)
// references in practice: a 50-digit 1D quadrature already takes ~1 s.
//
// Accuracy (tests/filtering_weights_test.cpp): at κ = ∞ against the closed forms of
// filtering_weights.hpp, ≤ 2e-15 relative in double over λ ∈ [1e-3, 1e5] (≤ 5e-14 where q is
// below 1e-20: the rounding of a large exponent), ≤ 3e-48 in mp50; Gaussian lobes ≤ 1e-15
// (double), ≤ 1e-50 (mp50); the κ-smoothed
// ring integrals against an azimuthal quadrature of independently computed smoothed profiles
// (Tsai–Shih for SGs, reference.hpp's D(κ, t) for the cosine): ≤ 1e-11.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <boost/math/quadrature/gauss_kronrod.hpp>
#include <boost/math/quadrature/tanh_sinh.hpp>

#include "sglab/asg_integral.hpp"  // bessel_i0_scaled
#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"

namespace sglab {

// A zonal lobe profile f(ω·ξ).
enum class ZonalLobeShape { sg, clamped_cosine };

template <class T>
struct ZonalLobe {
  ZonalLobeShape shape;
  T sharpness;  // the SG's λ ≥ 0 (ignored for the clamped cosine)
};

namespace filtering_detail {

// One tanh-sinh integrator per nesting level and thread (see the header comment).
template <class T>
boost::math::quadrature::tanh_sinh<T>& integrator(int level) {
  thread_local boost::math::quadrature::tanh_sinh<T> levels[3];
  return levels[level];
}

// Panel ends c ± w·2^k (k = −1, 0, 1, …) inside (lo, hi), plus c itself if inside.
template <class T>
void add_geometric_breaks(std::vector<T>& out, const T& c, const T& width, const T& lo, const T& hi) {
  if (c > lo && c < hi) out.push_back(c);
  if (!(width > 0)) return;
  for (T d = width / 2; d < hi - lo; d *= 2) {
    if (c + d > lo && c + d < hi) out.push_back(c + d);
    if (c - d > lo && c - d < hi) out.push_back(c - d);
  }
}

// ∫ f over [breaks.front(), breaks.back()] (breaks in any order, duplicates allowed), to an
// absolute error of about `tolerance` × the integral's scale, in two passes (as in
// glossy_reference.hpp): a 31-point Gauss–Kronrod rule per panel gives each panel's value, error
// estimate and the scale S = Σ|panel|; a panel whose GK error estimate exceeds tolerance·S/n
// (n panels) is integrated again by tanh-sinh with the relative tolerance that makes its
// absolute error ≈ tolerance·S/n. Panels are placed at every peak and kink, so most are smooth
// on the scale of their length and the GK result is final (31 evaluations); panels ending at a
// kink of the clamped cosine ((distance)^{3/2} behaviour) go to tanh-sinh, which converges
// doubly exponentially there. Without the scale, a panel on which the integrand is only
// rounding residue would be refined to tanh-sinh's last level for nothing.
template <class T, class F>
T integrate_panels(std::vector<T> breaks, const F& f, int level, const T& tolerance) {
  using std::abs;
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
  const std::size_t n = breaks.size() < 2 ? 0 : breaks.size() - 1;
  std::vector<T> value(n, T(0)), error(n, T(0)), l1(n, T(0));
  T scale = T(0);
  for (std::size_t i = 0; i < n; ++i) {
    value[i] = boost::math::quadrature::gauss_kronrod<T, 31>::integrate(f, breaks[i], breaks[i + 1], 0, T(0), &error[i],
                                                                        &l1[i]);
    scale += l1[i];
  }
  const T target = tolerance * scale / T(n > 0 ? n : 1);
  auto& ts = integrator<T>(level);
  T sum = T(0);
  for (std::size_t i = 0; i < n; ++i) {
    if (error[i] > target && l1[i] > T(1e-2) * target) {
      T relative = l1[i] > target ? T(target / l1[i]) : T(0.1);
      if (relative > T(0.1)) relative = T(0.1);
      // Boost's two-argument form (abscissa, distance to the nearer end): the one-argument
      // form of Boost 1.74 can place an abscissa exactly on an end of a short panel (its
      // assertion `position != a`).
      value[i] = ts.integrate([&](const T& x, const T&) { return f(x); }, breaks[i], breaks[i + 1], relative);
    }
    sum += value[i];
  }
  return sum;
}

// The default error target of the references, relative to the integral's scale: 1000 ε
// (2.2e-13 in double, 1e-47 in mp50). The GK31 error estimate is pessimistic for smooth panels
// (it is (200|G − K|)^{3/2}), so the results are closer to ε (measured: ≤ 1e-15 relative in
// double, ≤ 1e-48 in mp50 against closed forms, tests/filtering_weights_test.cpp).
template <class T>
T default_tolerance() {
  return T(epsilon<T>()) * T(1000);
}

// Angular width of an SG peak of sharpness λ for panel placement: 1/√λ (π when broad).
template <class T>
T angular_width(const T& sharpness) {
  using std::sqrt;
  return sharpness > T(1) ? T(T(1) / sqrt(sharpness)) : pi<T>();
}

// e^{λ(cos d − 1)} with cos d − 1 = −2 sin²(d/2).
template <class T>
T sg_of_angle(const T& sharpness, const T& angle) {
  using std::exp;
  using std::sin;
  const T h = sin(angle / 2);
  return exp(T(-2) * sharpness * h * h);
}

// The angular radius beyond which an SG of sharpness λ is below ε³ of its peak (negligible at
// T's precision, as in reference.hpp): 2λ sin²(d/2) = −3 ln ε.
template <class T>
T sg_reach(const T& sharpness) {
  using std::asin;
  using std::log;
  using std::sqrt;
  const T cutoff = T(-3) * log(T(epsilon<T>()));
  const T x = sqrt(cutoff / (T(2) * sharpness));
  return x < T(1) ? T(T(2) * asin(x)) : pi<T>();
}

// Panel ends of an integral over θ ∈ [lo, hi] that involves the lobe f about an axis at angle φ:
// φ and geometric about it at the SG's width (`width`, already including any smoothing), and the
// kinks π/2 ± φ of the clamped cosine.
template <class T>
void add_lobe_breaks(std::vector<T>& b, const ZonalLobe<T>& f, const T& phi, const T& width, const T& lo, const T& hi) {
  const T half_pi = pi<T>() / 2;
  if (f.shape == ZonalLobeShape::sg) {
    add_geometric_breaks(b, phi, width, lo, hi);
  } else {
    if (phi > lo && phi < hi) b.push_back(phi);
    // The kinks of R_f: θ + φ = π/2 or 3π/2, |θ − φ| = π/2 (see zonal_ring_integral).
    for (const T& k : {T(half_pi - phi), T(T(3) * half_pi - phi), T(phi + half_pi), T(phi - half_pi)}) {
      if (k > lo && k < hi) b.push_back(k);
    }
  }
}

}  // namespace filtering_detail

// R_f(θ, φ) = ∫_0^{2π} f(cos θ cos φ + sin θ sin φ cos ϕ) dϕ for θ, φ ∈ [0, π] (closed forms above).
template <class T>
T zonal_ring_integral(const ZonalLobe<T>& f, const T& theta, const T& phi) {
  using std::abs;
  using std::atan2;
  using std::cos;
  using std::sin;
  using std::sqrt;
  if (f.shape == ZonalLobeShape::sg) {
    const T x = f.sharpness * sin(theta) * sin(phi);
    // e^{−x}I0(x) = e^{−x}(1 + x²/4 + x⁴/64 + …): for x below ε^{1/4} the two terms are exact.
    // (The axes at φ = 0 or π make x a rounding residue; Boost's I0 costs ~1 ms in 50 digits.)
    using std::exp;
    const T i0e = x < T(series_threshold<T>(4)) ? T(exp(-x) * (T(1) + x * x / T(4))) : T(bessel_i0_scaled(x));
    return two_pi<T>() * filtering_detail::sg_of_angle(f.sharpness, T(theta - phi)) * i0e;
  }
  // The circle is wholly above the horizon iff cos(θ + φ) ≥ 0 (u ≥ v), i.e. θ + φ ≤ π/2 or
  // θ + φ ≥ 3π/2, and wholly below iff cos(θ − φ) ≤ 0 (u ≤ −v), i.e. |θ − φ| ≥ π/2. Decided on
  // the angles, the same numbers as the panel ends (add_lobe_breaks), so that a panel beyond a
  // kink sees exact zeros, not cos(π/2) = 6e-17 residue.
  const T half_pi = pi<T>() / 2;
  const T u = cos(theta) * cos(phi);
  if (theta + phi <= half_pi || theta + phi >= T(3) * half_pi) return two_pi<T>() * u;
  if (abs(theta - phi) >= half_pi) return T(0);
  const T m = -cos(theta + phi) * cos(theta - phi);
  const T root = safe_sqrt(m);
  return T(2) * (u * atan2(root, -u) + root);
}

// R_{f⊛K}(θ, φ) for the vMF kernel of sharpness κ (κ = +∞: R_f itself). The θ' integral runs
// over the kernel's reach about θ (beyond it the kernel is below ε³ of its peak).
template <class T>
T smoothed_ring_integral(const ZonalLobe<T>& f, const T& theta, const T& phi, const T& kappa,
                         const T& tolerance = filtering_detail::default_tolerance<T>(), int level = 1) {
  using std::isinf;
  using std::sin;
  if (isinf(kappa)) return zonal_ring_integral(f, theta, phi);
  const T norm = sg_integral(kappa);
  const T sin_theta = sin(theta);
  auto integrand = [&](const T& tp) -> T {
    const T kernel = two_pi<T>() * filtering_detail::sg_of_angle(kappa, T(theta - tp)) *
                     bessel_i0_scaled(T(kappa * sin_theta * sin(tp))) / norm;
    if (kernel == 0) return T(0);
    return sin(tp) * zonal_ring_integral(f, tp, phi) * kernel;
  };
  const T reach = filtering_detail::sg_reach(kappa);
  const T lo = theta - reach > T(0) ? T(theta - reach) : T(0);
  const T hi = theta + reach < pi<T>() ? T(theta + reach) : pi<T>();
  std::vector<T> breaks{lo, hi};
  filtering_detail::add_geometric_breaks(breaks, theta, filtering_detail::angular_width(kappa), lo, hi);
  filtering_detail::add_lobe_breaks(breaks, f, phi, filtering_detail::angular_width(f.sharpness), lo, hi);
  return filtering_detail::integrate_panels(std::move(breaks), integrand, level, tolerance);
}

// ∫_{S²} c_i(ω·ξ_i) c_j(ω·ξ_j) dω for lobes smoothed by the vMF kernel of sharpness κ
// (κ = +∞: the lobes themselves), ξ_i·ξ_j = cosine.
template <class T>
T zonal_lobe_inner_product(const ZonalLobe<T>& lobe_i, const ZonalLobe<T>& lobe_j, const T& cosine, const T& kappa,
                           const T& tolerance = filtering_detail::default_tolerance<T>()) {
  using std::acos;
  using std::atan2;
  using std::cos;
  using std::isinf;
  using std::sin;
  using std::sqrt;
  const T phi = acos(clamp_cosine(cosine));
  const bool smoothed = !isinf(kappa);
  auto profile_i = [&](const T& theta) -> T {  // c_i at angle θ from ξ_i
    if (!smoothed) {
      if (lobe_i.shape == ZonalLobeShape::sg) {
        return filtering_detail::sg_of_angle(lobe_i.sharpness, theta);
      }
      return positive_part(T(cos(theta)));
    }
    return smoothed_ring_integral(lobe_i, theta, T(0), kappa, tolerance, 1) / two_pi<T>();
  };
  auto integrand = [&](const T& theta) -> T {
    const T ci = profile_i(theta);
    if (ci == 0) return T(0);
    return sin(theta) * ci * smoothed_ring_integral(lobe_j, theta, phi, kappa, tolerance, 1);
  };
  // Widths of the (smoothed) peaks: the variances 1/λ and 1/κ add (Eq. C.1 is only used here to
  // place panel ends; the integral itself is exact).
  auto width = [&](const ZonalLobe<T>& f) -> T {
    if (f.shape != ZonalLobeShape::sg) return pi<T>();
    const T inv = (f.sharpness > T(0) ? T(T(1) / f.sharpness) : T(1)) + (smoothed ? T(T(1) / kappa) : T(0));
    return filtering_detail::angular_width(T(T(1) / inv));
  };
  std::vector<T> breaks{T(0), pi<T>()};
  filtering_detail::add_lobe_breaks(breaks, lobe_i, T(0), width(lobe_i), T(0), pi<T>());
  filtering_detail::add_lobe_breaks(breaks, lobe_j, phi, width(lobe_j), T(0), pi<T>());
  if (lobe_i.shape == ZonalLobeShape::sg && lobe_j.shape == ZonalLobeShape::sg) {
    // Peak of the product of the two SGs: the axis of λ_iξ_i + λ_jξ_j.
    const T li = lobe_i.sharpness, lj = lobe_j.sharpness;
    const T peak = atan2(T(lj * sin(phi)), T(li + lj * cos(phi)));
    const T l3 = sqrt(li * li + lj * lj + T(2) * li * lj * cos(phi));
    filtering_detail::add_geometric_breaks(breaks, peak, filtering_detail::angular_width(l3), T(0), pi<T>());
  }
  return filtering_detail::integrate_panels(std::move(breaks), integrand, 0, tolerance);
}

// q_ij = ∫c_ic_j/√(∫c_i² ∫c_j²) by direct numerical integration (see the header comment).
template <class T>
T lobe_similarity_reference(const ZonalLobe<T>& lobe_i, const ZonalLobe<T>& lobe_j, const T& cosine, const T& kappa,
                            const T& tolerance = filtering_detail::default_tolerance<T>()) {
  using std::sqrt;
  const T ij = zonal_lobe_inner_product(lobe_i, lobe_j, cosine, kappa, tolerance);
  const T ii = zonal_lobe_inner_product(lobe_i, lobe_i, T(1), kappa, tolerance);
  const T jj = zonal_lobe_inner_product(lobe_j, lobe_j, T(1), kappa, tolerance);
  return ij / sqrt(ii * jj);
}

// ---- ℝ^m, Gaussian lobes (App. A) ----------------------------------------------------------------

// The 1D similarity of a_i = g(x − x_i, τ_i²), a_j = g(x − x_j, τ_j²) smoothed by g(·, ν²)
// (ν² = 0: unsmoothed), g(x, σ²) = exp(−x²/(2σ²)), by nested quadrature over ℝ (truncated 40
// widths beyond the outermost peak, where g < e^{−800}).
template <class T>
T gaussian_similarity_reference_1d(const T& offset, const T& variance_i, const T& variance_j,
                                   const T& kernel_variance) {
  using std::exp;
  using std::sqrt;
  const T sd_i = sqrt(variance_i), sd_j = sqrt(variance_j), sd_k = sqrt(kernel_variance);
  auto g = [](const T& x, const T& var) -> T { return exp(-x * x / (T(2) * var)); };
  // c(x) for the lobe centred at `centre` with variance `var`.
  auto smoothed = [&](const T& x, const T& centre, const T& var, const T& sd) -> T {
    if (!(kernel_variance > 0)) return g(T(x - centre), var);
    const T reach = T(40) * (sd > sd_k ? sd : sd_k);
    std::vector<T> breaks{T(centre - reach), T(centre + reach), T(x - reach), T(x + reach)};
    filtering_detail::add_geometric_breaks(breaks, centre, sd, T(centre - reach), T(centre + reach));
    filtering_detail::add_geometric_breaks(breaks, x, sd_k, T(x - reach), T(x + reach));
    return filtering_detail::integrate_panels(
        std::move(breaks), [&](const T& xp) { return g(T(xp - centre), var) * g(T(x - xp), kernel_variance); }, 1,
        filtering_detail::default_tolerance<T>());
  };
  auto inner = [&](const T& ci, const T& vi, const T& si, const T& cj, const T& vj, const T& sj) -> T {
    const T wi = sqrt(vi + kernel_variance), wj = sqrt(vj + kernel_variance);
    const T lo = (ci < cj ? ci : cj) - T(40) * (wi > wj ? wi : wj);
    const T hi = (ci > cj ? ci : cj) + T(40) * (wi > wj ? wi : wj);
    std::vector<T> breaks{lo, hi};
    filtering_detail::add_geometric_breaks(breaks, ci, wi, lo, hi);
    filtering_detail::add_geometric_breaks(breaks, cj, wj, lo, hi);
    return filtering_detail::integrate_panels(
        std::move(breaks), [&](const T& x) { return smoothed(x, ci, vi, si) * smoothed(x, cj, vj, sj); }, 0,
        filtering_detail::default_tolerance<T>());
  };
  const T ij = inner(T(0), variance_i, sd_i, offset, variance_j, sd_j);
  const T ii = inner(T(0), variance_i, sd_i, T(0), variance_i, sd_i);
  const T jj = inner(T(0), variance_j, sd_j, T(0), variance_j, sd_j);
  return ij / sqrt(ii * jj);
}

}  // namespace sglab
