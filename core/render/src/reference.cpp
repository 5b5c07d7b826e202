// The exact VPL sum (reference.hpp).
#include "sglab/render/reference.hpp"

#include <cmath>

#include "sglab/render/material_brdf.hpp"
#include "sglab/render/visibility.hpp"

namespace sglab::render {

VplList prepare_vpls(const ReflectiveShadowMap& rsm) {
  VplList list;
  for (const Vpl& v : rsm.texels) {
    if (!v.valid || !(v.flux > 0).any()) continue;
    list.vpls.push_back(v);
    list.any_glossy = list.any_glossy || v.glossy();
  }
  return list;
}

Rgb reference_radiance(const ShadingPoint& p, const VplList& list, const Scene* visibility_scene) {
  Rgb sum = Rgb::Zero();
  for (const Vpl& v : list.vpls) {
    const Vec3 offset = p.position - v.position;
    const double d2 = offset.squaredNorm();
    if (!(d2 > 0)) continue;  // the point is the VPL: ω undefined, and ⟨ω·n_i⟩⟨−ω·n_p⟩ → 0 on a surface
    const Vec3 omega = offset / std::sqrt(d2);  // from the VPL towards the point
    const double cos_vpl = omega.dot(v.normal), cos_point = -omega.dot(p.normal);
    if (!(cos_vpl > 0) || !(cos_point > 0)) continue;
    if (visibility_scene && !vpl_visible(*visibility_scene, p.position, p.normal, v.position)) continue;
    // I_i(ω)/Φ_i = ρ_i(ω'_i, ω)⟨ω·n_i⟩ (reciprocal, so either argument order of brdf_cosine).
    const Rgb emitted = brdf_cosine(v.diffuse_reflectance, v.f0, v.roughness, v.normal, v.incoming, omega);
    const Rgb reflected = brdf_cosine(p.diffuse_reflectance, p.f0, p.roughness, p.normal, p.view, -omega);
    sum += v.flux * emitted * reflected / (d2 + v.footprint_radius * v.footprint_radius);
  }
  return sum;
}

}  // namespace sglab::render
