// Real spherical harmonics up to order L (the basis of SH irradiance environment lighting,
// Ramamoorthi & Hanrahan 2001, "An efficient representation for irradiance environment maps").
//
//   Y_lm(θ, φ) = √2 K_lm cos(mφ) P_l^m(cos θ)       m > 0
//              = K_l0 P_l^0(cos θ)                    m = 0
//              = √2 K_l|m| sin(|m|φ) P_l^|m|(cos θ)   m < 0,
//   K_lm = √((2l + 1)/(4π) · (l − m)!/(l + m)!),
// with P_l^m the associated Legendre functions without the Condon–Shortley phase (so that
// Y_1,1 = +√(3/(4π)) x, as in Sloan 2008, "Stupid spherical harmonics tricks", Appendix A2),
// evaluated by the standard three-term recurrences in cos θ (stable for these orders). The
// (L + 1)² values of a direction are stored at index l(l + 1) + m.
//
// Irradiance by the clamped-cosine zonal convolution (Ramamoorthi & Hanrahan 2001, eq. 7–9):
//   E(n) = Σ_lm Â_l L_lm Y_lm(n),  Â_0 = π, Â_1 = 2π/3, Â_l = 0 for odd l > 1,
//   Â_l = 2π (−1)^{l/2 − 1} / ((l + 2)(l − 1)) · l!/(2^l ((l/2)!)²) for even l ≥ 2.
// It is exact for the order-L projection of the radiance: no window is applied.
#pragma once

#include <cmath>
#include <vector>

#include "sglab/sg.hpp"

namespace sglab {

inline constexpr int kMaxShOrder = 8;

inline constexpr int sh_count(int order) { return (order + 1) * (order + 1); }
inline constexpr int sh_index(int l, int m) { return l * (l + 1) + m; }

// All (L + 1)² real SH values at the unit direction w, written to y[0 … (L+1)² − 1].
template <class T>
void sh_eval(int order, const Vec3<T>& w, T* y) {
  // std's sqrt for the built-in types (a bare sqrt here would otherwise find sglab::sqrt(Trace), by
  // conversion, wherever trace.hpp came first: as in a batch of fit/), the argument's own by lookup otherwise.
  using std::sqrt;
  const T z = w(2);
  const T rxy = sqrt(w(0) * w(0) + w(1) * w(1));
  // cos(mφ), sin(mφ) by the angle-addition recurrence on (x, y)/r (φ = 0 at the pole).
  T cm[kMaxShOrder + 1], sm[kMaxShOrder + 1];
  cm[0] = T(1);
  sm[0] = T(0);
  const T c1 = rxy > T(0) ? T(w(0) / rxy) : T(1), s1 = rxy > T(0) ? T(w(1) / rxy) : T(0);
  for (int m = 1; m <= order; ++m) {
    cm[m] = cm[m - 1] * c1 - sm[m - 1] * s1;
    sm[m] = sm[m - 1] * c1 + cm[m - 1] * s1;
  }
  // P_m^m = (2m − 1)!! (sin θ)^m, P_{m+1}^m = (2m + 1) z P_m^m,
  // P_l^m = ((2l − 1) z P_{l−1}^m − (l + m − 1) P_{l−2}^m)/(l − m).
  T pmm = T(1);
  for (int m = 0; m <= order; ++m) {
    if (m > 0) pmm = pmm * T(2 * m - 1) * rxy;
    T p_prev2 = T(0), p_prev = pmm;
    for (int l = m; l <= order; ++l) {
      T p;
      if (l == m) {
        p = pmm;
      } else if (l == m + 1) {
        p = T(2 * m + 1) * z * pmm;
      } else {
        p = (T(2 * l - 1) * z * p_prev - T(l + m - 1) * p_prev2) / T(l - m);
      }
      if (l > m) {
        p_prev2 = p_prev;
        p_prev = p;
      }
      // K_lm = √((2l + 1)/(4π) (l − m)!/(l + m)!)
      T ratio = T(1);
      for (int k = l - m + 1; k <= l + m; ++k) ratio /= T(k);
      const T K = sqrt(T(2 * l + 1) / (T(4) * pi<T>()) * ratio);
      if (m == 0) {
        y[sh_index(l, 0)] = K * p;
      } else {
        const T s2 = sqrt(T(2));
        y[sh_index(l, m)] = s2 * K * cm[m] * p;
        y[sh_index(l, -m)] = s2 * K * sm[m] * p;
      }
    }
  }
}

// Â_l of the clamped cosine max(0, cos θ) (file comment).
template <class T>
T sh_clamped_cosine_band(int l) {
  if (l == 0) return pi<T>();
  if (l == 1) return T(2) * pi<T>() / T(3);
  if (l % 2 == 1) return T(0);
  T ratio = T(1);  // l!/(2^l ((l/2)!)²) = C(l, l/2)/2^l
  for (int k = 1; k <= l / 2; ++k) ratio *= T(l / 2 + k) / T(k) / T(4);
  const T sign = (l / 2 - 1) % 2 == 0 ? T(1) : T(-1);
  return T(2) * pi<T>() * sign / (T(l + 2) * T(l - 1)) * ratio;
}

}  // namespace sglab
