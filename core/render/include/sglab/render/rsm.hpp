// The reflective shadow map (Dachsbacher & Stamminger 2005): the spotlight's
// view at RES × RES whose texels are the VPLs of vpl.hpp.
//
// Per texel: the first hit of the ray through the texel's centre gives position, normal (facing
// the light), incoming direction (towards the light) and the material (R_d, f0, α); the flux is
// the power the spotlight sends through the texel's whole solid angle,
//   Φ_i = ∫_texel I(ω) dω,
// integrated exactly (see texel_emission_fraction), so that the sum of Φ over the texels that
// hit geometry is the power inside the cone that hits geometry (to the texel-centre sampling of
// the geometry's silhouette). R_s is the GGX layer's directional albedo at the incoming
// direction (ggx_directional_albedo, through a GgxAlbedoTable per glossy material).
#pragma once

#include <memory>
#include <vector>

#include "sglab/render/scene.hpp"
#include "sglab/render/shadow_map.hpp"
#include "sglab/render/vpl.hpp"

namespace sglab::render {

// ∫_texel I(ω) dω / Φ for texel (i, j) of `view` (which must be the light's view): the fraction
// of the light's power sent through the texel. Texels entirely inside the inner cone are
// I0/Φ·Ω_texel with the closed-form solid angle (image_rectangle_solid_angle); texels entirely
// outside the cone are 0. For the others (crossed by the cone's edge or its smooth falloff) the
// radial integral is closed-form — in polar image coordinates dω = r dr dφ/(1 + r²)^{3/2} = −dc dφ
// with c = cos θ = 1/√(1 + r²), so ∫ s(c) r dr/(1 + r²)^{3/2} = ∫ s dc, a piecewise polynomial —
// and the texel is the signed sum of the four triangles (axis, edge), each a 1D integral over the
// azimuth by adaptive Gauss–Kronrod with panel ends where the edge crosses the inner and outer
// circles (so a hard edge is a panel end, not a jump inside a panel): ≤ 1e-12 relative.
double texel_emission_fraction(const Spotlight& light, const LightView& view, int i, int j);

// Directional albedo of the GGX layer, split as in Karis 2013 ("Real Shading in Unreal Engine 4",
// split-sum) so that f0 enters linearly: for Schlick's F = f0 + (1 − f0)(1 − ω'·h)⁵,
//   R_s(ω') = ∫ f_ggx(ω', ω)⟨ω·n⟩ dω = f0·(e1 − e5) + e5,
//   e1 = ∫ D·V·⟨ω·n⟩·4(ω'·h)… with F = 1, e5 = the same with F = (1 − ω'·h)⁵.
struct GgxAlbedo {
  double e1 = 0, e5 = 0;
  double reflectance(double f0) const { return f0 * (e1 - e5) + e5; }
};
// Deterministic quadrature over the half vector in the GGX sampling variables (Walter et al.
// 2007, Eqs. 35–36): tan²θh = α²u/(1 − u), φh uniform, for which D(h) cos θh dω_h = du dφ/(2π);
// with dω = 4(ω'·h) dω_h the integrand is V·⟨ω·n⟩·4(ω'·h)/cos θh, smooth and bounded. The
// horizon ω·n = 0 is at θh = θ*(φ) in closed form (rsm.cpp), so u runs over [0, u*(φ)] and no
// kink lies inside the domain: Gauss–Legendre 32 × 32 (φ ∈ [0, π], the integrand is even in φ;
// at grazing incidence the φ range is split geometrically about π/2, where the horizon θ*(φ)
// swings from π/2 to 0 within Δφ ~ cos θ'). Absolute error ≤ 3e-5 for cos θ' ≥ 0.2 and ≤ 3e-4 down
// to cos θ' = 0.005, α ∈ [0.02, 1] (tests/render_test.cpp, against core's adaptive sphere
// quadrature; the rest is the Smith term's transition of width ~cos θ' at the horizon).
GgxAlbedo ggx_directional_albedo(double alpha, double cos_incoming);

// ggx_directional_albedo tabulated for one α at cos θ' = s², s = k/128 (k = 0 … 128, cos θ' floored
// at 1e-4), linear in s (dense where the albedo varies fastest, at grazing incidence). What the RSM
// uses: one table per glossy material (129 quadratures, ~0.1 s) instead of one quadrature per VPL.
// Interpolation error ≤ 1e-3 for α ≥ 0.01 (at cos θ' → 0); for cos θ' ≥ 0.01, ≤ 4e-4 at α = 0.01
// and ≤ 1e-4 for α ≥ 0.05 (tests/render_test.cpp).
class GgxAlbedoTable {
 public:
  explicit GgxAlbedoTable(double alpha);
  GgxAlbedo operator()(double cos_incoming) const;
  static constexpr int kNodes = 128;
  static constexpr double kMinCos = 1e-4;

 private:
  std::vector<GgxAlbedo> nodes_;
};

// The table of α, built on first use and kept for the process (up to 64 roughness values, then
// built anew): the RSMs of a sweep, and the many steps of `sglab reproduce` in one process,
// render the same few glossy materials again and again. The time of the RSM that first needs a
// table includes its build. Thread-safe; no lock is held while a table is built.
std::shared_ptr<const GgxAlbedoTable> ggx_albedo_table(double alpha);

// The RSM at resolution × resolution. Parallel over rows (TBB).
ReflectiveShadowMap render_rsm(const Scene& scene, int resolution);

}  // namespace sglab::render
