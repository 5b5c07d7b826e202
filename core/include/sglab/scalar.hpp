// Scalar types and small, safe numeric helpers shared by every core header.
//
// Every function in core/ is a template on the scalar type T and calls math unqualified
// (`using std::exp; exp(x)`) so that float, double, ceres::Jet and the 50-digit mp50 type
// (sglab/mp50.hpp) all instantiate it. Helpers here follow pbrt-v4's util/math.h habit: one small function per
// numerical hazard, with the reason written next to it.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include <boost/math/constants/constants.hpp>

namespace ceres {
template <typename T, int N>
struct Jet;
}

namespace sglab {

// ---- scalar traits -------------------------------------------------------------------------
template <class T>
struct scalar_traits {
  using value_type = T;  // the plain number type underneath (double for Jet<double, N>)
  static const T& value(const T& x) { return x; }
};
template <class T, int N>
struct scalar_traits<ceres::Jet<T, N>> {
  using value_type = T;
  static const T& value(const ceres::Jet<T, N>& x) { return x.a; }
};

// The plain value of x (the Jet's scalar part; x itself otherwise). Use it only for control
// flow (branch selection, loop termination), never in a returned expression.
template <class T>
auto value_of(const T& x) {
  return scalar_traits<T>::value(x);
}

template <class T>
using value_type_t = typename scalar_traits<T>::value_type;

// Whether T is a multiprecision number (mp50): true only where sglab/mp50.hpp, which defines the
// type, says so. This header names no multiprecision type, so that the units that never evaluate
// in 50 digits compile without Boost.Multiprecision (about 1.5 CPU s per unit).
template <class T>
struct is_mp : std::false_type {};
template <class T>
constexpr bool is_mp_v = is_mp<T>::value;

// Machine epsilon of T's underlying number type.
template <class T>
value_type_t<T> epsilon() {
  return std::numeric_limits<value_type_t<T>>::epsilon();
}

// π to the full precision of T (boost's constant is exact to the type's last digit, which
// matters for mp50; a double literal would cap mp50 results at 16 digits).
template <class T>
T pi() {
  return T(boost::math::constants::pi<value_type_t<T>>());
}
template <class T>
T two_pi() {
  return T(boost::math::constants::two_pi<value_type_t<T>>());
}

// A decimal literal at T's full precision (exact decimal for mp50, correctly rounded otherwise).
template <class T>
T from_string(const char* digits) {
  if constexpr (is_mp_v<T>) {
    return T(digits);
  } else {
    return T(static_cast<value_type_t<T>>(std::strtod(digits, nullptr)));
  }
}

// ---- selects instead of value-dependent branches ---------------------------------------------
// select(cond, if_true, if_false) returns if_true() when cond holds and if_false() otherwise, the
// two sides given as callables. For float, double, Jets and mp50 (cond a bool) only the chosen
// side runs — exactly the `if` it replaces, the same operations and the same result. For the
// tracing type of trace.hpp (cond a TraceBool) both sides are recorded and joined by a select
// node, which is how a formula with a branch on its inputs becomes exportable shader code; the
// SIMD kernels' xsimd::select is the same idea. Write every branch on a value that reaches a
// result this way (ARCHITECTURE.md: one formula, many evaluators).
template <class F, class G>
auto select(bool cond, F&& if_true, G&& if_false) -> decltype(if_true()) {
  return cond ? if_true() : if_false();
}

// choose(cond, a, b): a when cond holds and b otherwise, of two values already computed (cheap
// sides, nothing to skip): select's value. On SIMD lanes it is a blend of the lanes, without the
// test of the mask by which select skips a side no lane takes (an overload found by
// argument-dependent lookup, core/src/simd/simd_lanes.hpp), and without its branch, which lanes
// that disagree at random mispredict.
template <class C, class T>
T choose(const C& cond, const T& a, const T& b) {
  return select(
      cond, [&]() -> T { return a; }, [&]() -> T { return b; });
}

// Whether a series summed term by term has converged: the term no longer changes the sum at T's
// precision. `terms` is how many terms the sum holds (a traced series sums a fixed number of
// terms: trace.hpp).
template <class T>
bool series_converged(const T& term, const T& sum, int /*terms*/) {
  using std::abs;
  return abs(value_of(term)) <= epsilon<T>() * abs(value_of(sum));
}

// ---- safe helpers --------------------------------------------------------------------------

// max(x, 0) written so that Jets keep their derivative on the positive side.
template <class T>
T positive_part(const T& x) {
  return select(
      value_of(x) > 0, [&]() -> T { return x; }, []() -> T { return T(0); });
}

// Clamp x into [lo, hi] by value (for Jets the derivative is that of the selected branch).
template <class T>
T clamp(const T& x, const T& lo, const T& hi) {
  return select(
      value_of(x) < value_of(lo), [&]() -> T { return lo; },
      [&]() -> T {
        return select(
            value_of(x) > value_of(hi), [&]() -> T { return hi; }, [&]() -> T { return x; });
      });
}

// A cosine that rounding may have pushed just past ±1 (|c| = 1 + 1 ulp from a dot product of
// unit vectors): clamp it back, so acos/sqrt(1 - c²) never see an out-of-domain value
// (docs/math.md §10: "|c| slightly above 1 from rounding").
template <class T>
T clamp_cosine(const T& c) {
  return clamp(c, T(-1), T(1));
}

// sqrt(max(x, 0)): rounding can make a true zero (1 - c² at c = 1, a variance) slightly negative.
// pbrt-v4 SafeSqrt. The derivative at exactly 0 is not defined; callers avoid differentiating
// there.
template <class T>
T safe_sqrt(const T& x) {
  using std::sqrt;
  return select(
      value_of(x) > 0, [&]() -> T { return sqrt(x); }, []() -> T { return T(0); });
}

// Below this |x| the first terms of a Taylor series are exact to T's precision. For a series
// truncated after the x^k term, the first neglected term is ~x^(k+1)/(k+2)!, so
// |x| < eps^(1/(k+1)) keeps it below eps (a conservative bound; the factorial only helps).
template <class T>
value_type_t<T> series_threshold(int neglected_power) {
  using std::pow;
  using V = value_type_t<T>;
  return V(pow(V(epsilon<T>()), V(1) / V(neglected_power)));
}

// expm1(x)/x, exactly 1 at x = 0 and without the 0/0 there. Used by A(λ) = 4π·expm1(−2λ)/(−2λ)
// (docs/math.md §1) and every (1 − e^{−λ})/λ factor. Series 1 + x/2 + x²/6 + x³/24 below the
// threshold; expm1 is accurate everywhere else (Higham, "Accuracy and Stability of Numerical
// Algorithms", §1.14.1).
// `em` = expm1(x), when the caller needs expm1(x) itself as well (one call serves both: a
// vectorized evaluation runs both sides of a select whose lanes disagree, docs/simd.md).
template <class T>
T expm1_over_x(const T& x, const T& em) {
  using std::abs;
  return select(
      abs(value_of(x)) < series_threshold<T>(4),
      [&]() -> T { return T(1) + x * (T(0.5) + x * (T(1) / T(6) + x * (T(1) / T(24)))); },
      [&]() -> T { return em / x; });
}
template <class T>
T expm1_over_x(const T& x) {
  using std::expm1;
  return expm1_over_x(x, T(expm1(x)));
}

// 1 − e^{−x} for x ≥ 0 without cancellation.
template <class T>
T one_minus_exp_neg(const T& x) {
  using std::expm1;
  return -expm1(-x);
}

// A finite, non-negative result check used by tests and the stability atlas.
template <class T>
bool is_finite_value(const T& x) {
  using std::isfinite;
  return static_cast<bool>(isfinite(value_of(x)));
}

}  // namespace sglab
