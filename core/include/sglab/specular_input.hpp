// The input of the `specular` quantities (`specular`, GGX; `specular-gaussian-ndf`) and their
// frame: roughness, light sharpness λ, light_cos, view_cos, light_azimuth, f0 as the registry's
// rows carry them, in the frame n = (0, 0, 1), ωo = (√(1 − v²), 0, v), ξ = (s cos φ, s sin φ, c),
// s = √(1 − c²). A header of its own, which the methods' formulas (specular.hpp, specular_sglab.hpp,
// gaussian_ndf.hpp) and the exact reference (glossy_reference.hpp) include: a unit that needs one
// of them (the own method's fit and experiment need specular_sglab.hpp) does not include the
// others, and an edit of one recompiles only its own users (docs/testing.md, "Rebuilding after a
// method's header").
#pragma once

#include <algorithm>
#include <span>

#include "sglab/brdf.hpp"
#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"

namespace sglab {

template <class T>
struct SpecularInput {
  T roughness, light_sharpness, light_cos, view_cos, light_azimuth, f0;
};

// From a registry row (columns in the order above).
template <class T>
SpecularInput<T> specular_input(std::span<const T> a) {
  return {a[0], a[1], a[2], a[3], a[4], a[5]};
}

namespace detail {
// A row's roughness floored at kMinRoughness (brdf.hpp), as the specular methods take it.
template <class T>
T floored_roughness(const T& alpha) {
  using std::max;
  return max(alpha, T(kMinRoughness));
}
}  // namespace detail

template <class T>
Vec3<T> specular_view(const T& view_cos) {
  const T v = clamp(view_cos, T(0), T(1));
  return Vec3<T>(safe_sqrt(sin2_from_cos(v)), T(0), v);
}

// The light axis ξ from its cosine and cos φ, sin φ of its azimuth; specular_light_axis from φ.
// (The renderer's columns carry ξ's components themselves: sglab/simd_specular_pair.hpp.)
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

}  // namespace sglab
