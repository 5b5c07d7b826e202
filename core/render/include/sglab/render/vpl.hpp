// The interface between the two halves of the renderer: the reflective shadow map (RSM) that the
// scene pass produces (rsm.hpp) and that VSGL generation (vsgl_generation.hpp) and the exact VPL
// sum (reference.hpp) consume; and the shading point both shading paths evaluate.
// Units: positions in scene units, flux in W per channel, radiance in W/(m² sr) per channel.
#pragma once

#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace sglab::render {

using Vec3 = Eigen::Vector3d;
using Rgb = Eigen::Array3d;

// The arithmetic of the renderer's vectorized loops: double (the default), or float where the
// result stays within 1e-5 relative of the double path (`sglab render --precision`; which parts
// and the measured difference: reference.hpp, vsgl_shading.hpp).
enum class Precision { single, double_ };

// The instruction set the renderer's vectorized loops run on: always sglab::simd::active_isa()'s
// (sglab/simd.hpp; SGLAB_SIMD selects it for the registry and the renderer alike).
std::string_view kernel_isa();

// One virtual point light = one RSM texel (Dachsbacher & Stamminger 2005).
struct Vpl {
  bool valid = false;                     // the texel saw geometry (false: the spotlight's ray missed)
  Vec3 position = Vec3::Zero();           // x_i
  Vec3 normal = Vec3::UnitZ();            // n_i, unit
  Vec3 incoming = Vec3::UnitZ();          // ω' at x_i: unit direction from x_i towards the light
  Rgb flux = Rgb::Zero();                 // Φ_i: power the spotlight delivers to the texel's patch (W)
  Rgb diffuse_reflectance = Rgb::Zero();  // R_d: Lambert albedo of the surface
  Rgb f0 = Rgb::Zero();                   // Schlick f0 of the GGX layer (zero: not glossy)
  double roughness = 1;                   // GGX α of the surface
  // R_s: the fraction of Φ_i the specular lobe reflects — the directional albedo of the
  // GGX·G2·Schlick BRDF at `incoming`, computed by the RSM pass. Zero for non-glossy surfaces.
  Rgb specular_reflectance = Rgb::Zero();
  // r_i: radius of the disc whose area is the texel's cross-section at the VPL, √(Ω_i/π)·t_i
  // (Ω_i the texel's solid angle, t_i the distance from the light). The exact VPL sum uses it to
  // bound 1/d² near the VPL (reference.hpp). Added by the scene/RSM side.
  double footprint_radius = 0;
  bool glossy() const { return (f0 > 0).any(); }
};

// A res × res RSM, row-major (texel (x, y) at y * resolution + x).
struct ReflectiveShadowMap {
  int resolution = 0;
  std::vector<Vpl> texels;
  const Vpl& at(int x, int y) const { return texels[std::size_t(y) * std::size_t(resolution) + std::size_t(x)]; }
};

// What a pixel's indirect illumination is evaluated at: the first camera hit.
struct ShadingPoint {
  Vec3 position = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  // unit, facing the viewer
  Vec3 view = Vec3::UnitZ();    // ω_o: unit direction from the point towards the camera
  Rgb diffuse_reflectance = Rgb::Zero();
  Rgb f0 = Rgb::Zero();
  double roughness = 1;
  bool glossy() const { return (f0 > 0).any(); }
};

}  // namespace sglab::render
