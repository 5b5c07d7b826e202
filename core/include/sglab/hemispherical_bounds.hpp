// The hemispherical integral's closed-form bounds at c = ±1 and the interpolation between them that
// both published approximations use (docs/math.md §2): Meder & Brüderlin's (hemispherical_meder.hpp)
// and Tokuyoshi's (hemispherical.hpp). Shared code, not a method: a header of its own so that neither
// method's header includes the other.
#pragma once

#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"

namespace sglab {

// H at c = 1 (axis on the normal): 2π(1 − e^{−λ})/λ, exactly 2π at λ = 0.
template <class T>
T hemispherical_upper(const T& sharpness) {
  return two_pi<T>() * expm1_over_x(-sharpness);
}

// H at c = −1 (axis opposite the normal): 2π e^{−λ}(1 − e^{−λ})/λ.
template <class T>
T hemispherical_lower(const T& sharpness) {
  using std::exp;
  return exp(-sharpness) * hemispherical_upper(sharpness);
}

// e^{−λ} + s(1 − e^{−λ}) = lerp(e^{−λ}, 1, s), the normalized interpolation between the lower
// and upper bound shared by Meder–Brüderlin and Tokuyoshi 2022. 1 − e^{−λ} through expm1.
// From e = e^{−λ} and em = expm1(−λ) when the caller has them (one call each serves all uses: a
// vectorized evaluation does not merge repeated calls, docs/simd.md).
template <class T>
T bound_lerp(const T& e, const T& em, const T& s) {
  return e + s * -em;
}
template <class T>
T bound_lerp(const T& sharpness, const T& s) {
  using std::exp;
  using std::expm1;
  return bound_lerp(T(exp(-sharpness)), T(expm1(-sharpness)), s);
}

// hemispherical_upper(λ)·bound_lerp(λ, s), the form of both published approximations below.
template <class T>
T hemispherical_upper_times_lerp(const T& sharpness, const T& s) {
  using std::exp;
  using std::expm1;
  const T em = expm1(-sharpness);
  return two_pi<T>() * expm1_over_x(T(-sharpness), em) * bound_lerp(T(exp(-sharpness)), em, s);
}

}  // namespace sglab
