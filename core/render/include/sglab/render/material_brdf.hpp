// The scene's true BRDF times the cosine, in world space: f(ωo, ωi)⟨n·ωi⟩ with
// f = R_d/π + D·G2·F/(4 cos θo cos θi) — GGX D (Walter et al. 2007), height-correlated Smith G2
// (Heitz 2014) and Schlick F per channel, from core's brdf.hpp (written there as D·F·V·cos θi,
// finite at grazing view). Used by direct lighting and by the exact VPL sum, at both ends of a
// light path. The GGX layer is skipped entirely for non-glossy materials (f0 = 0).
#pragma once

#include "sglab/brdf.hpp"
#include "sglab/render/vpl.hpp"

namespace sglab::render {

// f(ωo, ωi)⟨n·ωi⟩ for unit n, ωo (towards the viewer or the next vertex), ωi (towards the
// light). Zero when ωi is below the surface; a view below the surface sees only the Lambert part
// (the GGX factor is 0 there, as in brdf.hpp).
inline Rgb brdf_cosine(const Rgb& albedo, const Rgb& f0, double alpha, const Vec3& n, const Vec3& wo, const Vec3& wi) {
  const double ci = n.dot(wi);
  if (!(ci > 0)) return Rgb::Zero();
  Rgb value = albedo * (ci / std::numbers::pi);
  if ((f0 > 0).any()) {
    const double co = n.dot(wo);
    if (co >= 0) {
      const Vec3 h = (wo + wi).normalized();
      const double dv = ggx_ndf(alpha, n.dot(h)) * smith_visibility_ggx(alpha, co, ci) * ci;
      if (dv > 0) {
        const double coh = wo.dot(h);
        for (int k = 0; k < 3; ++k) value(k) += dv * fresnel_schlick(f0(k), coh);
      }
    }
  }
  return value;
}

}  // namespace sglab::render
