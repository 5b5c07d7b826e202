// The exact sum over all VPLs: what the VSGLs approximate, with the true BRDFs at
// both ends and no SG anywhere, so that the measured error is the VSGL approximation's alone.
//
// VPL i at x_i with normal n_i, incoming direction ω'_i and flux Φ_i has radiant intensity
//   I_i(ω) = Φ_i ρ_i(ω'_i, ω)⟨ω·n_i⟩            (Tokuyoshi 2015 (two-VSGL poster) §2.1, Tokuyoshi 2016 §3.1),
// ρ_i = R_d/π + GGX·G2·Schlick (material_brdf.hpp). The radiance it reflects at shading point y_p
// towards the viewer ωo, with ω = (y_p − x_i)/d the direction from the VPL to the point, is
//   L_i = I_i(ω) · f_p(ωo, −ω)⟨−ω·n_p⟩ / d²,
// and the reference is Σ_i L_i. Visibility between VPL and receiver is ignored, as the VSGLs
// ignore it (the papers' assumption; both paths see the same light).
//
// The 1/d² singularity. A VPL is the flux of its RSM texel's patch concentrated at a point; next to
// it (d of the order of the patch size) 1/d² is the point approximation's artefact, not light the
// patch would deliver. Each VPL is therefore given the extent of its patch: 1/d² is replaced by
//   1/(d² + r_i²),  r_i = Vpl::footprint_radius = √(Ω_i/π)·t_i,
// the exact on-axis irradiance factor of a uniform Lambertian disc of radius r_i (area = the
// texel's cross-section at the VPL), which tends to 1/d² far away (relative change r_i²/d², < 1 %
// beyond d = 10 r_i) and is bounded by 1/r_i² at the patch itself. No VPL is skipped. The
// VSGLs need no such bound: their positional Gaussian spreads each cluster (Tokuyoshi 2015 (two-VSGL poster) §2.2).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "sglab/render/vpl.hpp"

namespace sglab::render {

// The VPLs as structure-of-arrays for the vectorized sum: one array per field, the Lambert VPLs
// and the glossy ones apart (only the latter need the GGX layer), each padded with zero-flux
// entries to a multiple of kVplLanes so that the inner loop has no remainder. T: double, or float
// for the float path (the double values rounded).
template <class T>
struct VplArraysT {
  static constexpr std::size_t kVplLanes = 16;
  std::size_t count = 0;  // VPLs (without the padding)
  // position, normal, incoming direction ω', r_i², Φ_i R_d,i/π per channel
  std::vector<T> x, y, z, nx, ny, nz, ix, iy, iz, r2, lambert_r, lambert_g, lambert_b;
  // glossy VPLs only: Φ_i, f0, α, n_i·ω', and the GGX visibility's root on the incoming side,
  // √(c² + α²(1 − c²)) at c = n_i·ω' (computed in T from the T values before it; every term of the
  // VPL shares it)
  std::vector<T> flux_r, flux_g, flux_b, f0_r, f0_g, f0_b, alpha, cos_incoming, smith_in;
};
using VplArrays = VplArraysT<double>;

// The VPLs of an RSM prepared for summation: valid texels with non-zero flux only.
struct VplList {
  std::vector<Vpl> vpls;
  bool any_glossy = false;
  // `vpls` as arrays (prepare_vpls fills them; a list built by hand is converted per call).
  VplArrays lambert, glossy;
  VplArraysT<float> lambert_float, glossy_float;  // the same in float (Precision::single)
};
VplList prepare_vpls(const ReflectiveShadowMap& rsm);
// Fills list.lambert and list.glossy from list.vpls.
void prepare_vpl_arrays(VplList& list);

// Σ_i L_i at one shading point (radiance, W/(m² sr) per channel). With `visibility_scene`, each
// term is multiplied by V(y_p, x_i) by ray casting against that scene (visibility.hpp), the
// reference of VSGLs with visibility (Tokuyoshi 2016 supplement §4.1).
// The sum is vectorized over the VPL arrays (the terms are summed in a different order than one by
// one, so the result agrees with the plain loop to rounding), in double or, with
// Precision::single, in float (each lane's partial sum in float, the lanes added in double). With
// visibility, V is found first for every VPL whose term is not already 0 by its cosines (a ray
// cast each), and the vectorized sum masks the terms with it.
struct Scene;
Rgb reference_radiance(const ShadingPoint& point, const VplList& vpls, const Scene* visibility_scene = nullptr,
                       Precision precision = Precision::double_);
// reference_radiance of every point into out (as many), each value reference_radiance's to the
// bit. Two points of the same kind (both glossy or neither) that follow each other share one pass
// over the VPL arrays, their terms interleaved (render_kernels_vpl.hpp vpl_sum_blocks): 1.2–1.3×
// faster per point on the machine measured (docs/simd.md), so a caller with many points passes them
// here, in order, neighbours together. Throws std::invalid_argument if out is not as long as points.
void reference_radiances(std::span<const ShadingPoint* const> points, const VplList& vpls, std::span<Rgb> out,
                         const Scene* visibility_scene = nullptr, Precision precision = Precision::double_);

}  // namespace sglab::render
