// Synthetic RSMs with known totals for the VSGL tests (vsgl_generation_test.cpp,
// vsgl_shading_test.cpp).
#pragma once

#include <cstdint>
#include <random>

#include "sglab/render/rsm.hpp"
#include "sglab/render/vsgl_generation.hpp"

namespace sglab::render::vsgl_test {

struct RsmSpec {
  int resolution = 16;
  bool glossy = false;  // the floor half gets a GGX layer
  bool grey = false;    // one chromaticity everywhere (power ∝ importance when not glossy)
  std::uint64_t seed = 1;
};

// Left half of the texels on the floor z = 0 (normal +z), right half on the wall x = 1 (normal
inline ReflectiveShadowMap make_rsm(const RsmSpec& spec) {
  std::mt19937_64 rng(spec.seed);
  std::uniform_real_distribution<double> u(0.5, 1.5);
  const int res = spec.resolution;
  ReflectiveShadowMap rsm;
  rsm.resolution = res;
  rsm.texels.resize(std::size_t(res) * res);
  const Vec3 light(0.5, 0.5, 2.0);
  for (int y = 0; y < res; ++y) {
    for (int x = 0; x < res; ++x) {
      Vpl& v = rsm.texels[std::size_t(y) * res + x];
      const double flux = u(rng);
      const Rgb tint = spec.grey ? Rgb(1, 1, 1) : Rgb(u(rng), u(rng), u(rng));
      if (y == 0 && x % 3 == 0) continue;  // invalid: the light's ray missed
      v.valid = true;
      const double s = (y + 0.5) / res;
      if (x < res / 2) {
        v.position = Vec3((x + 0.5) / (res / 2), s, 0);
        v.normal = Vec3(0, 0, 1);
        v.diffuse_reflectance = spec.grey ? Rgb(0.5, 0.5, 0.5) : Rgb(0.7, 0.3, 0.2);
        if (spec.glossy) {
          v.f0 = Rgb(0.04, 0.04, 0.04);
          v.roughness = 0.25;
        }
      } else {
        v.position = Vec3(1, s, (x - res / 2 + 0.5) / (res / 2));
        v.normal = Vec3(-1, 0, 0);
        v.diffuse_reflectance = spec.grey ? Rgb(0.4, 0.4, 0.4) : Rgb(0.3, 0.6, 0.3);
      }
      v.incoming = (light - v.position).normalized();
      // R_s as the RSM pass computes it: the GGX layer's directional albedo (rsm.hpp).
      if (v.glossy())
        v.specular_reflectance = Rgb::Constant(
            ggx_directional_albedo(v.roughness, v.incoming.dot(v.normal)).reflectance(0.04));
      v.flux = flux * tint * 1e-3;
    }
  }
  return rsm;
}

inline double max_rel(const Rgb& a, const Rgb& b) { return ((a - b).abs() / b.abs().max(1e-300)).maxCoeff(); }

inline VsglOptions options(VsglMode mode, int count, std::uint64_t seed = kDefaultVsglSeed) {
  return {.mode = mode, .count = count, .seed = seed};
}

}  // namespace sglab::render::vsgl_test
