// The Meder cosine (docs/math.md §3, "meder"): ⟨ω·n⟩ as an SG minus a constant, each term through a
// hemispherical integral. A header of its own, which clamped_cosine.hpp does not include: its users
// (the diffuse registry, kernels and SIMD table, gaussian_ndf.hpp for `sg-warp-meder`, the fit of
// its constants, fit/cosine_sg.cpp, and the naive peer) include it themselves, so that an edit of
// another diffuse method does not recompile the Gaussian-NDF registry and an edit of this one
// recompiles only its users.
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
