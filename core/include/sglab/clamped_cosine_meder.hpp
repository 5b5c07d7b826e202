// The Meder cosine (docs/math.md §3, "meder"): ⟨ω·n⟩ as an SG minus a constant, each term through a
// hemispherical integral. A header of its own, included by clamped_cosine.hpp with the other diffuse
// methods, so that gaussian_ndf.hpp (`sg-warp-meder`) takes this method and not every diffuse one:
// an edit of another diffuse method then does not recompile the Gaussian-NDF registry.
#pragma once

#include "sglab/hemispherical_meder.hpp"
#include "sglab/scalar.hpp"
#include "sglab/sg.hpp"

namespace sglab {

// ---- meder: ⟨ω·n⟩ ≈ a·G(ω; n, λ_m) − b, each term through the Meder hemispherical integral ----
// Meder & Brüderlin 2018; used by PhySG (Zhang et al. 2021) ("i.n = G(i; n, 0.0315, 32.7080) −
// 31.7003"). Re-derived by `sglab fit cosine-sg`.
// Known flaw, kept as published: the difference of the two terms can go negative (at grazing
// and back-facing c for sharp lights, where the linear fit of the cosine undershoots 0).
struct MederCosineSg {
  static constexpr double amplitude = 32.7080;  // Meder & Brüderlin 2018
  static constexpr double sharpness = 0.0315;   // Meder & Brüderlin 2018
  static constexpr double offset = 31.7003;     // Meder & Brüderlin 2018
};

// ∫_{ω·n>0} G(ω;ξ,λ)·G(ω;n,λ2) dω through a given hemispherical-integral function: the product
// SG e^{L} G(ω; ξ3, λ3) with c3 = ξ3·n = (λc + λ2)/λ3 (c3 = 1 when λ3 = 0: the product is then the
// constant e^{L} and any axis gives the same hemispherical integral only if H(0, ·) is constant,
// which holds for every H here: H(0, c) = 2π).
template <class T, class Hemi>
T hemispherical_product(const T& sharpness, const T& cosine, const T& sharpness2, const T& extra_log_amplitude,
                        const Hemi& hemi) {
  using std::exp;
  const T c = clamp_cosine(cosine);
  const T l3 = product_sharpness(sharpness, sharpness2, c);
  const T log_amp = product_log_amplitude(sharpness, sharpness2, c, l3) + extra_log_amplitude;
  const T c3 = select(
      value_of(l3) > 0, [&]() -> T { return clamp_cosine(T((sharpness * c + sharpness2) / l3)); },
      []() -> T { return T(1); });
  return exp(log_amp) * hemi(l3, c3);
}

// amplitude, lobe_sharpness, offset (the cosine fit) and p1…p4 (the Meder logistic of both
// hemispherical integrals) default to the published values.
template <class T>
T clamped_cosine_meder(const T& sharpness, const T& cosine, const T& amplitude = T(MederCosineSg::amplitude),
                       const T& lobe_sharpness = T(MederCosineSg::sharpness),
                       const T& offset = T(MederCosineSg::offset), const T& p1 = T(MederLogistic::p1),
                       const T& p2 = T(MederLogistic::p2), const T& p3 = T(MederLogistic::p3),
                       const T& p4 = T(MederLogistic::p4)) {
  auto hemi = [&](const T& l, const T& c) { return hemispherical_meder(l, c, p1, p2, p3, p4); };
  return amplitude * hemispherical_product(sharpness, cosine, lobe_sharpness, T(0), hemi) -
         offset * hemi(sharpness, clamp_cosine(cosine));
}

}  // namespace sglab
