// Exact references by deterministic quadrature (docs/math.md §2 and §3), templated on the scalar
// type so that the same code gives a double reference (≤ 1e-12 relative) and a 50-digit one.
//
// Formulation. Measure directions by t = ω·ξ (the cosine from the lobe axis) and the azimuth φ
// about ξ. With c = ξ·n and s = √(1 − c²), ω·n = tc + s√(1 − t²) cos φ, so both integrals are
// one-dimensional in t after the azimuthal integral is done in closed form:
//   H(λ, c) = ∫_{−1}^{1} e^{λ(t−1)} g_H(t) dt,   D(λ, c) = ∫_{−1}^{1} e^{λ(t−1)} g_D(t) dt,
// where, with u = tc and m = s² − t² = (s − t)(s + t) (the azimuth is only partly visible when
// |t| < s):
//   g_H = 2π, g_D = 2πu                     if the whole circle is above the horizon (u ≥ 0, m ≤ 0)
//   g_H = g_D = 0                           if it is wholly below (u < 0, m ≤ 0)
//   g_H = 2ψ, g_D = 2(uψ + √m)              otherwise, ψ = atan2(√m, −u)
// ψ = acos(−u/v) with v = s√(1 − t²), written as atan2 so that the endpoints |t| = s, where the
// acos argument reaches ±1 through cancellation, stay exact (v² − u² = m exactly).
// This is the θ-integral of docs/math.md §2 (I0 Bessel form) with the azimuth taken around ξ instead
// of n; the two are compared in tests/reference_test.cpp.
//
// Quadrature. The three panels [−1, −s], [−s, s], [s, 1] are smooth inside (the kinks at ±s are
// panel ends). On each panel the factor e^{λ(t−1)} peaks at the upper end b, so the panel is
// written as e^{λ(b−1)} ∫_0^{b−a} e^{−λx} g(b − x) dx and split geometrically in x at
// 2^k/λ (k = −1, 0, 1, …) until e^{−λx} is below T's epsilon; each piece is integrated with
// tanh-sinh (Boost.Math), which handles the square-root endpoint behaviour of g at ±s.
// Every exponent is ≤ 0, so nothing overflows for λ up to 1e8 and beyond.
#pragma once

#include <vector>

#include <boost/math/quadrature/tanh_sinh.hpp>

#include "sglab/scalar.hpp"

namespace sglab {
namespace detail {

template <class T>
boost::math::quadrature::tanh_sinh<T>& tanh_sinh_integrator() {
  // Constructing the abscissa tables is the expensive part (notably for mp50): one per type and
  // thread (the integrator refines its tables lazily, so it is not shared across threads).
  thread_local boost::math::quadrature::tanh_sinh<T> integrator;
  return integrator;
}

// ∫_0^{length} e^{−λx} h(x, length − x) dx, geometric pieces in x as described above. h receives
// the distance to both ends of [0, length] exactly (from tanh-sinh's complement argument), so
// square-root behaviour at either end is resolved to full precision.
template <class T, class H>
T integrate_decaying(const T& sharpness, const T& length, const H& h) {
  using std::log;
  using std::min;
  using std::sqrt;
  if (!(length > 0)) return T(0);
  auto& ts = tanh_sinh_integrator<T>();
  // Beyond x·λ = cutoff, e^{−λx} < eps³ relative to the peak: negligible at T's precision.
  const T cutoff = T(-3) * log(T(epsilon<T>()));
  std::vector<T> breaks{T(0)};
  if (sharpness > T(0.5)) {
    T x = T(0.5) / sharpness;
    while (x < length && x * sharpness < cutoff) {
      breaks.push_back(x);
      x *= 2;
    }
    breaks.push_back(min(length, x));
  } else {
    breaks.push_back(length);
  }
  const T tolerance = sqrt(T(epsilon<T>())) * T(1e-2);
  T sum = T(0);
  for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
    const T a = breaks[i], b = breaks[i + 1];
    if (!(b > a)) continue;
    // Boost's two-argument form: xc = a − x (≤ 0) on the left half of [a, b], b − x (≥ 0) on
    // the right half, exact even where x itself rounds to an end.
    auto f = [&](const T&, const T& xc) -> T {
      using std::exp;
      const T& end = xc < 0 ? a : b;
      const T from_start = end - xc;
      const T to_end = (length - end) + xc;
      return exp(-sharpness * from_start) * h(from_start, to_end);
    };
    sum += ts.integrate(f, a, b, tolerance);
  }
  return sum;
}

// ∫_{t=-1}^{1} e^{λ(t−1)} g(t, s − t, s + t) dt over the three panels [−1, −s], [−s, s], [s, 1].
// On the middle panel t = s − x, so s − t = x and s + t = 2s − x = length − x, both exact.
template <class T, class G>
T integrate_over_cosine(const T& sharpness, const T& s, const G& g) {
  using std::exp;
  T total = T(0);
  const T ends[4] = {T(-1), -s, s, T(1)};
  for (int p = 0; p < 3; ++p) {
    const T a = ends[p], b = ends[p + 1];
    if (!(b > a)) continue;
    const T scale = exp(sharpness * (b - T(1)));
    if (scale == 0) continue;
    auto h = [&](const T& x, const T& rest) -> T {
      const T t = b - x;
      if (p == 1) return g(t, x, rest);
      return g(t, T(s - t), T(s + t));
    };
    total += scale * integrate_decaying(sharpness, T(b - a), h);
  }
  return total;
}

// ∫_{−1}^{1} e^{λ(t−1)} g(t) dt for an azimuthal integral g of the formulation above, given by
// `whole(u)` where the circle is wholly above the horizon (u ≥ 0, m ≤ 0) and `partial(u, √m)` where
// it is partly visible (m > 0); wholly below, g = 0.
template <class T, class Whole, class Partial>
T integrate_azimuthal(const T& sharpness, const T& cosine, const Whole& whole, const Partial& partial) {
  using std::sqrt;
  const T c = clamp_cosine(cosine);
  const T s = sqrt((T(1) - c) * (T(1) + c));
  auto g = [&](const T& t, const T& s_minus_t, const T& s_plus_t) -> T {
    const T u = t * c;
    const T m = s_minus_t * s_plus_t;
    if (!(m > 0)) return u >= 0 ? whole(u) : T(0);
    return partial(u, sqrt(m));
  };
  return integrate_over_cosine(sharpness, s, g);
}

}  // namespace detail

// Exact H(λ, c) = ∫_{ω·n>0} G(ω; ξ, λ) dω. Valid for λ ≥ 0, any c (clamped to [−1, 1]).
template <class T>
T hemispherical_reference(const T& sharpness, const T& cosine) {
  using std::atan2;
  return detail::integrate_azimuthal(
      sharpness, cosine, [](const T&) { return two_pi<T>(); },
      [](const T& u, const T& root) -> T { return T(2) * atan2(root, -u); });
}

// Exact D(λ, c) = ∫ G(ω; ξ, λ)⟨ω·n⟩ dω (docs/math.md §3, method `reference`).
template <class T>
T clamped_cosine_reference(const T& sharpness, const T& cosine) {
  using std::atan2;
  return detail::integrate_azimuthal(
      sharpness, cosine, [](const T& u) -> T { return two_pi<T>() * u; },
      [](const T& u, const T& root) -> T { return T(2) * (u * atan2(root, -u) + root); });
}

// The double quadratures are compiled once, in core/src/quadrature_reference.cpp: the registry,
// the fits, the renderer and the tests link them instead of instantiating tanh-sinh again in every
// unit that includes this header (other types still instantiate here; the mp50 ones are declared
// with the type, in sglab/reference_mp50.hpp).
extern template double hemispherical_reference<double>(const double&, const double&);
extern template double clamped_cosine_reference<double>(const double&, const double&);

}  // namespace sglab
