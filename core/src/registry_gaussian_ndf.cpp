// The `specular-gaussian-ndf` quantity (docs/math.md §5): specular reflection of an SG light off
// the Cook–Torrance-style BRDF with the Gaussian-angle NDF D(h) = e^{−(θ_h/m)²} of Wang et al.
// 2009 (gaussian_ndf.hpp), its exact reference and the SG approximations built on it. A quantity of
// its own beside `specular` (GGX), so that every table of `specular` stays as it is.
#include <string>

#include "sglab/gaussian_ndf.hpp"
#include "sglab/registry_mp50.hpp"
#include "registry_specular.hpp"

namespace sglab {

void register_gaussian_ndf_quantities(std::vector<Quantity>& out) {
  Quantity q{
      "specular-gaussian-ndf",
      "L = ∫ G(ω; ξ, λ) f(ωo, ω)⟨ω·n⟩ dω, unit-amplitude SG light, f = F·S·D/(π (n·ω)(n·ωo)) with the "
      "Gaussian-angle NDF D = e^{−(θ_h/m)²} (D(n) = 1), V-cavity S and Schlick F (Wang et al. 2009; docs/math.md §5); "
      "n = (0,0,1), ωo = (√(1−v²), 0, v), ξ = (s cos φ, s sin φ, light_cos)",
      specular_columns("the NDF's angular width m > 0 (radians; ≈ Beckmann/GGX α at small angles)"),
      "reference",
      {}};
  q.methods.push_back(make_method(
      "reference",
      "adaptive 2D Gauss–Kronrod about the light axis and the mirror direction (glossy_reference.hpp), the "
      "Gaussian-angle BRDF",
      "double quadrature, ≤ 1e-6 relative (checked against a quadrature over the half vector); float rounds and mp50 "
      "converts the double result (an mp50 2D quadrature is too slow); at exactly grazing view the "
      "light's offset from the mirror direction is formed in the row's precision first",
      false,
      [](std::span<const double> a) -> std::optional<std::string> {
        if (a[0] >= kMinReferenceRoughness) return std::nullopt;
        return "roughness (m) below " + std::to_string(kMinReferenceRoughness).substr(0, 5) +
               ": the quadrature's cost grows without bound as m → 0";
      },
      [](auto a) { return specular_gaussian_ndf_reference_value(specular_input(a)); }));
  q.methods.back().evaluates_in_double = true;
  q.methods.push_back(make_method(
      "sg-warp",
      "D ≈ G(h; n, 2/m², 1) warped to G(ω; p_D, (2/m²)/(4|n·ωo|)) (Wang et al. 2009) × SG light, exact product "
      "integral "
      "(Tsai & Shih 2006), M_o·(n·ω) at the lobe axis p_D: F(n·ωo)/(π n·ωo)",
      "isotropic lobe about the mirror direction (wrong shape at grazing view); the cosine and 1/(n·ω) taken at p_D; "
      "the SG overestimates D by up to e^{θ⁴/(12m²)} (large m); the product integral runs over the whole sphere, so a "
      "light below the horizon still contributes (unbounded relative error there)",
      false, nullptr, [](auto a) { return specular_gaussian_ndf_sg_warp(specular_input(a)); }));
  q.methods.push_back(make_method("sg-warp-meder",
                                  "the same warped lobe × SG light with M_o(p_D) = F(n·ωo)/(π (n·ωo)²) pulled out and "
                                  "the cosine as 32.7080·G(ω; n, 0.0315) − "
                                  "31.7003 over the upper hemisphere, each term by Meder & Brüderlin 2018's "
                                  "hemispherical integral (the cosine fit as used by "
                                  "PhySG, Zhang et al. 2021)",
                                  "as sg-warp; 1/(n·ω) taken at p_D while the cosine is integrated: diverges like "
                                  "1/(n·ωo) at grazing view; the Meder cosine "
                                  "can make it negative (grazing and back-facing product lobes)",
                                  true, nullptr,
                                  [](auto a) { return specular_gaussian_ndf_sg_meder(specular_input(a)); }));
  q.methods.push_back(make_method(
      "sg-warp-exact-cosine",
      "as sg-warp-meder with the cosine kept exactly: the product lobe's SG × clamped-cosine integral by its 1D "
      "quadrature reference",
      "as sg-warp-meder without the cosine fit's error (isolates it); a 1D quadrature per value (mp50 slow)", false,
      nullptr, [](auto a) { return specular_gaussian_ndf_sg_exact_cosine(specular_input(a)); }));
  // Too slow a reference for a whole stiff grid: the stability atlas compares a spread subset.
  q.reference_reach = {
      kQuadratureMaxSharpness,
      nullptr,
      "",
      16,
      4,
      [](std::span<const double> a) { return a[0] >= 0.1 && a[1] <= 1e4; },
      "the reference (adaptive 2D quadrature) takes 0.01–1 s per point, more at small m with grazing view",
      "those with roughness ≥ 0.1 and light sharpness ≤ 1e4"};
  out.push_back(std::move(q));
}

}  // namespace sglab
